"""The damper as a complex spring: `DamperStiffness`, a pure-JAX k_of_psi(psi_a_mrad) -> (k_re,
k_im) with its status and limits, built by method ("exact": the steady travel-limited cycle at each
amplitude; "interpolated": the paper's, on the Base-Cycle), and the curves derived from one
(tabulated, scaled by the paper's law, stuck, none)."""

from __future__ import annotations

import inspect
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..amplitude import amplitude_kernel
from ..cycle import base_cycle_kernel
from ..conventions import MRAD_PER_RAD
from ..ellipse import elliptic_kernel, gross_slip_amplitude_kernel
from ..geometry import is_wedge
from .._validate import check_scalar, check_values, traced
from ..design import check_design
from ..motion import Motion, as_ellipse, validate_motion
from ..harmonics import complex_stiffness, five_numbers_kernel
from ..params import Contacts, LoadCase, prepare_inputs
from ..residual import through_residual
from ..status import RESULTS, number_repr, status_repr

__all__ = ["KOfPsi", "DamperStiffness", "CompiledSource", "STIFFNESS_METHODS", "check_damper",
           "interpolated_damper", "base_scale", "exact_damper", "register_stiffness_method",
           "damper_stiffness_kernel", "damper_stiffness", "tabulated_stiffness",
           "scaled_stiffness", "stuck_damper", "no_damper", "PATH_HISTORIES", "check_history", "PathStiffness", "path_cycle_kernel",
           "path_damper", "STUCK_FRACTION", "through_residual", "with_residual"]


KOfPsi = Callable[[jnp.ndarray], tuple]


class DamperStiffness(NamedTuple):
    """The damper as a complex spring: k_of_psi(psi_a_mrad) -> (k_re, k_im) in N mm/mrad.

    status: RESULTS code of the damper model (liftoff, not_converged, ...); k_re_stuck: the
    stick-state stiffness k_Re,fs (the stuck limit); psi_ref_mrad: an amplitude scale of the curve
    (psi_BC), used to place amplitude grids.
    """

    k_of_psi: KOfPsi
    status: jnp.ndarray
    k_re_stuck: jnp.ndarray
    psi_ref_mrad: jnp.ndarray
    # The same curve for values only (None: k_of_psi): the design held constant, so that searches
    # (the peak's amplitude grid and root iterations) run the curve's value program even while an
    # outer jacfwd/grad differentiates the design; only the root's IFT step uses k_of_psi.
    k_values: KOfPsi | None = None
    # How `damper_stiffness` built this curve from concrete inputs (a `CompiledSource`), so that
    # `peak_response` on it runs one compiled program instead of op by op; None otherwise.
    source: "CompiledSource | None" = None

    def __repr__(self):
        return (f"DamperStiffness(k_Re,stuck {number_repr(self.k_re_stuck, 'N mm/mrad')}, psi_ref "
                f"{number_repr(self.psi_ref_mrad, 'mrad')}, status {status_repr(self.status)})")

    def values(self, psi):
        """(k_re, k_im) at psi without derivatives with respect to the design."""
        return (self.k_of_psi if self.k_values is None else self.k_values)(psi)


class CompiledSource:
    """The stiffness method, its options and the prepared design a `DamperStiffness` was built
    from, tied to its curve function: a plain object (a pytree leaf), not data to differentiate."""

    __slots__ = ("k_of_psi", "method", "options", "design")

    def __init__(self, k_of_psi, method: str, options: tuple, design: tuple):
        self.k_of_psi, self.method, self.options, self.design = k_of_psi, method, options, design

    def matches(self, damper: "DamperStiffness") -> bool:
        """True while the damper still is the curve it was built as (a `_replace` of k_of_psi,
        as `tabulated_stiffness` or `scaled_stiffness` make, unties it)."""
        return damper.k_of_psi is self.k_of_psi


def interpolated_damper(shape, mu, contacts, load) -> DamperStiffness:
    """The paper's k(psi_a) on the Base-Cycle (kernels only: traceable, inputs not checked). The
    status is the Base-Cycle's own (ill_conditioned, liftoff, ...), never rebuilt from flags."""
    bc = base_cycle_kernel(shape, mu, contacts, load)
    nums = five_numbers_kernel(bc)
    return DamperStiffness(lambda psi: complex_stiffness(bc, psi, method="interpolated"),
                           bc.status, nums.k_re_fs, jnp.maximum(nums.psi_bc, 1e-12))


@jax.jit
def base_scale(shape, mu, contacts, load):
    """(status, stuck k_Re, psi_BC) of the curved-flat damper's Base-Cycle (`interpolated_damper`):
    the curve's limits and amplitude scale, as a program of its own for callers that use them
    many times (a row's engine orders, a band's peaks). Unchecked."""
    base = interpolated_damper(shape, mu, contacts, load)
    return base.status, base.k_re_stuck, base.psi_ref_mrad


def exact_damper(shape, mu, contacts, load, initial: str = "gross_slip") -> DamperStiffness:
    """k(psi_a) from the exact steady cycle at each amplitude (`jaxdamp.amplitude`), from the named
    initial state (gross_slip: the state after a gross-slip history). The stuck limit, the
    amplitude scale and the status come from the Base-Cycle."""
    check_history(initial)  # here, before any work, not when k(psi) is first evaluated
    base = interpolated_damper(shape, mu, contacts, load)

    def curve(design):
        def k_of_psi(psi):
            psi = jnp.asarray(psi, float)
            cycles = jax.vmap(lambda a: amplitude_kernel(*design, a, initial=initial))(
                psi.reshape(-1))
            return cycles.k_re.reshape(psi.shape), cycles.k_im.reshape(psi.shape)
        return k_of_psi

    design = (shape, mu, contacts, load)
    return base._replace(k_of_psi=curve(design), k_values=curve(jax.lax.stop_gradient(design)))


PATH_HISTORIES = ("assembly", "gross_slip")


def check_history(initial: str) -> None:
    """ValueError in one line unless initial is one of PATH_HISTORIES."""
    if initial not in PATH_HISTORIES:
        raise ValueError(f"initial must be one of {', '.join(PATH_HISTORIES)}; got {initial!r}")

STUCK_FRACTION = 1e-6  # of psi_ref: an amplitude at which every pad sticks (the stuck limit)


class PathStiffness(NamedTuple):
    """The complex stiffness of one steady cycle on a platform path (a pytree; unpacks as
    (k_re, k_im, status))."""

    k_re: jnp.ndarray  # N mm/mrad of the path's parameter (zero where the status has no numbers)
    k_im: jnp.ndarray
    status: jnp.ndarray  # RESULTS code of the cycle

    def __repr__(self) -> str:
        return (f"PathStiffness(status={status_repr(self.status)}, "
                f"k_re={number_repr(self.k_re, 'N mm/mrad')}, "
                f"k_im={number_repr(self.k_im, 'N mm/mrad')})")


def path_cycle_kernel(shape, mu, contacts, load, amplitude, motion, initial: str = "assembly",
                      loop: str = "auto", repeats: int | None = None) -> PathStiffness:
    """`PathStiffness` (k_re, k_im, status) of the steady cycle at `amplitude` (mrad of the path's parameter) on
    a platform path: motion None is the paper's in-phase motion (`amplitude_kernel`), a straight
    Motion runs `amplitude_kernel(..., motion=)`, an elliptic one `elliptic_kernel` (its gross
    slip: a straight move along the ellipse's tau = 0 direction to gross slip, `jaxdamp.ellipse`).
    loop: the kernels' (`amplitude_kernel`). repeats: the bound on the iteration to a periodic
    cycle (pairs of halves on a straight path, periods on an ellipse; None: the kernels' own).
    Unchecked, traceable (jit, vmap, grad)."""
    check_history(initial)
    if is_wedge(shape):  # a wedge runs on the path engine, a straight path as a flat ellipse
        motion = _engine_path(motion, load)
    bound = {} if repeats is None else {"max_periods" if motion is not None
                                        and motion.quadrature is not None else "max_pairs": repeats}
    if motion is not None and motion.quadrature is not None:
        c = elliptic_kernel(shape, mu, contacts, load, amplitude, motion, initial=initial, loop=loop,
                            **bound)
    else:
        c = amplitude_kernel(shape, mu, contacts, load, amplitude, initial=initial, motion=motion,
                             loop=loop, **bound)
    return PathStiffness(c.k_re, c.k_im, c.status)


def _engine_path(motion, load) -> Motion:
    """The Motion the tract engine runs: the in-phase path for None, a straight one with a zero
    quadrature (an ellipse of zero width)."""
    if motion is None:
        q = jnp.asarray(load.q_star, float)
        motion = Motion(jnp.stack([jnp.zeros_like(q), q / MRAD_PER_RAD, jnp.zeros_like(q)]),
                        jnp.ones_like(q))
    return as_ellipse(motion)


def path_damper(shape, mu, contacts, load, motion=None, initial: str = "assembly",
                loop: str = "auto", repeats: int | None = None, base=None) -> DamperStiffness:
    """k(psi) from the exact steady cycle on a platform path (`path_cycle_kernel`; psi in mrad
    of the path's parameter): the damper of one engine order of a bladed disk
    (`jaxdamp.response.modes`). motion None is `exact_damper`'s in-phase curve. The status and
    the amplitude scale come from the paper's (in-phase) Base-Cycle, the design check; for a
    wedge (no Base-Cycle; in-phase too on the path engine) from the path's gross-slip move
    (`ellipse.gross_slip_amplitude_kernel`). The stuck limit is the path's own (the cycle at
    STUCK_FRACTION psi_ref, where every pad sticks).
    loop: the cycles' (`amplitude_kernel`): "while" traces several times faster where no reverse
    derivative is needed (forward mode still passes); repeats: `path_cycle_kernel`'s. base: the
    curved-flat damper's (status, psi_BC) from its Base-Cycle (`base_scale`) where the caller has
    them (a row: one Base-Cycle for every engine order, in a program of its own); unused for a
    wedge. Unchecked, traceable (jit, vmap, grad); concrete inputs are checked as one design's and
    its path."""
    if not traced(shape, mu, contacts, load, motion):
        check_design(shape, mu, contacts, load, wedge_ok=True)
        if motion is not None:
            validate_motion(motion, load)
    if is_wedge(shape):
        # No Base-Cycle for a wedge: the amplitude scale is the path's gross-slip amplitude, the
        # status that of the move there (unseated, unreachable).
        motion = _engine_path(motion, load)
        a_gs, status = gross_slip_amplitude_kernel(shape, mu, contacts, load, motion)
        base = DamperStiffness(None, status, jnp.zeros(()), jnp.maximum(a_gs, 1e-12))
    elif motion is None:
        return exact_damper(shape, mu, contacts, load, initial)
    elif base is not None:
        base = DamperStiffness(None, base[0], jnp.zeros(()), base[1])
    else:
        base = interpolated_damper(shape, mu, contacts, load)

    def curve(design, path):
        def k_of_psi(psi):
            psi = jnp.asarray(psi, float)
            k_re, k_im, _ = jax.vmap(lambda a: path_cycle_kernel(*design, a, path, initial, loop,
                                                                 repeats))(
                psi.reshape(-1))
            return k_re.reshape(psi.shape), k_im.reshape(psi.shape)
        return k_of_psi

    design = (shape, mu, contacts, load)
    stuck, _, _ = path_cycle_kernel(*design, STUCK_FRACTION * base.psi_ref_mrad, motion, initial,
                                    loop, repeats)
    return base._replace(k_of_psi=curve(design, motion), k_re_stuck=stuck,
                         k_values=curve(*jax.lax.stop_gradient((design, motion))))


def with_residual(damper: DamperStiffness, c) -> DamperStiffness:
    """The damper as the mode sees it through the residual flexibility c (mrad per N mm):
    `through_residual` on its curve; the stuck limit k_s / (1 + c k_s). Values only."""
    def wrap(k_fn):
        def k_of_psi(psi):
            def cycle(p):
                k_re, k_im = k_fn(p)
                return k_re, k_im, jnp.zeros(jnp.shape(p), jnp.int32)
            return through_residual(cycle, psi, c)[:2]
        return k_of_psi

    stuck = damper.k_re_stuck / (1.0 + c * damper.k_re_stuck)
    return damper._replace(k_of_psi=wrap(damper.k_of_psi), k_values=wrap(damper.values),
                           k_re_stuck=stuck, source=None)


STIFFNESS_METHODS: dict[str, Callable[..., DamperStiffness]] = {"interpolated": interpolated_damper,
                                                                "exact": exact_damper}


def register_stiffness_method(name: str, factory: Callable[..., DamperStiffness]) -> None:
    """Add a way to build k(psi_a): factory(shape, mu, contacts, load) -> DamperStiffness.

    Built in: "exact" (the travel-limited steady cycles of `jaxdamp.amplitude`, option initial=)
    and "interpolated" (the paper's linear microslip interpolation, for comparison with it)."""
    STIFFNESS_METHODS[name] = factory


def check_damper(damper) -> DamperStiffness:
    """damper as it is, or a TypeError in one line naming it (a number there failed inside with
    an AttributeError)."""
    if not isinstance(damper, DamperStiffness):
        raise TypeError(f"damper must be a jaxdamp.DamperStiffness (from damper_stiffness); got "
                        f"{type(damper).__name__}")
    return damper


def damper_stiffness_kernel(shape, mu, contacts, load, method: str = "exact",
                            **options) -> DamperStiffness:
    """`damper_stiffness` without input checks, for use inside jit/vmap/grad (inputs as
    `prepare_scene` returns them)."""
    if method not in STIFFNESS_METHODS:
        raise ValueError(f"method must be one of {', '.join(STIFFNESS_METHODS)}; got {method!r}")
    _check_options(method, options)
    return STIFFNESS_METHODS[method](shape, mu, contacts, load, **options)


def _check_options(method: str, options: dict) -> None:
    """ValueError in one line for an option that `method`'s factory does not take (its
    parameters after the design's four; a factory taking **options takes any)."""
    params = list(inspect.signature(STIFFNESS_METHODS[method]).parameters.values())[4:]
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params):
        return
    taken = [p.name for p in params]
    for name in options:
        if name not in taken:
            raise ValueError(f"{name} is not an option of method {method!r}: its options are "
                             f"{', '.join(taken) or 'none'}")


def damper_stiffness(shape, mu, contacts=None, load=None, method: str = "exact",
                     **options) -> DamperStiffness:
    """The damper's amplitude-dependent complex stiffness for one design (pure JAX, traceable in
    the shape, mu, contact stiffness and load). method: a key of STIFFNESS_METHODS, by default the
    exact curve from a gross-slip history (options: initial="gross_slip" | "assembly").

    Concrete inputs are checked here (`params.prepare_inputs`); traced ones are not (check them
    once outside, or call `damper_stiffness_kernel`)."""
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    if traced(shape, mu, contacts, load):
        return damper_stiffness_kernel(shape, mu, contacts, load, method, **options)
    design = prepare_inputs(shape, mu, contacts, load)
    damper = damper_stiffness_kernel(*design, method, **options)
    source = CompiledSource(damper.k_of_psi, method, tuple(sorted(options.items())), design)
    return damper._replace(source=source)


def tabulated_stiffness(psi_grid_mrad, k_re, k_im, base: DamperStiffness,
                        envelope: str = "linear") -> DamperStiffness:
    """A damper curve known on an amplitude grid (mrad); status, stuck limit and amplitude scale
    from `base`. Between grid points k_Im is linear (envelope="linear"), or the larger ("upper") or
    smaller ("lower") of the two neighbouring values: a conservative envelope of a bound curve that
    is monotone between grid points. Beyond the ends the end values hold.
    Unchecked, traceable (jit, vmap, grad): the grid (increasing, mrad) and values are taken as
    given."""
    grid = jnp.asarray(psi_grid_mrad, float)
    k_re, k_im = jnp.asarray(k_re, float), jnp.asarray(k_im, float)
    pick = {"upper": jnp.maximum, "lower": jnp.minimum}.get(envelope)

    def k_of_psi(psi):
        psi = jnp.asarray(psi, float)
        if pick is None:
            return jnp.interp(psi, grid, k_re), jnp.interp(psi, grid, k_im)
        right = jnp.clip(jnp.searchsorted(grid, psi), 0, grid.size - 1)
        left = jnp.clip(right - 1, 0, grid.size - 1)
        return jnp.interp(psi, grid, k_re), pick(k_im[left], k_im[right])

    return base._replace(k_of_psi=k_of_psi)



def scaled_stiffness(ref: DamperStiffness, fd_ref_n, fd_n, contact_scale=1.0) -> DamperStiffness:
    """The paper's scaling law: k(psi; F_D, c kn, c kt) from the curve at (F_D0, kn, kt).

    Forces (and moments) scale with F_D; displacements (and psi) with F_D / k at fixed kt/kn. So
    M(psi; F_D, c) = (F_D/F_D0) M0(psi / s) with s = (F_D/F_D0) / c, and k = M / psi gives
    k(psi; F_D, c) = c k0(psi c F_D0 / F_D). At fixed contact stiffness (c = 1) an F_D change only
    stretches the psi axis: the stick stiffness is independent of F_D. An F_D sweep costs one curve.
    Unchecked, traceable (jit, vmap, grad): fd_ref_n, fd_n (> 0 N) and contact_scale (> 0) are taken
    as given (traced in the designer's diagram); `ref` comes from `damper_stiffness` (checked).
    Concrete ones are checked (F_D's range, contact_scale > 0).
    """
    if not traced(fd_ref_n, fd_n, contact_scale):
        check_values("F_D", fd_ref_n, "fd_ref_n", max_ndim=0)
        check_values("F_D", fd_n, "fd_n")
        check_scalar("contact_scale", contact_scale, 0.0, np.inf, lo_open=True, hi_open=True)
    s = (jnp.asarray(fd_n, float) / fd_ref_n) / contact_scale

    def scaled(k_fn, stretch, c):
        def k_of_psi(psi):
            k_re, k_im = k_fn(jnp.asarray(psi, float) / stretch)
            return c * k_re, c * k_im
        return k_of_psi

    # The values-only curve holds the scaling constant too.
    frozen = scaled(ref.values, *jax.lax.stop_gradient((s, contact_scale)))
    return DamperStiffness(scaled(ref.k_of_psi, s, contact_scale), ref.status,
                           contact_scale * ref.k_re_stuck, ref.psi_ref_mrad * s, frozen)


def stuck_damper(k_re_stuck) -> DamperStiffness:
    """The stuck limit: a real spring k_Re,fs at every amplitude (no dissipation).
    Unchecked, traceable (jit, vmap, grad); a concrete k_re_stuck is checked (one number >= 0)."""
    if not traced(k_re_stuck):
        check_scalar("k_re_stuck", k_re_stuck, 0.0, np.inf, hi_open=True, unit="N mm/mrad")
    k = jnp.asarray(k_re_stuck, float)
    return DamperStiffness(lambda psi: (jnp.zeros_like(psi) + k, jnp.zeros_like(psi)),
                           jnp.int32(RESULTS.ok), k, jnp.asarray(1.0))


def no_damper() -> DamperStiffness:
    """The free limit: platforms without a damper (no inputs)."""
    return stuck_damper(0.0)
