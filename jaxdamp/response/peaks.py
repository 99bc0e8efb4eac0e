"""The peak response: every root of A (eta k_b + 1e-3 r^2 k_Im(r A)) = F, bracketed on a grid and
refined, with implicit-function derivatives; the compiled programs for peaks and response curves,
one per stiffness method and options, built once per process."""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..geometry import is_wedge
from ..motion import in_phase_motion, validate_motion
from ..runtime import batch_jit
from ..status import RESULTS, number_repr, status_repr
from .._validate import check_int, check_range, check_values, traced
from .root_search import GRID_CHUNK, grid_apart_then_roots, grid_then_roots
from .frf import FRF, FRF_POINTS, dynamic_stiffness, frf, frf_amplitude_grid, linear_frf
from .scene import BladeMode, Scene, prepare_scene, validate_mode
from .stiffness import (DamperStiffness, check_damper, check_history, damper_stiffness_kernel,
                        path_cycle_kernel, path_damper, with_residual)

__all__ = ["N_GRID", "GRID_DECADES", "MAX_ROOTS", "REFINE_STEPS",
           "SHARED_GRID_FACTOR", "Peaks", "peak_residual", "peak_frequency_hz", "peak_response",
           "peak_program", "ResponseCurves", "curves_program", "response_curves", "design_peaks",
           "PATH_LOOP", "PATH_REPEATS", "path_peaks", "series_peaks", "path_curves_program",
           "path_response_curves"]


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
    _, im = dynamic_stiffness(mode, damper.k_of_psi, a)
    return a * im - force_n


def peak_frequency_hz(damper: DamperStiffness, mode: BladeMode, amplitude_mm):
    """f = f0 sqrt(1 + 1e-3 r^2 k_Re(r A) / k_b): the frequency where Re D = 0 at amplitude A."""
    re, _ = dynamic_stiffness(mode, damper.k_of_psi, amplitude_mm)
    w = re / mode.k_b
    ok = w > 0
    return jnp.where(ok, mode.f0_hz * jnp.sqrt(jnp.where(ok, w, 1.0)), 0.0)


def _root_ift(g, x):
    """The roots x of g (arrays; g elementwise, so its Jacobian is diagonal), found by a values-
    only search (`root_search`), differentiable by the implicit function theorem:
    dA* = -g_theta / g_A, through whatever g closes over (hoisted by jax.closure_convert).

    A custom JVP rather than jax.lax.custom_root: custom_root traces its tangent solve (the
    damper curve's JVP, the largest trace of the response program: 12 of 39 s under a profiler)
    on every call, differentiated or not; a custom JVP rule is traced only under
    differentiation."""
    x = jax.lax.stop_gradient(x)
    g_closed, consts = jax.closure_convert(g, x)

    @jax.custom_jvp
    def root(x, consts):
        return x

    @root.defjvp
    def root_jvp(primals, tangents):  # x's own tangent is zero: it comes from the values
        (x, c), (_, dc) = primals, tangents
        g_a = jax.jvp(lambda a: g_closed(a, *c), (x,), (jnp.ones_like(x),))[1]  # the diagonal
        g_t = jax.jvp(lambda *cc: g_closed(x, *cc), tuple(c), tuple(dc))[1]
        ok = jnp.abs(g_a) > 0
        return x, jnp.where(ok, -g_t / jnp.where(ok, g_a, 1.0), 0.0)

    return root(jax.lax.stop_gradient(x), tuple(consts))


def _amplitude_grid(damper: DamperStiffness, mode: BladeMode, forces, n_grid: int,
                    amplitude_cap_mm=None, shared: bool = True):
    """The peak search's tip amplitudes (mm), 0 first, then log-spaced up to the largest force's
    bound (`peak_response`; shared False: one force's grid, forces of size 1); values only."""
    damped = mode.eta * mode.k_b > 0
    cap = (1e6 * damper.psi_ref_mrad / mode.r if amplitude_cap_mm is None
           else jnp.asarray(amplitude_cap_mm, float))
    a_hi = jnp.where(damped, forces / jnp.where(damped, mode.eta * mode.k_b, 1.0) * (1.0 + 1e-9),
                     cap)
    a_hi = jax.lax.stop_gradient(a_hi)
    if not shared:
        grid = a_hi[0] * jnp.logspace(-GRID_DECADES, 0.0, n_grid)
    else:
        top = jnp.max(a_hi)
        decades = GRID_DECADES + jnp.log10(top / jnp.min(a_hi))
        grid = top * jnp.logspace(-1.0, 0.0, int(SHARED_GRID_FACTOR * n_grid)) ** decades
    return jnp.concatenate([jnp.zeros(1), grid])


SHARED_GRID_FACTOR = 1.5  # a force array's shared grid has this many times n_grid points


def _check_search(damper, n_grid, max_roots, amplitude_cap_mm, search_width, flags) -> None:
    """`peak_response`'s damper and search options, each refused in one line (a grid smaller than
    max_roots failed inside with a broadcasting error, one point found no root silently, no root
    slot with an IndexError)."""
    check_damper(damper)
    for name, flag in flags.items():  # "no" was taken as True
        if not isinstance(flag, (bool, np.bool_)):
            raise ValueError(f"{name} must be True or False; got {flag!r}")
    max_roots = check_int("max_roots", max_roots, 1)
    check_int("n_grid", n_grid, max(2, max_roots))  # a bracket needs two points; a root a bracket
    if search_width is not None:
        check_int("search_width", search_width, 1)
    if amplitude_cap_mm is not None and not traced(amplitude_cap_mm):
        check_range("amplitude_cap_mm", amplitude_cap_mm, 0.0, np.inf, lo_open=True, hi_open=True,
                    unit="mm")


def peak_response(damper: DamperStiffness, mode: BladeMode, force_n, *, n_grid: int = N_GRID,
                  max_roots: int = MAX_ROOTS, amplitude_cap_mm=None,
                  differentiable: bool = True, frequencies: bool = True,
                  search_width: int | None = None) -> Peaks:
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

    differentiable=False: values only (the roots are not wrapped for the implicit function
    theorem, and nothing of the damper curve's derivative is traced: a program several times
    faster to build, for searches that no gradient passes through). frequencies=False: the
    frequencies are left zero, for a caller that evaluates the curve at the roots itself (one
    call of the curve fewer in its program: `path_peaks`). search_width: None, the grid is
    evaluated in one call before the search; an int, in the search's loop, that many amplitudes a
    step (`root_search.grid_then_roots`: one copy of the curve in the program instead of two, for
    an expensive curve such as a path's cycles).

    mode: a BladeMode (checked here when concrete and the compiled program runs), or a Scene
    (`prepare_scene`: its mode, checked already). damper: a DamperStiffness (checked when
    `damper_stiffness` made it). Otherwise unchecked, traceable (jit, vmap, grad): a damper built
    by hand or traced, with its mode and force_n, is taken as given.
    """
    _check_search(damper, n_grid, max_roots, amplitude_cap_mm, search_width,
                  dict(differentiable=differentiable, frequencies=frequencies))
    checked = isinstance(mode, Scene)
    mode = mode.mode if checked else mode
    if not traced(force_n):  # a concrete force is checked (a negative one gave NaN peaks)
        check_values("force_n", force_n)
    f = jnp.asarray(force_n, float)
    if f.ndim > 1:
        raise ValueError(f"force_n must be a scalar or a 1-D array of forces in N; got shape {f.shape}")
    if not differentiable:
        damper = damper._replace(k_of_psi=damper.values)
    if (differentiable and damper.source is not None and damper.source.matches(damper)
            and n_grid == N_GRID
            and max_roots == MAX_ROOTS and amplitude_cap_mm is None and not traced(mode, f)):
        # A curve that `damper_stiffness` built from concrete inputs, called from plain Python:
        # the compiled peak program of its method (the same function, jitted), not op by op.
        src = damper.source
        if not checked:
            mode = BladeMode(*(jnp.asarray(v, float) for v in validate_mode(mode)))
        return peak_program(src.method, src.options)(*src.design, mode, f)
    forces = f.reshape(-1)
    grid = _amplitude_grid(damper, mode, forces, n_grid, amplitude_cap_mm, f.ndim > 0)
    # The search runs on the curve's values (see DamperStiffness.values); g(a) = a im(a) - F, so
    # the residual at F = 0 serves every force (arrays (n_f, ...)).
    values = damper._replace(k_of_psi=damper.values)
    force = jax.lax.stop_gradient(forces[:, None])
    search = (grid_apart_then_roots if search_width is None
              else functools.partial(grid_then_roots, width=search_width))
    roots, _, found, n_roots = search(lambda a: (peak_residual(values, mode, 0.0, a), ()), grid,
                                      force, max_roots, REFINE_STEPS)
    if differentiable:
        roots = _root_ift(lambda a: peak_residual(damper, mode, forces[:, None], a), roots)
    roots = jnp.where(found, roots, 0.0)
    freqs = (jnp.where(found, peak_frequency_hz(damper, mode, jnp.where(found, roots, 1.0)), 0.0)
             if frequencies else jnp.zeros_like(roots))
    peaks = _peaks_of(roots, freqs, found, n_roots, mode.r * roots[:, 0], damper.status)
    return jax.tree_util.tree_map(lambda x: x[0], peaks) if f.ndim == 0 else peaks


def _peaks_of(roots, freqs, found, n_roots, psi_a_mrad, damper_status) -> Peaks:
    """`Peaks` (fields (n_f, ...)) of the roots (n_f, max_roots; 0 where not found) and their
    frequencies; psi_a_mrad (n_f,) the damper's amplitude at the first root."""
    max_roots = roots.shape[1]
    last = jnp.clip(jnp.minimum(n_roots, max_roots) - 1, 0, max_roots - 1)
    status = RESULTS.first({RESULTS.no_root: n_roots == 0}, damper_status)
    return Peaks(roots, freqs, found, n_roots, roots[:, 0], freqs[:, 0], psi_a_mrad,
                 jnp.take_along_axis(roots, last[:, None], axis=1)[:, 0], status)


@functools.cache
def peak_program(method: str, options: tuple = ()):
    """One compiled peak solver per stiffness method and options (sorted (name, value) pairs),
    reused by every call: (shape, mu, contacts, load, mode, force_n) -> Peaks, on prepared inputs
    (`prepare_scene`); force_n a scalar or a 1-D array."""
    def run(shape, mu, contacts, load, mode, force_n):
        d = damper_stiffness_kernel(shape, mu, contacts, load, method, **dict(options))
        return peak_response(d, mode, force_n)

    return batch_jit(run)


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


@functools.cache
def curves_program(method: str, options: tuple = ()):
    """One compiled program per stiffness method and options (sorted (name, value) pairs): the
    damper curve once, the peaks of every force on one shared grid, and the three FRFs:
    (shape, mu, contacts, load, mode, forces (n,)) -> ResponseCurves, on prepared inputs."""
    def run(shape, mu, contacts, load, mode, forces):
        d = damper_stiffness_kernel(shape, mu, contacts, load, method, **dict(options))
        # Values only: the program's inputs are checked concretely (`response_curves`), so
        # nothing differentiates it, and the roots' derivative rule would be one more trace.
        peaks = peak_response(d, mode, forces, differentiable=False, frequencies=False)
        at_roots, grids, flat = _root_and_frf_amplitudes(mode, forces, peaks, FRF_POINTS)
        k_re, k_im = d.k_of_psi(mode.r * flat)  # the curve at the roots and the FRFs, one batch
        peaks, on_grids = _at_roots_and_grids(peaks, d, mode, at_roots, grids, k_re, k_im)
        return _curves(d, mode, forces, peaks, on_grids)

    return batch_jit(run)


def _root_and_frf_amplitudes(mode: BladeMode, forces, peaks: Peaks, frf_points: int):
    """(the amplitudes at the roots (n_f, MAX_ROOTS), 1 where absent; the damped FRFs' amplitude
    grids (n_f, frf_points), None without frf_points; both flat, one array): where a response
    program evaluates the damper curve once after the peak search."""
    at_roots = jnp.where(peaks.found, peaks.roots_mm, 1.0)
    grids = (jax.vmap(lambda t: frf_amplitude_grid(t, frf_points))(_frf_tops(mode, forces, peaks))
             if frf_points else None)
    parts = [at_roots] if grids is None else [at_roots, grids]
    return at_roots, grids, jnp.concatenate([a.reshape(-1) for a in parts])


def _at_roots_and_grids(peaks: Peaks, damper: DamperStiffness, mode: BladeMode, at_roots, grids,
                        k_re, k_im):
    """(the peaks with their frequencies, the damped FRFs' (amplitudes, k_re, k_im) or None
    without grids) from the curve's values (k_re, k_im) on `_root_and_frf_amplitudes`' flat
    array."""
    n = at_roots.size
    at = damper._replace(k_of_psi=lambda _: (k_re[:n].reshape(at_roots.shape),
                                             k_im[:n].reshape(at_roots.shape)))
    freqs = jnp.where(peaks.found, peak_frequency_hz(at, mode, at_roots), 0.0)
    on_grids = (None if grids is None
                else (grids, k_re[n:].reshape(grids.shape), k_im[n:].reshape(grids.shape)))
    return peaks._replace(frequency_hz=freqs, peak_frequency_hz=freqs[:, 0]), on_grids


def _frf_tops(mode: BladeMode, forces, peaks: Peaks):
    """Where each force's damped FRF ends: its largest root, or F / (eta k_b) (at most 1e6 mm)
    where the damper is not valid."""
    valid = RESULTS.valid(peaks.status) & (peaks.max_amplitude_mm > 0)
    free_top = forces / jnp.maximum(mode.eta * mode.k_b, 1e-300)
    return jnp.where(valid, peaks.max_amplitude_mm, jnp.minimum(free_top, 1e6))


def _curves(d: DamperStiffness, mode: BladeMode, forces, peaks: Peaks,
            on_grids) -> ResponseCurves:
    """The three FRFs around the peaks of every force: the damped one up to `_frf_tops`, the
    free and stuck ones across their own. on_grids: (amplitudes, k_re, k_im), (n_f, n) each, the
    damped FRFs' amplitudes and the curve there, computed already (`_at_roots_and_grids`)."""
    def tabulated(f, a, k_re, k_im):  # the curve's values at exactly these amplitudes
        return frf(d._replace(k_of_psi=lambda _: (k_re, k_im)), mode, f, a)

    damped = jax.vmap(tabulated)(forces, *on_grids)
    free = jax.vmap(lambda f: linear_frf(mode, 0.0, f))(forces)
    stuck = jax.vmap(lambda f: linear_frf(mode, d.k_re_stuck, f))(forces)
    return ResponseCurves(peaks, damped, free, stuck, d.status, d.k_re_stuck)


# The cycles' loops on a platform path: values only, so while loops (measured on the row's
# elliptic program of two engine orders: trace 55 s and run 0.08 s, against 35 s and 0.57 s with
# masked scans; the CLI saves the traced program, so a repeat pays only the run).
PATH_LOOP = "while"
# The cycles' bound on periods (pairs of halves on straight paths): while loops, so only a lane
# that needs them pays. A path may settle slowly (the out-of-phase path near gross slip: 21
# pairs), beyond the kernels' default bounds (12 pairs, 16 periods).
PATH_REPEATS = 64


def path_peaks(shape, mu, contacts, load, mode: BladeMode, motion, force_n,
               initial: str = "assembly", frf_points: int = 0, residual=None,
               search_width: int = GRID_CHUNK, base=None):
    """(the damper on the path, its peaks at force_n (1-D), and with frf_points > 0 the damped
    FRFs' (amplitudes, k_re, k_im), (n_f, frf_points) each): `path_damper` (values only: while
    loops) and `peak_response`; then one batch of steady cycles at every root (the peaks'
    frequencies) and on the FRF grids, one copy of the cycle in the program instead of one per
    use. The cycle at each peak overrides a valid peak's status where it says more: a pad that
    opens there on a straight path (liftoff), a damper unseated on an ellipse, a cycle that does
    not settle (the grid may miss these), or a damper that sticks there (shakedown: no
    dissipation). residual: the path's residual flexibility c (mrad per N mm, `modes`; None: the
    program without it): the damper in series with it (`with_residual`; its peaks searched in
    the damper's own amplitude, `series_peaks`), its peaks' psi_a_mrad the damper's own
    amplitude. search_width: the cycles a step of the peak search evaluates
    (`root_search.grid_then_roots`); a caller that vmaps this over many paths passes fewer
    (`row.ROW_SEARCH_WIDTH`); base: `path_damper`'s. Unchecked, traceable (jit, vmap)."""
    damper = path_damper(shape, mu, contacts, load, motion, initial, loop=PATH_LOOP,
                         repeats=PATH_REPEATS, base=base)
    forces = jnp.asarray(force_n, float)

    def cycles(psi):
        return jax.vmap(lambda a: path_cycle_kernel(
            shape, mu, contacts, load, a, motion, initial, PATH_LOOP, PATH_REPEATS))(psi)

    if residual is None:
        peaks = peak_response(damper, mode, forces, differentiable=False, frequencies=False,
                              search_width=search_width)
        at_roots, grids, flat = _root_and_frf_amplitudes(mode, forces, peaks, frf_points)
        k_re, k_im, status = cycles(mode.r * flat)
        peaks, on_grids = _at_roots_and_grids(peaks, damper, mode, at_roots, grids, k_re, k_im)
        at_peak = status[:at_roots.size].reshape(at_roots.shape)[:, 0]
    else:
        peaks, at_peak = series_peaks(damper, mode, forces, residual, cycles, search_width)
        damper, on_grids = with_residual(damper, residual), None
        if frf_points:  # the FRFs' amplitudes are the path's: the series solved at each
            _, grids, _ = _root_and_frf_amplitudes(mode, forces, peaks, frf_points)
            k_re, k_im = damper.k_of_psi(mode.r * grids)
            on_grids = (grids, k_re, k_im)
    told = RESULTS.valid(peaks.status) & (at_peak != RESULTS.ok) & (peaks.psi_a_mrad > 0)
    return damper, peaks._replace(status=jnp.where(told, at_peak, peaks.status)), on_grids


def series_peaks(damper: DamperStiffness, mode: BladeMode, forces, c, cycles,
                 search_width: int = GRID_CHUNK):
    """(Peaks (fields (n_f, ...)), the status of the damper's cycle at each first root (n_f,)) of
    the damper in series with a flexibility c (mrad per N mm) at the forces (1-D), searched in the
    damper's own amplitude psi_d: there the series is explicit, no fixed point to iterate
    (`through_residual`'s, one per amplitude of a search in A). At psi_d the damper's k gives
    the path's amplitude psi = psi_d |1 + c k| (so A = psi / r) and the mode's spring
    k / (1 + c k); the peak equation A (eta k_b + 1e-3 r^2 Im k / (1 + c k)) = F is bracketed on
    `peak_response`'s grid (in psi_d: psi_d <= psi, as |1 + c k| >= 1 for Re k >= 0) and refined
    as its roots are, one cycle per evaluation. Every root is a consistent (A, psi_d), so the
    search needs no uniqueness of the series' fixed point. cycles(psi_d) -> (k_re, k_im, status)
    at each amplitude of a 1-D array: the damper's curve (`damper.values`') with its status,
    evaluated on the grid and in the search in one loop (`root_search.grid_then_roots`), whose
    last evaluation per root gives the peaks' frequencies and statuses: one copy of the cycle in
    the program (three before: the grid, the search and the roots after it); the damper gives
    the grid's scale and its status.
    psi_a_mrad is psi_d at the first root. search_width: the amplitudes a step of the search
    evaluates (`grid_then_roots`' width). Values only; unchecked, traceable (jit, vmap)."""
    r = mode.r

    def series(psi_d, k_re, k_im):  # (A, the spring the mode sees) at the damper's amplitude
        k = k_re + 1j * k_im
        z = 1.0 + c * k
        return psi_d * jnp.abs(z) / r, k / z

    def g0(psi_d):  # (the peak equation's left side at psi_d (N), the cycles there)
        got = tuple(v.reshape(psi_d.shape) for v in cycles(psi_d.reshape(-1)))
        a, k = series(psi_d, *got[:2])
        return a * (mode.eta * mode.k_b + 1e-3 * r ** 2 * jnp.imag(k)), got

    grid = r * _amplitude_grid(damper, mode, forces, N_GRID)
    psi_d, (k_re, k_im, status), found, n_roots = grid_then_roots(
        g0, grid, forces[:, None], MAX_ROOTS, REFINE_STEPS, search_width)
    at = jnp.where(found, psi_d, 1.0)
    a, k = series(at, k_re, k_im)
    roots = jnp.where(found, a, 0.0)
    spring = damper._replace(k_of_psi=lambda _: (jnp.real(k), jnp.imag(k)))
    freqs = jnp.where(found, peak_frequency_hz(spring, mode, jnp.where(found, a, 1.0)), 0.0)
    peaks = _peaks_of(roots, freqs, found, n_roots, jnp.where(found[:, 0], psi_d[:, 0], 0.0),
                      damper.status)
    return peaks, status[:, 0]


@functools.cache
def path_curves_program(initial: str = "assembly"):
    """One compiled program per contact history: (shape, mu, contacts, load, mode, motion,
    forces (n,)) -> ResponseCurves of the damper on a platform path (`path_peaks`), on prepared
    inputs. A straight and an elliptic Motion are different pytrees, so each kind compiles once."""
    def run(shape, mu, contacts, load, mode, motion, forces):
        d, peaks, on_grids = path_peaks(shape, mu, contacts, load, mode, motion, forces, initial,
                                        frf_points=FRF_POINTS)
        return _curves(d, mode, forces, peaks, on_grids)

    return batch_jit(run)


def response_curves(shape, mu=None, contacts=None, load=None, mode: BladeMode | None = None,
                    force_n=(1.0,), method: str = "exact", **options) -> ResponseCurves:
    """Peaks and FRFs (damper, free, stuck) of one design at the forces force_n (N, 1-D): inputs
    checked once here (shape may be a Scene, checked already: `prepare_scene`), then one compiled
    program (`curves_program`)."""
    scene = prepare_scene(shape, mu, contacts, load, mode)
    forces = jnp.asarray(np.atleast_1d(check_values("force_n", force_n)))
    return curves_program(method, tuple(sorted(options.items())))(*scene, forces)


def path_response_curves(shape, mu=None, contacts=None, load=None, mode: BladeMode | None = None,
                         motion=None, force_n=(1.0,), initial: str = "assembly") -> ResponseCurves:
    """Peaks and FRFs (damper, free, stuck) of one design on a platform path: `motion` a
    `jaxdamp.Motion` (`interblade_motion`, `general_motion`; None is the paper's in-phase motion,
    `response_curves`), the mode's r in mrad of the path's parameter per mm of tip (for
    `interblade_motion`, the left-hand blade's platform rotation). initial: "assembly" (default)
    or "gross_slip" (on an ellipse a straight move along its tau = 0 direction to gross slip,
    `jaxdamp.ellipse`). Inputs checked once here, then one compiled program
    (`path_curves_program`). The damper's status and amplitude scale are the in-phase
    Base-Cycle's for the curved-flat damper, the path's gross-slip move's for a wedge
    (`path_damper`; a wedge runs on the path engine in-phase too, motion None)."""
    check_history(initial)
    scene = prepare_scene(shape, mu, contacts, load, mode, wedge_ok=True)
    forces = jnp.asarray(np.atleast_1d(check_values("force_n", force_n)))
    if motion is None:
        if not is_wedge(scene.shape):
            return response_curves(scene, force_n=forces, initial=initial)
        motion = in_phase_motion(float(scene.load.q_star))
    return path_curves_program(initial)(*scene, validate_motion(motion, scene.load), forces)


def design_peaks(shape, mu=None, contacts=None, load=None, mode: BladeMode | None = None,
                 force_n=1.0, method: str = "exact", **options) -> Peaks:
    """`peak_response` of one design, compiled (force_n may be an array: vmapped over it; shape
    may be a Scene, checked already: `prepare_scene`)."""
    shape, mu, contacts, load, mode = prepare_scene(shape, mu, contacts, load, mode)
    force = jnp.asarray(check_values("force_n", force_n))
    run = peak_program(method, tuple(sorted(options.items())))
    if force.ndim == 0:
        return run(shape, mu, contacts, load, mode, force)
    return jax.vmap(run, in_axes=(None, None, None, None, None, 0))(shape, mu, contacts, load,
                                                                    mode, force)

