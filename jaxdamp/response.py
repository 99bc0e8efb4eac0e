"""Blade forced response from the damper's complex stiffness (the Platform Centred Reduction).

One blade-dominated mode of a tuned bladed disk at one interblade phase angle, reduced to the tip
displacement amplitude A (mm). The damper is a complex spring between the platforms: at platform
rotation amplitude psi_a = r A (mrad) it adds 1e-3 r^2 (k_Re + i k_Im) (N/mm) to the modal dynamic
stiffness, with k in N mm/mrad (M = k psi, psi in mrad, and the modal force of a moment M is
1e-3 r M since a rotation psi (mrad) is 1e-3 r A rad per mm of tip motion):

    D(omega, A) = k_b (1 - (omega/omega0)^2 + i eta) + 1e-3 r^2 (k_Re(r A) + i k_Im(r A))

and the first-harmonic steady state is |D(omega, A)| A = F (the amplitude-layered solution: each
amplitude A is a linear problem). For each A the equation is quadratic in omega^2 (`frf`); at the
peak Re D = 0, so A (eta k_b + 1e-3 r^2 k_Im(r A)) = F (`peak_response`).

The damper enters only through a pure-JAX, differentiable `k_of_psi(psi_a_mrad) -> (k_re, k_im)`
built by `damper_stiffness(shape, mu, contacts, load, method=...)`: "exact" (default) takes the
steady travel-limited cycle at each amplitude (`jaxdamp.amplitude`, from a gross-slip history
unless initial="assembly"); "interpolated" is the paper's, `complex_stiffness(method=
"interpolated")` on the Base-Cycle (exact for psi_a >= psi_BC, linear in the microslip range).

Units: A and tip displacements in mm, F in N, k_b in N/mm, f in Hz, r in mrad/mm, psi in mrad,
k in N mm/mrad.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_positive, check_range
from .amplitude import amplitude_kernel
from .band import amplitude_bands
from .cycle import base_cycle_kernel
from .harmonics import complex_stiffness, five_numbers_kernel
from .params import Contacts, LoadCase, prepare_inputs, validate_mu
from .runtime import batch_jit
from .status import RESULTS, number_repr, status_repr


# ----------------------------------------------------------------------------- the blade mode


class BladeMode(NamedTuple):
    """One blade mode with the platforms free (a pytree: every field may be traced).

    ILLUSTRATIVE defaults, chosen to be realistic rather than flattering (they are not the paper's:
    the paper gives no blade). With the paper's reference damper (60sym, mu = 0.5, F_D = 1000 N,
    q* = 100 mm, the reference contact pair), k_Re,fs = 28 744 N mm/mrad and k_Im,BC = 4 927
    N mm/mrad at psi_BC = 2.18 mrad. With the defaults:

    - f0 = 500 Hz and k_b = 500 N/mm: a tip-normalised modal mass k_b / omega0^2 = 51 g, the order
      of a small turbine blade's first bending mode;
    - r = 1 mrad/mm: 0.1 mm of relative radial platform motion per mm of tip motion at q* = 100 mm
      (platforms near the root move a tenth of the tip);
    - eta = 1e-3: the upper end of a blade's material + root-joint loss factor (1e-4 ... 1e-3);
      a larger eta makes the damper look less effective, which is the non-flattering side.

    Then the stuck damper raises the frequency by sqrt(1 + 1e-3 r^2 k_Re,fs / k_b) - 1 = 2.8 %
    (a few per cent, as measured on rigs with stuck underplatform dampers), and at the Base-Cycle
    the damper's modal loss term 1e-3 r^2 k_Im,BC = 4.9 N/mm is ten times eta k_b = 0.5 N/mm.
    """

    f0_hz: jnp.ndarray | float = 500.0
    k_b: jnp.ndarray | float = 500.0  # modal stiffness, N/mm
    eta: jnp.ndarray | float = 1e-3  # structural loss factor
    r: jnp.ndarray | float = 1.0  # platform rotation per tip displacement, mrad/mm


def validate_mode(mode: BladeMode) -> BladeMode:
    """ValueError naming the parameter and its range (concrete values only)."""
    check_positive("f0_hz", mode.f0_hz, unit="Hz")
    check_positive("k_b", mode.k_b, unit="N/mm")
    check_range("eta", mode.eta, 0.0, 1.0)
    check_range("r", mode.r, 0.0, 1e6, lo_open=True, unit="mrad/mm")
    return mode


# ----------------------------------------------------------------------------- damper stiffness

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


def _interpolated(shape, mu, contacts, load) -> DamperStiffness:
    """The paper's k(psi_a) on the Base-Cycle (kernels only: traceable, inputs not checked). The
    status is the Base-Cycle's own (ill_conditioned, liftoff, ...), never rebuilt from flags."""
    bc = base_cycle_kernel(shape, mu, contacts, load)
    nums = five_numbers_kernel(bc)
    return DamperStiffness(lambda psi: complex_stiffness(bc, psi, method="interpolated"),
                           bc.status, nums.k_re_fs, jnp.maximum(nums.psi_bc, 1e-12))


def _exact(shape, mu, contacts, load, initial: str = "gross_slip") -> DamperStiffness:
    """k(psi_a) from the exact steady cycle at each amplitude (`jaxdamp.amplitude`), from the named
    initial state (gross_slip: the state after a gross-slip history). The stuck limit, the
    amplitude scale and the status come from the Base-Cycle."""
    base = _interpolated(shape, mu, contacts, load)

    def curve(design):
        def k_of_psi(psi):
            psi = jnp.asarray(psi, float)
            cycles = jax.vmap(lambda a: amplitude_kernel(*design, a, initial=initial))(
                psi.reshape(-1))
            return cycles.k_re.reshape(psi.shape), cycles.k_im.reshape(psi.shape)
        return k_of_psi

    design = (shape, mu, contacts, load)
    return base._replace(k_of_psi=curve(design), k_values=curve(jax.lax.stop_gradient(design)))


STIFFNESS_METHODS: dict[str, Callable[..., DamperStiffness]] = {"interpolated": _interpolated,
                                                                "exact": _exact}


def register_stiffness_method(name: str, factory: Callable[..., DamperStiffness]) -> None:
    """Add a way to build k(psi_a): factory(shape, mu, contacts, load) -> DamperStiffness.

    Built in: "exact" (the travel-limited steady cycles of `jaxdamp.amplitude`, option initial=)
    and "interpolated" (the paper's linear microslip interpolation, for comparison with it)."""
    STIFFNESS_METHODS[name] = factory


def _is_traced(*trees) -> bool:
    return any(isinstance(x, jax.core.Tracer) for x in jax.tree_util.tree_leaves(trees))


def damper_stiffness_kernel(shape, mu, contacts, load, method: str = "exact",
                            **options) -> DamperStiffness:
    """`damper_stiffness` without input checks, for use inside jit/vmap/grad (inputs as
    `prepare_scene` returns them)."""
    if method not in STIFFNESS_METHODS:
        raise ValueError(f"method must be one of {', '.join(STIFFNESS_METHODS)}; got {method!r}")
    return STIFFNESS_METHODS[method](shape, mu, contacts, load, **options)


def damper_stiffness(shape, mu, contacts=None, load=None, method: str = "exact",
                     **options) -> DamperStiffness:
    """The damper's amplitude-dependent complex stiffness for one design (pure JAX, traceable in
    the shape, mu, contact stiffness and load). method: a key of STIFFNESS_METHODS, by default the
    exact curve from a gross-slip history (options: initial="gross_slip" | "assembly").

    Concrete inputs are checked here (`params.prepare_inputs`); traced ones are not (check them
    once outside, or call `damper_stiffness_kernel`)."""
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    if _is_traced(shape, mu, contacts, load):
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
    is monotone between grid points. Beyond the ends the end values hold."""
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


def peak_band(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode(), force_n=1.0,
              psi_grid_mrad=None, n_samples: int = 64, steps: int = 6, runner=None):
    """Bounds of the peak amplitude A* (mm) over every admissible contact history.

    At each amplitude every history's steady cycle has k_Im inside the band
    (`jaxdamp.band.amplitude_band`), and the peak equation A (eta k_b + 1e-3 r^2 k_Im(r A)) = F
    gives a smaller A for a larger k_Im: the peaks of the band's lower and upper k_Im curves bracket
    the peak of every history. The band is tabulated on psi_grid_mrad (default: 24 amplitudes from
    0.05 psi_BC to 3 psi_BC, one batched program: `band.amplitude_bands`; runner as there) and
    interpolated linearly between them. Returns (Peaks with the band's
    lowest k_Im: the highest A*, Peaks with its highest k_Im: the lowest A*, the grid and the
    bound curves)."""
    shape, mu, contacts, load, mode = prepare_scene(shape, mu, contacts, load, mode)
    base = _interpolated(shape, mu, contacts, load)
    if psi_grid_mrad is None:
        psi_ref = float(base.psi_ref_mrad)
        psi_grid_mrad = np.geomspace(0.05 * psi_ref, 3.0 * psi_ref, 24)
    grid = np.asarray(psi_grid_mrad, float)
    # every amplitude's band in one batched program (sampling plus the trust-region refinement)
    bands = amplitude_bands(shape, mu, grid, contacts, load, n_samples=n_samples, steps=steps,
                            runner=runner)
    # (n, 4): k_re_min, k_re_max, k_im_min, k_im_max; zero where no history gives a valid cycle
    k = np.array([b.bounds if b.status == RESULTS.ok else np.zeros(4) for b in bands])
    # The frequency uses k_Re; at the bound of k_Im take the k_Re of the same band (its middle).
    k_re_mid = 0.5 * (k[:, 0] + k[:, 1])
    force = jnp.asarray(force_n, float)
    forces = force.reshape(-1)
    pick = (lambda x: x[0]) if force.ndim == 0 else (lambda x: x)  # noqa: E731

    def solve(k_im, envelope):
        peaks = _tabulated_peaks(jnp.asarray(grid), jnp.asarray(k_re_mid), jnp.asarray(k_im),
                                 base.status, base.k_re_stuck, base.psi_ref_mrad, mode, forces,
                                 envelope=envelope)
        return jax.tree_util.tree_map(pick, peaks)

    return solve(k[:, 2], "lower"), solve(k[:, 3], "upper"), grid, k


@batch_jit(static_argnames=("envelope",))
def _tabulated_peaks(grid, k_re, k_im, status, k_re_stuck, psi_ref, mode, forces, envelope):
    """Peaks at each force of the curve tabulated on grid (`tabulated_stiffness`): one module-level
    program whose curve is an argument, so that every band's peaks reuse it."""
    base = DamperStiffness(None, status, k_re_stuck, psi_ref)
    damper = tabulated_stiffness(grid, k_re, k_im, base, envelope=envelope)
    return jax.vmap(lambda f: peak_response(damper, mode, f))(forces)


def scaled_stiffness(ref: DamperStiffness, fd_ref_n, fd_n, contact_scale=1.0) -> DamperStiffness:
    """The paper's scaling law: k(psi; F_D, c kn, c kt) from the curve at (F_D0, kn, kt).

    Forces (and moments) scale with F_D; displacements (and psi) with F_D / k at fixed kt/kn. So
    M(psi; F_D, c) = (F_D/F_D0) M0(psi / s) with s = (F_D/F_D0) / c, and k = M / psi gives
    k(psi; F_D, c) = c k0(psi c F_D0 / F_D). At fixed contact stiffness (c = 1) an F_D change only
    stretches the psi axis: the stick stiffness is independent of F_D. An F_D sweep costs one curve.
    """
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
    """The stuck limit: a real spring k_Re,fs at every amplitude (no dissipation)."""
    k = jnp.asarray(k_re_stuck, float)
    return DamperStiffness(lambda psi: (jnp.zeros_like(psi) + k, jnp.zeros_like(psi)),
                           jnp.int32(RESULTS.ok), k, jnp.asarray(1.0))


def no_damper() -> DamperStiffness:
    """The free limit: platforms without a damper."""
    return stuck_damper(0.0)


# ----------------------------------------------------------------------------- FRF (closed form)


class FRF(NamedTuple):
    """First-harmonic response curve at force F, layered by amplitude (arrays over the A grid).

    At each A the equation |D| A = F has up to two frequencies: the low branch (below the peak
    frequency) and the high branch. Missing branches are masked (has_low / has_high False, value
    0), never NaN. status: the damper curve's RESULTS code (its numbers mean nothing unless valid).
    """

    amplitude_mm: jnp.ndarray
    f_low_hz: jnp.ndarray
    f_high_hz: jnp.ndarray
    has_low: jnp.ndarray
    has_high: jnp.ndarray
    status: jnp.ndarray

    def __repr__(self):
        return (f"FRF(amplitude {number_repr(self.amplitude_mm, 'mm')}, low branch "
                f"{number_repr(self.f_low_hz, 'Hz')}, high branch {number_repr(self.f_high_hz, 'Hz')}, "
                f"status {status_repr(self.status)})")


def _dyn(mode: BladeMode, k_of_psi, amplitude_mm):
    """Damper-modified modal stiffness terms at amplitude A: (real part less the inertia, imaginary)."""
    a = jnp.asarray(amplitude_mm, float)
    k_re, k_im = k_of_psi(mode.r * a)
    g = 1e-3 * mode.r ** 2
    return mode.k_b + g * k_re, mode.eta * mode.k_b + g * k_im


def frf(damper: DamperStiffness, mode: BladeMode, force_n, amplitude_mm) -> FRF:
    """Frequencies (Hz) at which the first-harmonic amplitude is A, for each A of amplitude_mm.

    k_b (1 - W) + K_re = +/- sqrt((F/A)^2 - K_im'^2) with W = (omega/omega0)^2 and
    K_im' = eta k_b + 1e-3 r^2 k_Im: W = (k_b + K_re -/+ s) / k_b, s = sqrt(...).
    """
    a = jnp.asarray(amplitude_mm, float)
    re, im = _dyn(mode, damper.k_of_psi, a)
    pos = a > 0
    fa = jnp.asarray(force_n, float) / jnp.where(pos, a, 1.0)
    disc = fa ** 2 - im ** 2
    real = pos & (disc >= 0)
    s = jnp.where(real, jnp.sqrt(jnp.where(real, disc, 1.0)), 0.0)
    w_hi = (re + s) / mode.k_b
    w_lo = (re - s) / mode.k_b
    has_hi = real & (w_hi > 0)
    has_lo = real & (w_lo > 0)
    f_hi = jnp.where(has_hi, mode.f0_hz * jnp.sqrt(jnp.where(has_hi, w_hi, 1.0)), 0.0)
    f_lo = jnp.where(has_lo, mode.f0_hz * jnp.sqrt(jnp.where(has_lo, w_lo, 1.0)), 0.0)
    return FRF(a, f_lo, f_hi, has_lo, has_hi, damper.status)


def frf_amplitude_grid(top_mm, n: int = 200, low: float = 1e-2):
    """Amplitudes (mm) for an FRF up to the peak top_mm: log-spaced from low * top, then dense
    towards the top where the two branches meet (1 - A/top from 1e-2 down to 1e-7)."""
    top = jnp.asarray(top_mm, float)
    m = n // 2
    base = top * jnp.geomspace(low, 0.99, n - m)
    near = top * (1.0 - jnp.geomspace(1e-2, 1e-7, m))
    return jnp.concatenate([base, near])


def response_amplitude_linear(mode: BladeMode, k_re, k_im, force_n, frequency_hz):
    """|A| = F / |D| for a damper frozen at (k_re, k_im) (a linear spring): the free and stuck
    limits' FRFs as a function of frequency."""
    w = (jnp.asarray(frequency_hz, float) / mode.f0_hz) ** 2
    g = 1e-3 * mode.r ** 2
    re = mode.k_b * (1.0 - w) + g * k_re
    im = mode.eta * mode.k_b + g * k_im
    return force_n / jnp.sqrt(re ** 2 + im ** 2)


def linear_frf(mode: BladeMode, k_re, force_n, n: int = 200) -> FRF:
    """The FRF of the blade with a damper frozen as a real spring k_re (N mm/mrad; 0: free, k_Re,fs:
    stuck) across its own resonance: amplitudes up to its own peak F / (eta k_b), at
    f0 sqrt(1 + 1e-3 r^2 k_re / k_b). Without structural damping (eta = 0) the peak is unbounded:
    the grid then stops at 1e3 F / k_b."""
    damped = mode.eta * mode.k_b > 0
    force = jnp.asarray(force_n, float)
    top = jnp.where(damped, force / jnp.where(damped, mode.eta * mode.k_b, 1.0),
                    1e3 * force / mode.k_b)
    return frf(stuck_damper(k_re), mode, force, frf_amplitude_grid(top, n))


# ----------------------------------------------------------------------------- peak response

N_GRID = 160  # bracketing grid points (log-spaced)
GRID_DECADES = 7.0  # the grid spans [A_hi 10^-7, A_hi]
MAX_ROOTS = 4
REFINE_STEPS = 60  # at most this many bracketed (Illinois) steps per root


class Peaks(NamedTuple):
    """Every peak amplitude A* at force F: the roots of A (eta k_b + 1e-3 r^2 k_Im(r A)) = F.

    roots_mm / frequency_hz: (MAX_ROOTS,) ascending, masked by `found` (0 where absent). Between
    the first and the second root the response curve has no point; roots 2 and 3 bound an isola
    (a detached branch), and so on. peak_amplitude_mm is the first root: the largest amplitude on
    the branch connected to small amplitudes; max_amplitude_mm is the largest root (isolas
    included). psi_a_mrad = r * peak_amplitude_mm. status: RESULTS (no_root where the search range
    holds no root, e.g. eta = 0 and F beyond the damper's friction force; the damper's own status
    otherwise). n_roots counts the sign changes on the grid (roots closer than a grid cell pair
    up and are missed: tangencies are not reported).
    """

    roots_mm: jnp.ndarray
    frequency_hz: jnp.ndarray
    found: jnp.ndarray
    n_roots: jnp.ndarray
    peak_amplitude_mm: jnp.ndarray
    peak_frequency_hz: jnp.ndarray
    psi_a_mrad: jnp.ndarray
    max_amplitude_mm: jnp.ndarray
    status: jnp.ndarray

    def __repr__(self):
        return (f"Peaks(A* {number_repr(self.peak_amplitude_mm, 'mm')} at "
                f"{number_repr(self.peak_frequency_hz, 'Hz')}, psi_a "
                f"{number_repr(self.psi_a_mrad, 'mrad')}, "
                f"roots {number_repr(self.n_roots, '', '.0f')}, "
                f"status {status_repr(self.status)})")


def peak_residual(damper: DamperStiffness, mode: BladeMode, force_n, amplitude_mm):
    """A (eta k_b + 1e-3 r^2 k_Im(r A)) - F, N: zero at a peak (Re D = 0 and |D| A = F)."""
    a = jnp.asarray(amplitude_mm, float)
    _, im = _dyn(mode, damper.k_of_psi, a)
    return a * im - force_n


def peak_frequency_hz(damper: DamperStiffness, mode: BladeMode, amplitude_mm):
    """f = f0 sqrt(1 + 1e-3 r^2 k_Re(r A) / k_b): the frequency where Re D = 0 at amplitude A."""
    re, _ = _dyn(mode, damper.k_of_psi, amplitude_mm)
    w = re / mode.k_b
    ok = w > 0
    return jnp.where(ok, mode.f0_hz * jnp.sqrt(jnp.where(ok, w, 1.0)), 0.0)


ROOT_RTOL = 1e-13  # relative step (or bracket width) at which a root has converged


def _bracketed_root(g, lo, hi, glo, ghi, steps):
    """Root of g in [lo, hi] from g(lo) = glo, g(hi) = ghi of opposite signs: the Illinois
    variant of regula falsi (superlinear, the bracket is kept), at most `steps` evaluations,
    stopping when a step or the bracket is below ROOT_RTOL of the root.

    Values only, and derivative-free: the damper curve's values run its fast program (loops that
    stop when done), while a Newton step would need its derivative program. `_root_ift`
    differentiates the root by the implicit function theorem, never through this loop, so it may
    be a while loop (under vmap it runs until every root has converged)."""

    def body(c):
        i, lo, hi, glo, ghi, x, side, _ = c
        d = ghi - glo
        ok = d != 0
        x_new = jnp.where(ok, (lo * ghi - hi * glo) / jnp.where(ok, d, 1.0), 0.5 * (lo + hi))
        x_new = jnp.clip(x_new, lo, hi)
        gx = g(x_new)
        right = jnp.sign(gx) == jnp.sign(ghi)  # the root is left of x_new: x_new becomes hi
        # Illinois: halve the value kept at the end that did not move twice in a row.
        glo = jnp.where(right, jnp.where(side > 0, 0.5 * glo, glo), gx)
        ghi = jnp.where(right, gx, jnp.where(side < 0, 0.5 * ghi, ghi))
        lo, hi = jnp.where(right, lo, x_new), jnp.where(right, x_new, hi)
        side = jnp.where(right, 1, -1)
        tol = ROOT_RTOL * jnp.abs(x_new)
        done = (gx == 0) | (jnp.abs(x_new - x) <= tol) | (hi - lo <= tol)
        return i + 1, lo, hi, glo, ghi, x_new, side, done

    def more(c):
        return (c[0] < steps) & ~c[7]

    start = (jnp.array(0), lo, hi, glo, ghi, hi, jnp.array(0), (hi - lo <= 0) | (glo == 0))
    x = jax.lax.while_loop(more, body, start)[5]
    return jnp.where(glo == 0, lo, x)


def _root_ift(g, g_values, lo, hi, glo, ghi, steps):
    """A root of the scalar g in the bracket [lo, hi], differentiable by the implicit function
    theorem (jax.lax.custom_root: dA* = -g_theta / g_A, through whatever g closes over). The
    search runs on g_values: g's values, with nothing to differentiate."""
    lo, hi, glo, ghi = (jax.lax.stop_gradient(v) for v in (lo, hi, glo, ghi))

    def solve(f, x0):
        return _bracketed_root(g_values, lo, hi, glo, ghi, steps)

    def tangent_solve(f_lin, y):
        d = f_lin(jnp.ones_like(y))
        ok = jnp.abs(d) > 0
        return jnp.where(ok, y / jnp.where(ok, d, 1.0), 0.0)

    return jax.lax.custom_root(g, 0.5 * (lo + hi), solve, tangent_solve)


SHARED_GRID_FACTOR = 1.5  # a force array's shared grid has this many times n_grid points


def peak_response(damper: DamperStiffness, mode: BladeMode, force_n, *, n_grid: int = N_GRID,
                  max_roots: int = MAX_ROOTS, amplitude_cap_mm=None) -> Peaks:
    """Every peak amplitude A* (mm) at modal force F (N) and its frequency (Hz); see `Peaks`.

    Search: since k_Im >= 0 and g(0) = -F < 0, every root lies in (0, F / (eta k_b)]; the grid is
    log-spaced over GRID_DECADES below that bound (or below amplitude_cap_mm when eta = 0, default
    1e6 psi_ref / r). Each sign change is refined by bracketed regula falsi (Illinois); gradients by
    the implicit function theorem. Pure JAX: jit, vmap (e.g. over designs), grad, jacfwd.

    force_n: a scalar, or a 1-D array of forces (then every field has a leading force axis). The
    forces of an array share one amplitude grid, since k(psi) does not depend on F (the layered
    method's point): SHARED_GRID_FACTOR * n_grid points from GRID_DECADES below the smallest
    force's bound to the largest's, as fine as one force's grid for forces within 10^3.5 of each
    other (coarser beyond). The damper curve is evaluated once on it instead of once per force.
    """
    f = jnp.asarray(force_n, float)
    if f.ndim > 1:
        raise ValueError(f"force_n must be a scalar or a 1-D array of forces in N; got shape {f.shape}")
    if (damper.source is not None and damper.source.matches(damper) and n_grid == N_GRID
            and max_roots == MAX_ROOTS and amplitude_cap_mm is None and not _is_traced(mode, f)):
        # A curve that `damper_stiffness` built from concrete inputs, called from plain Python:
        # the compiled peak program of its method (the same function, jitted), not op by op.
        src = damper.source
        mode = BladeMode(*(jnp.asarray(v, float) for v in validate_mode(mode)))
        return peak_program(src.method, src.options)(*src.design, mode, f)
    forces = f.reshape(-1)
    damped = mode.eta * mode.k_b > 0
    cap = (1e6 * damper.psi_ref_mrad / mode.r if amplitude_cap_mm is None
           else jnp.asarray(amplitude_cap_mm, float))
    a_hi = jnp.where(damped, forces / jnp.where(damped, mode.eta * mode.k_b, 1.0) * (1.0 + 1e-9),
                     cap)
    a_hi = jax.lax.stop_gradient(a_hi)
    if f.ndim == 0:
        grid = a_hi[0] * jnp.logspace(-GRID_DECADES, 0.0, n_grid)
    else:
        top = jnp.max(a_hi)
        decades = GRID_DECADES + jnp.log10(top / jnp.min(a_hi))
        grid = top * jnp.logspace(-1.0, 0.0, int(SHARED_GRID_FACTOR * n_grid)) ** decades
    grid = jnp.concatenate([jnp.zeros(1), grid])
    cells_n = grid.size - 1
    # The searches run on the curve's values (see DamperStiffness.values); g(a) = a im(a) - F, so
    # the grid's residual at F = 0 serves every force.
    values = damper._replace(k_of_psi=damper.values)
    a_im = jax.lax.stop_gradient(peak_residual(values, mode, 0.0, grid))

    def one_force(force):
        def g_of(a):
            return peak_residual(damper, mode, force, a)

        def g_values(a):
            return peak_residual(values, mode, jax.lax.stop_gradient(force), a)

        gg = a_im - force
        change = (jnp.sign(gg[:-1]) != jnp.sign(gg[1:])) & (gg[:-1] != 0)
        n_roots = jnp.sum(change).astype(jnp.int32)
        # The first max_roots sign changes, in ascending order (cells without a change sort last).
        cells = jnp.argsort(jnp.where(change, jnp.arange(cells_n), cells_n + 1))[:max_roots]
        found = jnp.arange(max_roots, dtype=jnp.int32) < n_roots
        lo = grid[cells]
        hi = jnp.where(found, grid[cells + 1], lo)  # an empty bracket: nothing to refine

        roots = jax.vmap(lambda *b: _root_ift(g_of, g_values, *b, REFINE_STEPS))(
            lo, hi, gg[cells], gg[cells + 1])
        roots = jnp.where(found, roots, 0.0)
        freqs = jnp.where(found, peak_frequency_hz(damper, mode, jnp.where(found, roots, 1.0)),
                          0.0)
        last = jnp.clip(jnp.minimum(n_roots, max_roots) - 1, 0, max_roots - 1)
        status = RESULTS.promote(damper.status, n_roots == 0, RESULTS.no_root)
        peak = roots[0]
        return Peaks(roots, freqs, found, n_roots, peak, freqs[0], mode.r * peak, roots[last],
                     status)

    peaks = jax.vmap(one_force)(forces)
    return jax.tree_util.tree_map(lambda x: x[0], peaks) if f.ndim == 0 else peaks


_PEAK_PROGRAMS: dict = {}


def peak_program(method: str, options: tuple = ()):
    """One compiled peak solver per stiffness method and options (sorted (name, value) pairs),
    reused by every call: (shape, mu, contacts, load, mode, force_n) -> Peaks, on prepared inputs
    (`prepare_scene`); force_n a scalar or a 1-D array."""
    if (method, options) not in _PEAK_PROGRAMS:
        def run(shape, mu, contacts, load, mode, force_n):
            d = damper_stiffness_kernel(shape, mu, contacts, load, method, **dict(options))
            return peak_response(d, mode, force_n)

        _PEAK_PROGRAMS[method, options] = batch_jit(run)
    return _PEAK_PROGRAMS[method, options]


class ResponseCurves(NamedTuple):
    """`response_curves`: the peaks at each force and the FRFs with the damper, free and stuck
    (each field has a leading force axis). The damped FRF runs up to the largest peak root (up to
    F / (eta k_b) where the damper is not valid); the free and stuck ones across their own peaks
    (`linear_frf`). status: the damper curve's RESULTS code; k_re_stuck in N mm/mrad."""

    peaks: Peaks
    damper: FRF
    free: FRF
    stuck: FRF
    status: jnp.ndarray
    k_re_stuck: jnp.ndarray

    def __repr__(self):
        return (f"ResponseCurves({self.peaks!r}, k_Re,stuck "
                f"{number_repr(self.k_re_stuck, 'N mm/mrad')}, status {status_repr(self.status)})")


_CURVE_PROGRAMS: dict = {}


def curves_program(method: str, options: tuple = ()):
    """One compiled program per stiffness method and options (sorted (name, value) pairs): the
    damper curve once, the peaks of every force on one shared grid, and the three FRFs:
    (shape, mu, contacts, load, mode, forces (n,)) -> ResponseCurves, on prepared inputs."""
    if (method, options) not in _CURVE_PROGRAMS:
        def run(shape, mu, contacts, load, mode, forces):
            d = damper_stiffness_kernel(shape, mu, contacts, load, method, **dict(options))
            peaks = peak_response(d, mode, forces)
            valid = RESULTS.valid(peaks.status) & (peaks.max_amplitude_mm > 0)
            free_top = forces / jnp.maximum(mode.eta * mode.k_b, 1e-300)
            top = jnp.where(valid, peaks.max_amplitude_mm, jnp.minimum(free_top, 1e6))
            damped = jax.vmap(lambda f, t: frf(d, mode, f, frf_amplitude_grid(t)))(forces, top)
            free = jax.vmap(lambda f: linear_frf(mode, 0.0, f))(forces)
            stuck = jax.vmap(lambda f: linear_frf(mode, d.k_re_stuck, f))(forces)
            return ResponseCurves(peaks, damped, free, stuck, d.status, d.k_re_stuck)

        _CURVE_PROGRAMS[method, options] = batch_jit(run)
    return _CURVE_PROGRAMS[method, options]


def response_curves(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode(),
                    force_n=(1.0,), method: str = "exact", **options) -> ResponseCurves:
    """Peaks and FRFs (damper, free, stuck) of one design at the forces force_n (N, 1-D): inputs
    checked once here, then one compiled program (`curves_program`)."""
    shape, mu, contacts, load, mode = prepare_scene(shape, mu, contacts, load, mode)
    forces = jnp.asarray(force_n, float).reshape(-1)
    check_positive("force_n", np.asarray(forces), unit="N")
    return curves_program(method, tuple(sorted(options.items())))(shape, mu, contacts, load, mode,
                                                                  forces)


def prepare_scene(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode()):
    """Validated design (`params.prepare_inputs`) and blade mode (`validate_mode`) as float arrays:
    what every compiled response, HBM and time-integration entry point takes."""
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    validate_mode(mode)
    return shape, mu, contacts, load, BladeMode(*(jnp.asarray(v, float) for v in mode))


def design_peaks(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode(), force_n=1.0,
                 method: str = "exact", **options) -> Peaks:
    """`peak_response` of one design, compiled (force_n may be an array: vmapped over it)."""
    shape, mu, contacts, load, mode = prepare_scene(shape, mu, contacts, load, mode)
    force = jnp.asarray(force_n, float)
    run = peak_program(method, tuple(sorted(options.items())))
    if force.ndim == 0:
        return run(shape, mu, contacts, load, mode, force)
    return jax.vmap(run, in_axes=(None, None, None, None, None, 0))(shape, mu, contacts, load,
                                                                    mode, force)


# ----------------------------------------------------------------------------- designer's diagram


class DesignerDiagram(NamedTuple):
    """Peak response against force and against F_D, over a friction range (numpy arrays).

    peak_vs_force_mm: (n_mu, n_force) at the design's F_D; peak_vs_fd_mm: (n_mu, n_fd) at
    force_at_fd_n. band_*: min and max over mu. stuck_*: the damper stuck (k_Re,fs, k_Im = 0);
    free_*: no damper. In the loss-factor model both limits have the peak F / (eta k_b): they
    coincide in amplitude and differ in frequency (stuck_frequency_hz, per mu, against f0).
    status: (n_mu,) damper status per mu.
    """

    mu: np.ndarray
    force_n: np.ndarray
    fd_n: np.ndarray
    force_at_fd_n: float
    peak_vs_force_mm: np.ndarray
    peak_vs_fd_mm: np.ndarray
    band_force_mm: np.ndarray  # (2, n_force): min, max over mu
    band_fd_mm: np.ndarray  # (2, n_fd)
    free_vs_force_mm: np.ndarray
    stuck_vs_force_mm: np.ndarray
    free_vs_fd_mm: np.ndarray
    stuck_vs_fd_mm: np.ndarray
    stuck_frequency_hz: np.ndarray  # (n_mu,)
    status: np.ndarray

    def __repr__(self):
        return (f"DesignerDiagram(mu {number_repr(self.mu, '')}, F {number_repr(self.force_n, 'N')}, "
                f"F_D {number_repr(self.fd_n, 'N')}, A* {number_repr(self.peak_vs_force_mm, 'mm')}, "
                f"status {status_repr(self.status)})")


DIAGRAM_MUS = (0.3, 0.4, 0.5, 0.6, 0.7)


def designer_diagram(shape, mode: BladeMode = BladeMode(), contacts=None, load=None, *,
                     force_n=None, fd_n=None, force_at_fd_n=None, mu=DIAGRAM_MUS,
                     method: str = "exact", runner=None, **options) -> DesignerDiagram:
    """The designer's diagram of one shape: peak A* against F (log-log) and against F_D at fixed
    F, for each mu (the band is their envelope), with the stuck and free limits.

    The F_D sweep uses `scaled_stiffness`: one damper curve per mu for every F_D. One compiled
    program (`diagram_program`), vmapped over mu; runner(program, args) -> outputs runs it
    (default program(*args); the CLI passes one that reuses a saved export of the program).
    """
    load = LoadCase() if load is None else load
    fd0 = float(load.F_D)
    force = np.asarray(np.geomspace(0.05, 100.0, 41) if force_n is None else force_n, float)
    fds = np.asarray(np.geomspace(fd0 / 30.0, fd0 * 30.0, 41) if fd_n is None else fd_n, float)
    f_fd = float(np.median(force) if force_at_fd_n is None else force_at_fd_n)
    mus = np.asarray(mu, float)

    scene = prepare_scene(shape, mus[0], contacts, load, mode)
    for m in mus[1:]:
        validate_mu(float(m))
    program = diagram_program(method, tuple(sorted(options.items())))
    shape, _, contacts, load, mode = scene
    args = (shape, jnp.asarray(mus), contacts, load, mode, jnp.asarray(force), jnp.asarray(fds),
            jnp.asarray(fd0), jnp.asarray(f_fd))
    outs = program(*args) if runner is None else runner(program, args)
    by_force, by_fd, stuck_f, status = (np.asarray(v) for v in outs)
    free_f = force / (float(mode.eta) * float(mode.k_b))
    free_d = np.full(fds.shape, f_fd / (float(mode.eta) * float(mode.k_b)))
    return DesignerDiagram(
        mus, force, fds, f_fd, by_force, by_fd, np.stack([by_force.min(0), by_force.max(0)]),
        np.stack([by_fd.min(0), by_fd.max(0)]), free_f, free_f.copy(), free_d, free_d.copy(),
        stuck_f, status.astype(int))


_DIAGRAM_PROGRAMS: dict = {}


def diagram_program(method: str, options: tuple = ()):
    """The designer's diagram as one compiled program per method and options, vmapped over mu:
    (shape, mus, contacts, load, mode, forces, fds, fd0, force_at_fd) -> (peak against force
    (n_mu, n_force), against F_D (n_mu, n_fd), stuck frequency (n_mu,), status (n_mu,))."""
    if (method, options) not in _DIAGRAM_PROGRAMS:
        def per_mu(shape, m, contacts, load, mode, forces, fds, fd0, f_fd):
            d = damper_stiffness_kernel(shape, m, contacts, load, method, **dict(options))
            by_force = peak_response(d, mode, forces).peak_amplitude_mm  # one shared grid
            by_fd = jax.vmap(lambda fd: peak_response(scaled_stiffness(d, fd0, fd), mode,
                                                      f_fd).peak_amplitude_mm)(fds)
            stuck_f = peak_frequency_hz(stuck_damper(d.k_re_stuck), mode, 1.0)
            return by_force, by_fd, stuck_f, d.status

        _DIAGRAM_PROGRAMS[method, options] = batch_jit(jax.vmap(
            per_mu, in_axes=(None, 0, None, None, None, None, None, None, None)))
    return _DIAGRAM_PROGRAMS[method, options]


__all__ = ["BladeMode", "DamperStiffness", "FRF", "Peaks", "DesignerDiagram", "STIFFNESS_METHODS",
           "damper_stiffness", "register_stiffness_method", "scaled_stiffness", "stuck_damper",
           "no_damper", "frf", "frf_amplitude_grid", "response_amplitude_linear", "peak_residual",
           "peak_frequency_hz",
           "peak_response", "design_peaks", "designer_diagram", "validate_mode", "DIAGRAM_MUS",
           "damper_stiffness_kernel", "linear_frf", "ResponseCurves", "curves_program",
           "response_curves", "diagram_program", "peak_program", "prepare_scene", "peak_band",
           "tabulated_stiffness"]
