"""Contact parameters (mu, kn, kt) from measured hysteresis loops, with their uncertainty.

Two kinds of loop, freely mixed: moment loops (psi in mrad, M in N mm; below) and per-contact loops
(one contact's relative displacement d in mm against its tangential or normal force in N, recorded
at a given platform amplitude psi_a; `analyse_contact_loop`). A per-contact loop is compared as the
force against its own displacement on each half: the measured d's turning points mark the
reversals, a sample on a stretch where d decreases is compared with the model half along which the
contact's d decreases, at the same d (the model loop centred on the measured centre), minus a force
offset. The model's d is d_t = T / kt - slip (tangential; T = -kt (gt - slip), so gt = -d_t + const)
or d_n = N / kn (normal), exact and piecewise linear over the steady cycle from `amplitude_kernel`;
forces are in units of F_D in the model and N in the data (times load.F_D).

A measured loop is a series of samples (psi_i in mrad, M_i in N mm), several periods long, sampled
anyhow, with noise and a constant offset in each channel. `analyse_loop` finds its turning points,
its centre psi_c and amplitude psi_a (medians of the per-period extremes), and gives every sample
its *travel phase*: the half it lies on (forward = psi decreasing, the half that starts at the
Base-Cycle's state 0, as in `amplitude.py`) and the fraction u in [0, 1] of that half's travel.

The residual of a sample is the measured moment minus the model's exact steady loop
(`amplitude_kernel` at the measured psi_a, from the chosen history) at the same half and travel
fraction, minus a per-loop moment offset: the loops are compared as functions of the travel phase,
never point to nearest point, so the corners (where a contact starts to slip) count with their
full weight. The psi offset is the measured centre psi_c.

Parameters theta (the solver's unknowns): log mu (one shared, or one per contact), log(kn / K_REF)
and log(kt / K_REF) (shared, per side: R1 | L1 = L2, or per contact), and one moment offset per loop
in units of the data's moment scale. Logs keep mu, kn and kt positive and the problem well scaled.

The solve is optimistix's Levenberg-Marquardt (its QR linear solve; Jacobian columns by forward mode
through the exact cycle's custom JVP). Two stages: plain least squares from a generic start, then a
robust pseudo-Huber loss (residuals rescaled, r * sqrt(2 / (1 + sqrt(1 + (r/delta)^2))), so that
sum of squares = 2 delta^2 sum (sqrt(1 + (r/delta)^2) - 1)) with delta = ROBUST_DELTA times the
residuals' robust standard deviation (1.4826 MAD) after stage one. Outliers then weigh like
|r| instead of r^2.

Uncertainty: the Gauss-Newton covariance s^2 (J^T J)^-1 of the rescaled residuals at the optimum
(J from forward mode, s^2 = sum r^2 / (n - p)), standard errors, correlations, and confidence
intervals (for mu, kn, kt: exp of the log-parameter's interval, so they are asymmetric). A parameter
is reported as NOT IDENTIFIABLE (value null) when the Jacobian has a (near) null direction it takes
part in, or when its interval would span more than a factor MAX_SPAN; the intervals of the others
come from the pseudo-inverse of J^T J without the null directions (nothing held fixed).
"""

from __future__ import annotations

from functools import partial
from statistics import NormalDist
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_range, require_x64
from .amplitude import INITIAL_STATES, amplitude_cycle, amplitude_kernel
from .conventions import travel_mm
from .geometry import CONTACT_NAMES, DamperShape, platform_moment, validate_shape
from .params import Contacts, LoadCase, validate_load
from .status import RESULTS, number_repr, status_repr

__all__ = ["MomentLoop", "ContactLoop", "analyse_contact_loop", "loop_work", "loop_direction_error",
           "MIN_LOOP_AREA", "contact_path", "contact_loop_force",
           "sample_contact_loop", "COMPONENTS", "LoopFit", "FitSpec", "LoopError", "analyse_loop", "fit_loops",
           "loop_model_moment", "sample_loop", "identify", "FitProblem", "fit_problem",
           "fit_residuals", "DEFAULT_START", "GROUPINGS", "K_REF", "MAX_SPAN", "ROBUST_DELTA"]

# Generic start (as `jaxdamp calibrate`'s: a round order of magnitude, not the answer): mu = 0.5,
# kn = 1e4 N/mm, kt = kn / 2.
DEFAULT_START = {"mu": 0.5, "kn": 1.0e4, "kt": 5.0e3}
K_REF = 1.0e4  # N/mm, the stiffness of log-parameter 0
GROUPINGS = {"mu": ("shared", "contact"), "kn": ("shared", "side", "contact"),
             "kt": ("shared", "side", "contact")}
_INDEX = {"shared": (0, 0, 0), "side": (0, 1, 1), "contact": (0, 1, 2)}
_LABELS = {"shared": ("",), "side": ("R1", "L"), "contact": CONTACT_NAMES}
ROBUST_DELTA = 2.0  # pseudo-Huber threshold, in robust standard deviations of the residuals
MAX_SPAN = 4.0  # an interval wider than a factor 4 (hi / lo) is no measurement of the parameter
NULL_RCOND = 1e-7  # singular values below this fraction of the largest: null directions
NULL_LOADING = 0.1  # a parameter with a component above this in a null direction is in it
CONFIDENCE = 0.95
MIN_SAMPLES_PER_HALF = 3
ZONE = 0.25  # samples beyond +-ZONE of the range from its middle lie near a top / bottom


class LoopError(ValueError):
    """A measured loop that cannot be used (one line, says why)."""


class MomentLoop(NamedTuple):
    """A measured moment loop, analysed (numpy arrays, one entry per sample)."""

    psi: np.ndarray  # mrad, as measured
    moment: np.ndarray  # N mm, as measured
    psi_a: float  # mrad, amplitude found from the data
    psi_c: float  # mrad, centre found from the data
    forward: np.ndarray  # bool: the sample lies on the forward half (psi decreasing)
    u: np.ndarray  # travel fraction along its half, in [0, 1] (0 at the half's start)
    periods: int  # closed periods found (pairs of turning points after the first)

    x = property(lambda self: self.psi, doc="the driving channel as measured (psi, mrad)")
    y = property(lambda self: self.moment, doc="the force channel as measured (M, N mm)")


COMPONENTS = ("tangential", "normal")
MAX_DISP_MM = 100.0  # a contact loop's displacement amplitude must lie in (0, 100] mm


class ContactLoop(NamedTuple):
    """A measured per-contact loop, analysed: one contact's relative displacement (mm) against its
    tangential or normal force (N), recorded over a steady cycle driven at platform amplitude psi_a
    (mrad, given: the contact's own displacement amplitude depends on the unknown stiffnesses, so
    it cannot place the loop on the model's cycle). Tangential: disp = the platform's displacement
    relative to the damper along the contact's up-flank tangent (so that force = T rises with it in
    stick: T = kt (disp + const) there); normal: disp = the approach (compression > 0)."""

    disp: np.ndarray  # mm, as measured
    force: np.ndarray  # N, as measured
    psi_a: float  # mrad, the platform amplitude of the test (given)
    disp_a: float  # mm, the displacement amplitude found from the data
    disp_c: float  # mm, its centre found from the data
    forward: np.ndarray  # bool: the sample lies on a half along which disp decreases
    u: np.ndarray  # fraction along its half of the displacement range (for figures only)
    periods: int
    contact: int  # 0 R1, 1 L1, 2 L2
    component: str  # "tangential" | "normal"

    x = property(lambda self: self.disp, doc="the driving channel as measured (disp, mm)")
    y = property(lambda self: self.force, doc="the force channel as measured (N)")


def analyse_contact_loop(disp, force, contact, component: str, psi_a_mrad, name: str = "loop") -> ContactLoop:
    """Turning points, centre and amplitude of a measured contact loop (disp mm, force N) of contact
    `contact` (0-2 or "R1", "L1", "L2"), component "tangential" or "normal", recorded at the
    platform amplitude psi_a_mrad. LoopError (one line) for unusable data, as `analyse_loop`."""
    if isinstance(contact, str):
        if contact.upper() not in CONTACT_NAMES:
            raise LoopError(f"{name}: contact must be one of {', '.join(CONTACT_NAMES)}; got {contact!r}")
        contact = CONTACT_NAMES.index(contact.upper())
    if contact not in (0, 1, 2):
        raise LoopError(f"{name}: contact must be 0, 1, 2 (R1, L1, L2); got {contact!r}")
    if component not in COMPONENTS:
        raise LoopError(f"{name}: component must be tangential or normal; got {component!r}")
    try:
        psi_a = float(psi_a_mrad)
    except (TypeError, ValueError):
        raise LoopError(f"{name}: the platform amplitude psi_a must be a number in (0, 10000] mrad; "
                        f"got {psi_a_mrad!r}") from None
    if not 0.0 < psi_a <= 1e4:
        raise LoopError(f"{name}: the platform amplitude psi_a {psi_a:g} mrad is out of range: must be "
                        "in (0, 10000] mrad")
    lp = analyse_loop(disp, force, name, columns=("disp_mm", "force_n"), unit="mm",
                      max_amplitude=MAX_DISP_MM)
    return ContactLoop(lp.psi, lp.moment, psi_a, lp.psi_a, lp.psi_c, lp.forward, lp.u, lp.periods,
                       int(contact), component)


class FitSpec(NamedTuple):
    """How each contact parameter is shared: mu 'shared' | 'contact'; kn, kt 'shared' | 'side'
    (R1 | L1 = L2) | 'contact'."""

    mu: str = "shared"
    kn: str = "shared"
    kt: str = "shared"

    def sizes(self) -> tuple[int, int, int]:
        return tuple(len(_LABELS[g]) for g in self)

    def names(self) -> list[str]:
        out = []
        for p, g in zip(("mu", "kn", "kt"), self):
            out += [p if not lab else f"{p}_{lab}" for lab in _LABELS[g]]
        return out


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, stop) of the runs of True in mask."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]))


def analyse_loop(psi, moment, name: str = "loop", *, columns=("psi_mrad", "moment_nmm"),
                 unit: str = "mrad", max_amplitude: float = 1e4) -> MomentLoop:
    """Turning points, centre, amplitude and travel phase of a measured (psi, M) series.

    LoopError (a ValueError, one line naming `name`) for: unequal lengths, a NaN or infinity, fewer
    than two points, a constant psi, no closed period (psi must go top-bottom-top or
    bottom-top-bottom), an amplitude outside (0, 1e4] mrad."""
    psi = np.asarray(psi, float).reshape(-1)
    moment = np.asarray(moment, float).reshape(-1)
    if psi.shape != moment.shape:
        raise LoopError(f"{name}: {columns[0]} and {columns[1]} have different lengths ({psi.size}, "
                        f"{moment.size})")
    for label, v in zip(columns, (psi, moment)):
        bad = np.nonzero(~np.isfinite(v))[0]
        if bad.size:
            raise LoopError(f"{name}: {label} is not a finite number at sample {int(bad[0]) + 1} "
                            f"({bad.size} such samples); remove or fill them")
    if psi.size < 2:
        raise LoopError(f"{name}: {psi.size} sample{'s' if psi.size != 1 else ''}; a loop needs "
                        f"at least one closed period of {columns[0]}")
    lo, hi = float(psi.min()), float(psi.max())
    span = hi - lo
    if not span > 1e-12 * max(abs(hi), abs(lo), 1.0):
        raise LoopError(f"{name}: {columns[0]} is constant ({hi:g} {unit}): no loop")
    mid = 0.5 * (hi + lo)
    tops = [(a, b, a + int(np.argmax(psi[a:b]))) for a, b in _runs(psi > mid + ZONE * span)]
    bots = [(a, b, a + int(np.argmin(psi[a:b]))) for a, b in _runs(psi < mid - ZONE * span)]
    turns = sorted([(i, 1, a, b) for a, b, i in tops] + [(i, -1, a, b) for a, b, i in bots])
    # an extreme at the very end of the series may be a cut, not a turning point: keep it only where
    # it reaches the median of the interior ones (within 2 % of the range)
    interior = lambda kind: [psi[i] for i, k, a, b in turns  # noqa: E731
                             if k == kind and 0 < i < psi.size - 1]
    keep = []
    for i, k, a, b in turns:
        if i in (0, psi.size - 1):
            ref = interior(k)
            ref = np.median(ref) if ref else (hi if k > 0 else lo)
            if abs(psi[i] - ref) > 0.02 * span:
                continue
        keep.append((i, k))
    if len(keep) < 3:
        raise LoopError(f"{name}: no closed period: {columns[0]} must run top-bottom-top or "
                        "bottom-top-bottom "
                        f"(found {len(keep)} turning point{'s' if len(keep) != 1 else ''})")
    top = float(np.median([psi[i] for i, k in keep if k > 0]))
    bottom = float(np.median([psi[i] for i, k in keep if k < 0]))
    psi_c, psi_a = 0.5 * (top + bottom), 0.5 * (top - bottom)
    if not 0.0 < psi_a <= max_amplitude:
        raise LoopError(f"{name}: amplitude {psi_a:g} {unit} is out of range: must be in (0, "
                        f"{max_amplitude:g}] {unit}")
    # the half of every sample: between a top and the next bottom psi decreases (forward)
    idx = np.array([i for i, _ in keep])
    kinds = np.array([k for _, k in keep])
    n = psi.size
    pos = np.searchsorted(idx, np.arange(n), side="right")  # turning points at or before sample j
    nxt = np.clip(pos, 0, len(idx) - 1)
    prev = np.clip(pos - 1, 0, len(idx) - 1)
    # after a top (or before the first turning point, when it is a bottom): decreasing
    forward = np.where(pos > 0, kinds[prev] > 0, kinds[nxt] < 0)
    # a turning-point sample itself starts the next half
    x = np.clip((psi - psi_c) / psi_a, -1.0, 1.0)
    u = np.where(forward, 0.5 * (1.0 - x), 0.5 * (1.0 + x))
    half_len = np.diff(idx)
    if np.any(half_len < MIN_SAMPLES_PER_HALF - 1):
        raise LoopError(f"{name}: a half-period has fewer than {MIN_SAMPLES_PER_HALF} samples; "
                        "sample the loop more finely")
    periods = (len(keep) - 1) // 2
    return MomentLoop(psi, moment, psi_a, psi_c, forward.astype(bool), u, periods)


MIN_LOOP_AREA = 0.01  # a loop is checked for its direction where |its area| > 1 % of its box


def loop_work(x, y) -> float:
    """The signed area per period, the integral of y dx around a sampled loop (numpy): the polygon
    through the samples, closed by the chord from the last back to the first (so constant offsets
    in either channel drop out and a partial last period counts with its own orientation), divided
    by the periods travelled, sum |dx| / (2 range(x)): exact (to the trapezoids) over whole
    periods, approximate where the series ends part-way through one. For a moment loop (psi mrad, M N mm) this
    is the energy dissipated per cycle in N mm mrad (times 1e-3: N mm), positive under the
    conventions (`conventions.py`: the integral of M dpsi is the energy dissipated); for a
    tangential contact loop (disp mm, T N) the friction energy dissipated at that contact, N mm,
    positive too (the integral of T dd_t is minus that of T dslip, and T never pushes its slip)."""
    x = np.asarray(x, float).reshape(-1)
    y = np.asarray(y, float).reshape(-1)
    if x.size < 2 or x.shape != y.shape or not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        return 0.0
    xc, yc = np.append(x, x[0]), np.append(y, y[0])
    area = float(np.sum(0.5 * (yc[1:] + yc[:-1]) * np.diff(xc)))
    span = float(np.ptp(x))
    periods = float(np.sum(np.abs(np.diff(x)))) / (2.0 * span) if span > 0 else 0.0
    return area / periods if periods > 0 else 0.0


def loop_direction_error(loop, name: str = "loop") -> str | None:
    """None where an analysed loop (MomentLoop or ContactLoop) runs the way the conventions say,
    else one line saying that it encloses negative energy. Checked: moment loops and tangential
    contact loops, where the enclosed area is the energy dissipated and so positive; not normal
    contact loops (elastic: they enclose no energy, the sign of their area is noise), nor a loop
    whose area is within MIN_LOOP_AREA of its bounding box (nearly elastic: the sign is not
    measurable). Numpy only, no JAX: callers check before any fitting."""
    if isinstance(loop, ContactLoop) and loop.component != "tangential":
        return None
    w = loop_work(loop.x, loop.y)
    box = float(np.ptp(loop.x)) * float(np.ptp(loop.y))
    if not (box > 0 and w < -MIN_LOOP_AREA * box):
        return None
    if isinstance(loop, ContactLoop):
        return (f"{name}: the loop encloses negative energy under the convention (the integral of "
                f"T d(disp) = {w:.4g} N mm per cycle; it is the friction energy dissipated at "
                f"{CONTACT_NAMES[loop.contact]}, positive): the force or the displacement has the "
                "opposite sign; negate the force")
    return (f"{name}: the loop encloses negative energy under the convention (the integral of "
            f"M dpsi = {w * 1e-3:.4g} N mm per cycle; it is the energy dissipated, positive): the "
            "moment or psi has the opposite sign; negate the moment")


# ---------------------------------------------------------------- the model side (pure JAX)
def loop_model_moment(ac, forward, u):
    """The moment (N mm) of an AmplitudeCycle's steady loop at travel phase (forward, u): u in
    [0, 1] the fraction of the half's travel 2 psi_a q* / 1e3 (mm) from the half's start. The loop is
    piecewise linear in travel, so this is exact; differentiable in every input of the cycle."""
    travel = 2.0 * travel_mm(ac.psi_a, ac.load.q_star)
    t = u * travel

    def on(half, t):
        m0 = platform_moment(ac.shape, ac.load, half.N0, half.T0)
        dm = platform_moment(ac.shape, ac.load, half.dN, half.dT)
        dv = jnp.where(half.active, half.dv, 0.0)
        start = jnp.cumsum(dv) - dv
        # tract j holds t when start_j <= t (the last active one that does)
        j = jnp.sum((start[None, :] <= t[:, None]) & half.active[None, :], axis=1) - 1
        j = jnp.clip(j, 0, dv.shape[0] - 1)
        return m0[j] + dm[j] * (t - start[j])

    return jnp.where(forward, on(ac.forward, t), on(ac.backward, t))


# ---------------------------------------------------------------- per-contact loops (pure JAX)
def _half_states(half, kt_i, kn_i, i, s_start):
    """Contact i at the vertices of a half (its start, every tract start, its end): (d_t, d_n, T, N,
    slip at the end). d_t = T / kt - slip (mm: the platform's tangential displacement relative to
    the damper at the contact, T = -kt (gt - slip) with gt = -d_t + const), d_n = N / kn (mm, the
    normal approach); forces in units of F_D; s_start the slip at the half's start (mm)."""
    dv = jnp.where(half.active, half.dv, 0.0)
    start = jnp.cumsum(dv) - dv
    t = jnp.concatenate([start, jnp.sum(dv)[None]])
    j = jnp.sum((start[None, :] <= t[:, None]) & half.active[None, :], axis=1) - 1
    j = jnp.clip(j, 0, dv.shape[0] - 1)
    h = t - start[j]
    T = half.T0[j, i] + half.dT[j, i] * h
    N = half.N0[j, i] + half.dN[j, i] * h
    ds = jnp.where(half.active, half.dslip[:, i], 0.0) * dv
    s = s_start + (jnp.cumsum(ds) - ds)[j] + half.dslip[j, i] * h
    return T / kt_i - s, N / kn_i, T, N, s[-1], half.active


def contact_path(ac, i, normal):
    """Contact i's (displacement mm, force in units of F_D) at the vertices of each half of an
    AmplitudeCycle's steady loop: ((d_fwd, f_fwd), (d_bwd, f_bwd), active tracts fwd, bwd), with
    d the tangential d_t = T / kt - slip or (normal) d_n = N / kn; exact (piecewise linear between
    the vertices in the travel, hence in d)."""
    kt_i = ac.contacts.kt[i] / ac.load.F_D if jnp.ndim(ac.contacts.kt) else ac.contacts.kt / ac.load.F_D
    kn_i = ac.contacts.kn[i] / ac.load.F_D if jnp.ndim(ac.contacts.kn) else ac.contacts.kn / ac.load.F_D
    dtf, dnf, Tf, Nf, sf, af = _half_states(ac.forward, kt_i, kn_i, i, 0.0)
    dtb, dnb, Tb, Nb, _, ab = _half_states(ac.backward, kt_i, kn_i, i, sf)
    pick = lambda a, b: jnp.where(normal, a, b)  # noqa: E731
    return (pick(dnf, dtf), pick(Nf, Tf)), (pick(dnb, dtb), pick(Nb, Tb)), af, ab


def _safe_div(a, b):
    ok = b != 0.0
    return jnp.where(ok, a / jnp.where(ok, b, 1.0), 0.0)


def _force_at(d, f, active, xq):
    """f at displacement xq along one half's vertices (d, f): piecewise linear; the segment is the
    last non-degenerate one starting at or before xq in the half's direction (the first one before
    the start, the last one carried on past the end)."""
    sgn = jnp.where(d[-1] >= d[0], 1.0, -1.0)
    z = sgn * d
    zq = sgn * xq
    dz = z[1:] - z[:-1]
    tol = 1e-12 * (jnp.max(jnp.abs(d)) + 1e-300)
    valid = active & (dz > tol)
    k = jnp.arange(dz.shape[0])
    cand = valid[None, :] & (z[None, :-1] <= zq[:, None])
    first = jnp.argmax(valid)
    kk = jnp.max(jnp.where(cand, k[None, :], -1), axis=1)
    kk = jnp.where(kk < 0, first, kk)
    slope = _safe_div(f[1:] - f[:-1], dz)
    return f[kk] + slope[kk] * (zq - z[kk])


def contact_loop_force(ac, i, normal, decreasing, x):
    """The model force (units of F_D) of contact i (tangential, or normal where `normal`) at the
    measured displacement x (mm, relative to the loop's centre: 0.5 (max + min) of the model's d
    over the cycle) on the half along which d decreases (`decreasing`) or increases. Exact,
    differentiable. Also returns whether d is monotone along both halves (else a force is not a
    function of d on a half, and the loop cannot be compared this way)."""
    (df, ff), (db, fb), af, ab = contact_path(ac, i, normal)
    allv = jnp.concatenate([df, db])
    centre = 0.5 * (jnp.max(allv) + jnp.min(allv))
    xq = x + centre
    fwd_dec = df[-1] < df[0]
    use_fwd = decreasing == fwd_dec
    F = jnp.where(use_fwd, _force_at(df, ff, af, xq), _force_at(db, fb, ab, xq))

    def mono(d, a):
        s = jnp.where(d[-1] >= d[0], 1.0, -1.0)
        dz = s * (d[1:] - d[:-1])
        return jnp.all(~a | (dz >= -1e-9 * (jnp.max(allv) - jnp.min(allv) + 1e-300)))

    return F, mono(df, af) & mono(db, ab)


def _expand(theta, spec: FitSpec):
    """(mu, kn (3,), kt (3,), offsets) from the parameter vector."""
    n_mu, n_kn, n_kt = spec.sizes()
    lmu = theta[:n_mu]
    lkn = theta[n_mu:n_mu + n_kn]
    lkt = theta[n_mu + n_kn:n_mu + n_kn + n_kt]
    mu = jnp.exp(lmu)[0] if spec.mu == "shared" else jnp.exp(lmu)
    kn = K_REF * jnp.exp(lkn[jnp.asarray(_INDEX[spec.kn])])
    kt = K_REF * jnp.exp(lkt[jnp.asarray(_INDEX[spec.kt])])
    return mu, kn, kt, theta[n_mu + n_kn + n_kt:]


class _Data(NamedTuple):
    """The loops stacked and padded (loops, samples)."""

    psi_a: jnp.ndarray  # (L,)
    forward: jnp.ndarray  # (L, n) bool
    u: jnp.ndarray  # (L, n)
    moment: jnp.ndarray  # (L, n), in units of scale
    mask: jnp.ndarray  # (L, n) 1.0 for a sample, 0.0 for padding
    scale: jnp.ndarray  # (L,) each loop's force scale (N mm for moment loops, N for contact loops)
    kind: jnp.ndarray  # (L,) int: 0 moment loop, 1 tangential contact loop, 2 normal contact loop
    contact: jnp.ndarray  # (L,) int: the contact of a contact loop (0 R1, 1 L1, 2 L2)
    x: jnp.ndarray  # (L, n) contact loops: displacement from the measured centre, mm


def _model(theta, shape, load, data: _Data, spec: FitSpec, history: str):
    """(model moment or contact force (L, n) in units of each loop's scale, offsets, cycle statuses
    (L,), per loop: False for a tangential contact loop whose model displacement is not monotone
    along a half (then its force is not a function of the displacement there))."""
    mu, kn, kt, off = _expand(theta, spec)
    contacts = Contacts(kn, kt)

    def one(psi_a, fwd, u, kind, contact, x):
        ac = amplitude_kernel(shape, mu, contacts, load, psi_a, initial=history)
        m = loop_model_moment(ac, fwd, u)
        # contact loops: `forward` holds "the measured displacement decreases on this half"
        f, mono = contact_loop_force(ac, contact, kind == 2, fwd, x)
        return jnp.where(kind == 0, m, f * load.F_D), ac.status, mono | (kind != 1)

    m, status, mono = jax.vmap(one)(data.psi_a, data.forward, data.u, data.kind, data.contact, data.x)
    return m / data.scale[:, None], off, status, mono


_model_jit = jax.jit(_model, static_argnames=("spec", "history"))


def fit_residuals(theta, shape, load, data: _Data, spec: FitSpec, history: str, inv_delta):
    """Residuals (flattened, padding zero) in units of the moment scale, pseudo-Huber rescaled
    where inv_delta > 0 (1 / delta; 0: plain least squares)."""
    m, off, _, _ = _model(theta, shape, load, data, spec, history)
    r = (data.moment - m - off[:, None]) * data.mask
    z = r * inv_delta
    return (r * jnp.sqrt(2.0 / (1.0 + jnp.sqrt(1.0 + z * z)))).reshape(-1)


_LISTENERS: list = []  # the running fit's step callback (one compiled program for every caller)


def _report(step, loss, step_size):
    for f in _LISTENERS[-1:]:
        f(step, loss, step_size)


def _verbose(**kw):
    jax.debug.callback(_report, kw["num_steps"][1], kw["loss_last_accepted_step"][1],
                       kw["step_size"][1])


@partial(jax.jit, static_argnames=("spec", "history", "max_steps", "rtol"))
def _solve(theta0, shape, load, data, inv_delta, *, spec, history, max_steps, rtol):
    # Imported here, not with the module: optimistix (with equinox) adds 1-2 s to every
    # `import jaxdamp` (measured 2026-11-25), and only the loop fit uses it.
    import optimistix as optx

    def fn(theta, args):
        return fit_residuals(theta, shape, load, data, spec, history, inv_delta)

    verbose = _verbose
    solver = optx.LevenbergMarquardt(rtol=rtol, atol=rtol * 1e-3, verbose=verbose)
    sol = optx.least_squares(fn, solver, theta0, max_steps=max_steps, throw=False)
    r = fn(sol.value, None)
    jac = jax.jacfwd(fn)(sol.value, None)
    _, _, status, _ = _model(sol.value, shape, load, data, spec, history)
    return sol.value, r, jac, sol.result == optx.RESULTS.successful, sol.stats["num_steps"], status


class LoopFit(NamedTuple):
    """The fitted contact parameters and their uncertainty (`fit_loops`).

    names: the parameters (mu, kn, kt per their grouping, then offset_0...); value, se, lo, hi:
    per parameter, NaN where not identifiable (mu dimensionless, kn, kt in N/mm, offsets in N mm;
    lo, hi: the CONFIDENCE interval); correlation: (p, p), NaN rows for the unidentified ones.
    identifiable: bool per parameter; why: per parameter, "" or the reason it is not identifiable.
    mu, kn, kt: the fitted values as the solver takes them (mu a number or (3,), kn, kt (3,) N/mm),
    including unidentified ones at the value the solver ended on (to run the model, not as results).
    """

    names: list
    value: np.ndarray
    se: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    correlation: np.ndarray
    identifiable: np.ndarray
    why: list
    mu: object
    kn: np.ndarray
    kt: np.ndarray
    offsets: np.ndarray  # per loop: N mm (moment loop) or N (contact loop)
    sigma: float  # residual standard deviation (robust stage, rescaled residuals), N mm or N; NaN
    # where moment and contact loops are fitted together (no common unit)
    rms: np.ndarray  # per loop, plain rms residual at the optimum (N mm or N)
    loops: list  # the MomentLoop or ContactLoop of each input
    fitted: list  # per loop, the model moment (N mm) or force (N), offset included, at each sample
    statuses: np.ndarray  # RESULTS code of each loop's model cycle at the optimum
    converged: bool
    steps: list  # LM steps per stage
    history: list  # (stage, step, loss) as the solver went
    spec: FitSpec
    initial: str
    status: int  # RESULTS code: ok, not_converged, liftoff, ... (the worst)
    held: list  # the names not identified (their values are where the solver ended, no result)
    monotone: np.ndarray  # per loop: False for a tangential contact loop whose model displacement
    # is not monotone along a half at the optimum (its force is then not a function of it there)

    def __repr__(self) -> str:
        """One or two lines: status by name, each contact parameter with its unit and standard
        error (or 'not identifiable'), the residual sd, the loops and whether the solve converged."""
        try:
            parts = []
            for n, v, se, ok in zip(self.names, np.asarray(self.value, float), np.asarray(self.se, float),
                                    np.asarray(self.identifiable, bool)):
                if n.startswith("offset"):
                    continue
                unit = "" if n.startswith("mu") else " N/mm"
                parts.append(f"{n}={v:.5g} ± {se:.2g}{unit}" if ok else f"{n}=not identifiable")
            loops = list(self.loops)
            unit = "N mm" if all(isinstance(lp, MomentLoop) for lp in loops) else "N"
            mixed = not loops or not np.isfinite(float(self.sigma))  # moment and contact loops: no sd
            tail = (f"sigma={number_repr(self.sigma, '' if mixed else unit)}, loops={len(loops)}, "
                    f"converged={bool(np.asarray(self.converged))}")
            body = ", ".join(parts + [tail])
        except Exception:  # noqa: BLE001 - a repr must not raise (a hand-built or traced LoopFit)
            body = "<unavailable>"
        return f"LoopFit(status={status_repr(self.status)}, {body})"

    def as_dict(self) -> dict:
        """Plain-Python view (floats, lists; None where a number does not exist)."""
        f = lambda v: None if v is None or not np.isfinite(v) else float(v)  # noqa: E731
        params = {}
        for i, n in enumerate(self.names):
            params[n] = {"value": f(self.value[i]), "se": f(self.se[i]), "lo": f(self.lo[i]),
                         "hi": f(self.hi[i]), "identifiable": bool(self.identifiable[i]),
                         "why": self.why[i] or None}
        return {"parameters": params, "correlation": [[f(v) for v in row] for row in self.correlation],
                "sigma_nmm": f(self.sigma), "rms_nmm": [f(v) for v in self.rms],
                "converged": self.converged, "steps": self.steps,
                "status": RESULTS.name_of(self.status)}


def _robust_sd(r):
    r = np.asarray(r)
    return float(1.4826 * np.median(np.abs(r - np.median(r))))


def _pad(n: int) -> int:
    return max(512, 1 << int(np.ceil(np.log2(max(n, 1)))))


def _stack(loops: list, scale) -> _Data:
    n = _pad(max(lp.x.size for lp in loops))
    L = len(loops)
    fwd, u, m, mask, x = (np.zeros((L, n), bool), np.zeros((L, n)), np.zeros((L, n)), np.zeros((L, n)),
                          np.zeros((L, n)))
    kind, contact = np.zeros(L, np.int32), np.zeros(L, np.int32)
    scale = np.broadcast_to(np.asarray(scale, float), (L,))
    for i, lp in enumerate(loops):
        k = lp.x.size
        fwd[i, :k], u[i, :k], m[i, :k], mask[i, :k] = lp.forward, lp.u, lp.y / scale[i], 1.0
        if isinstance(lp, ContactLoop):
            kind[i] = 1 + COMPONENTS.index(lp.component)
            contact[i] = lp.contact
            x[i, :k] = lp.disp - lp.disp_c
    return _Data(jnp.asarray([lp.psi_a for lp in loops]), jnp.asarray(fwd), jnp.asarray(u),
                 jnp.asarray(m), jnp.asarray(mask), jnp.asarray(scale), jnp.asarray(kind),
                 jnp.asarray(contact), jnp.asarray(x))


def identify(jac, sigma2, names, n_phys):
    """(identifiable (p,) bool, why (p,) reasons, covariance (p, p), NaN for the unidentified) from
    the residuals' Jacobian (n, p) at the optimum and the residual variance sigma2. The first n_phys
    parameters are logs (their interval spans exp(2 z se)). A parameter with a component above
    NULL_LOADING in a direction whose singular value is below NULL_RCOND of the largest is not
    identifiable, nor is a log-parameter whose interval would span more than MAX_SPAN. The
    covariance is sigma2 (J^T J)^+ (pseudo-inverse with the null directions cut): for a parameter
    outside the null directions it is its full variance, the weakly determined directions
    included; nothing is held fixed."""
    p = jac.shape[1]
    ok = np.ones(p, bool)
    why = [""] * p
    _, s, vt = np.linalg.svd(jac, full_matrices=False)
    if not s[0] > 0.0:
        return ok & False, ["not identifiable: the loops carry no information on it (zero Jacobian)"] * p, \
            np.full((p, p), np.nan)
    for k in np.nonzero(s < NULL_RCOND * s[0])[0]:
        involved = np.nonzero(np.abs(vt[k]) > NULL_LOADING)[0]
        for j in involved:
            if ok[j]:
                others = [names[i] for i in involved if i != j]
                why[j] = ("not identifiable: the loops constrain only a combination of it"
                          + (f" with {', '.join(others)}" if others else " (it does not change them)")
                          + " (a null direction of the Jacobian)")
            ok[j] = False
    keep = s >= NULL_RCOND * s[0]
    vk = vt[keep]
    cov = sigma2 * (vk.T / s[keep] ** 2) @ vk
    se = np.sqrt(np.maximum(np.diag(cov), 0.0))
    z = _z()
    for j in range(min(n_phys, p)):
        span = float(np.exp(min(2 * z * se[j], 700.0)))
        if ok[j] and span > MAX_SPAN:
            why[j] = (f"not identifiable from these loops: its {CONFIDENCE:.0%} interval would span a "
                      f"factor {span:.3g} (more than {MAX_SPAN:g})")
            ok[j] = False
    cov[~ok, :] = np.nan
    cov[:, ~ok] = np.nan
    return ok, why, cov


def _z() -> float:
    return NormalDist().inv_cdf(0.5 + CONFIDENCE / 2)


class FitProblem(NamedTuple):
    """The least-squares problem of `fit_loops`, for your own solver: residuals(theta, inv_delta)
    (jit-compiled; flattened, padding zero, units of `scale`; inv_delta = 0 plain least squares, else
    1 / the pseudo-Huber threshold) from theta0 (the generic start, offsets from the data)."""

    residuals: Callable
    theta0: np.ndarray
    names: list
    scale: np.ndarray  # (L,) per loop: N mm or N
    loops: list
    spec: FitSpec
    n_phys: int
    data: object
    shape: DamperShape
    load: LoadCase
    initial: str
    loss0: float  # 0.5 sum r^2 at theta0 (plain)


def fit_problem(loops, shape: DamperShape, *, load: LoadCase = LoadCase(), initial: str = "gross_slip",
                mu: str = "shared", kn: str = "shared", kt: str = "shared", start: dict | None = None,
                names=None) -> FitProblem:
    """The checked, analysed and stacked problem that `fit_loops` solves (same arguments)."""
    require_x64()
    validate_shape(shape)
    validate_load(load)
    if initial not in INITIAL_STATES:
        raise ValueError(f"initial must be one of {', '.join(INITIAL_STATES)}; got {initial!r}")
    for key, g in (("mu", mu), ("kn", kn), ("kt", kt)):
        if g not in GROUPINGS[key]:
            raise ValueError(f"{key} grouping must be one of {', '.join(GROUPINGS[key])}; got {g!r}")
    st = dict(DEFAULT_START, **(start or {}))
    check_range("mu", st["mu"], 0.0, 5.0, lo_open=True)
    check_range("kn", st["kn"], 0.0, 1e12, lo_open=True, unit="N/mm")
    check_range("kt", st["kt"], 0.0, 1e12, lo_open=True, unit="N/mm")
    loops = list(loops)
    if not loops:
        raise ValueError("loops must hold at least one (psi_mrad, moment_nmm) loop")
    names = names or [f"loop {i + 1}" for i in range(len(loops))]
    loops = [lp if isinstance(lp, (MomentLoop, ContactLoop)) else analyse_loop(*lp, name=nm)
             for lp, nm in zip(loops, names)]
    for lp in loops:
        check_range("psi_a_mrad", lp.psi_a, 0.0, 1e4, lo_open=True, unit="mrad")
    spec = FitSpec(mu, kn, kt)
    n_mu, n_kn, n_kt = spec.sizes()
    n_phys = n_mu + n_kn + n_kt
    # one residual scale per unit (N mm for moment loops, N for contact loops): half the largest
    # range of the loops in that unit
    group = lambda lp: isinstance(lp, ContactLoop)  # noqa: E731
    gscale = {g: max(float(np.ptp(lp.y)) for lp in loops if group(lp) == g) / 2.0 or 1.0
              for g in {group(lp) for lp in loops}}
    scale = np.array([gscale[group(lp)] for lp in loops])
    data = _stack(loops, scale)
    shape_j = DamperShape(*(None if v is None else jnp.asarray(v, float) for v in shape))
    load_j = LoadCase(*(jnp.asarray(v, float) for v in load))
    theta = np.concatenate([np.full(n_mu, np.log(st["mu"])), np.full(n_kn, np.log(st["kn"] / K_REF)),
                            np.full(n_kt, np.log(st["kt"] / K_REF)), np.zeros(len(loops))])
    # start offsets: the mean gap between the measured loop and the model at the start
    m0, _, _, _ = _model_jit(jnp.asarray(theta), shape_j, load_j, data, spec, initial)
    gap = np.asarray(jnp.sum((data.moment - m0) * data.mask, axis=1) / jnp.sum(data.mask, axis=1))
    theta[n_phys:] = gap
    r0 = (data.moment - m0 - jnp.asarray(gap)[:, None]) * data.mask
    loss0 = float(0.5 * jnp.sum(r0 * r0))
    pnames = spec.names() + [f"offset_{i}" for i in range(len(loops))]
    res = jax.jit(lambda th, inv_delta: fit_residuals(th, shape_j, load_j, data, spec, initial,
                                                      inv_delta))
    return FitProblem(res, theta, pnames, scale, loops, spec, n_phys, data, shape_j, load_j, initial,
                      loss0)


def fit_loops(loops, shape: DamperShape, *, load: LoadCase = LoadCase(), initial: str = "gross_slip",
              mu: str = "shared", kn: str = "shared", kt: str = "shared", start: dict | None = None,
              robust: bool = True, max_steps: int = 100, rtol: float = 1e-6,
              callback: Callable | None = None, names=None) -> LoopFit:
    """Fit mu, kn, kt (and one moment offset per loop) to measured moment loops.

    loops: a list of (psi_mrad, moment_nmm) pairs of 1-D arrays (each several periods, any
    sampling) or of MomentLoop; shape: the damper's DamperShape; load: F_D, q*, r sin(beta) of the
    test. initial: the history of the model's steady cycle, "gross_slip" or "assembly". mu: "shared"
    or "contact"; kn, kt: "shared", "side" (R1 | L1 = L2) or "contact". start: {"mu", "kn", "kt"}
    (numbers; default DEFAULT_START, a generic guess). robust: a second, pseudo-Huber stage.
    callback(stage, step, loss): called as the solver goes (from the compiled solve).

    Returns a LoopFit: values, standard errors, CONFIDENCE intervals, correlations, and which
    parameters the loops do not identify (NaN values, with the reason). Loops that cannot be used
    raise LoopError (a ValueError) naming the loop.
    """
    if not isinstance(max_steps, int) or max_steps < 1:
        raise ValueError(f"max_steps must be an integer >= 1; got {max_steps!r}")
    prob = fit_problem(loops, shape, load=load, initial=initial, mu=mu, kn=kn, kt=kt, start=start,
                       names=names)
    spec, n_phys, data, scale, theta = prob.spec, prob.n_phys, prob.data, prob.scale, prob.theta0
    shape_j, load_j, loops = prob.shape, prob.load, prob.loops
    n_mu = spec.sizes()[0]
    history, steps = [], []
    stage_box = [0]

    def cb(step, loss, step_size):
        if int(step) == 0:  # optimistix reports no loss before its first step
            return
        history.append((stage_box[0], int(step), float(loss)))
        if callback is not None:
            callback(stage_box[0], int(step), float(loss))

    kw = dict(spec=spec, history=initial, max_steps=max_steps, rtol=rtol)
    history.append((0, 0, prob.loss0))  # the generic start
    if callback is not None:
        callback(0, 0, prob.loss0)
    _LISTENERS.append(cb)
    try:
        theta, r, jac, ok, nsteps, status = _solve(jnp.asarray(theta), shape_j, load_j, data,
                                                   jnp.asarray(0.0), **kw)
        steps.append(int(nsteps))
        converged = bool(ok)
        mask = np.asarray(data.mask).reshape(-1) > 0
        if robust:
            delta = ROBUST_DELTA * max(_robust_sd(np.asarray(r)[mask]), 1e-12)
            stage_box[0] = 1
            theta, r, jac, ok, nsteps, status = _solve(theta, shape_j, load_j, data,
                                                       jnp.asarray(1.0 / delta), **kw)
            steps.append(int(nsteps))
            converged = bool(ok)
        jax.effects_barrier()
        history.sort()  # (stage, step): debug callbacks may arrive out of order
    finally:
        _LISTENERS.remove(cb)
    theta, r, jac = np.asarray(theta), np.asarray(r)[mask], np.asarray(jac)[mask]
    n, p = r.size, theta.size
    dof = max(n - p, 1)
    sigma2 = float(np.sum(r ** 2) / dof)
    pnames = prob.names
    ident, why, cov = identify(jac, sigma2, pnames, n_phys)
    se_t = np.sqrt(np.maximum(np.diag(cov), 0.0))
    z = _z()
    value = np.concatenate([np.exp(theta[:n_mu]), K_REF * np.exp(theta[n_mu:n_phys]),
                            theta[n_phys:] * scale])
    se = np.concatenate([value[:n_phys] * se_t[:n_phys], se_t[n_phys:] * scale])
    lo = np.concatenate([value[:n_phys] * np.exp(-z * se_t[:n_phys]), value[n_phys:] - z * se[n_phys:]])
    hi = np.concatenate([value[:n_phys] * np.exp(z * se_t[:n_phys]), value[n_phys:] + z * se[n_phys:]])
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    for a in (value, se, lo, hi):
        a[~ident] = np.nan
    mu_v, kn_v, kt_v, _ = (np.asarray(v) for v in _expand(jnp.asarray(theta), spec))
    m_fit, off, cyc_status, mono = _model_jit(jnp.asarray(theta), shape_j, load_j, data, spec, initial)
    fitted = np.asarray((m_fit + off[:, None]) * scale[:, None])
    fitted_list = [fitted[i, :lp.x.size] for i, lp in enumerate(loops)]
    rms = np.array([float(np.sqrt(np.mean((lp.y - f) ** 2))) for lp, f in zip(loops, fitted_list)])
    # one residual sd where all loops share a unit (N mm or N); mixed units have none (see rms)
    sigma = float(np.sqrt(sigma2) * scale[0]) if np.all(scale == scale[0]) else float("nan")
    cyc_status = np.asarray(cyc_status)
    worst = RESULTS.ok
    for s in cyc_status:
        if not RESULTS.valid(int(s)):
            worst = int(s)
    if worst == RESULTS.ok and not converged:
        worst = RESULTS.not_converged
    held = [nm for nm, k in zip(pnames, ident) if not k]
    return LoopFit(pnames, value, se, lo, hi, corr, ident, why,
                   float(mu_v) if mu_v.ndim == 0 else mu_v, kn_v, kt_v, value[n_phys:] if np.all(
                       ident[n_phys:]) else theta[n_phys:] * scale, sigma,
                   rms, loops, fitted_list, cyc_status, converged, steps, history, spec, initial,
                   int(worst), held, np.asarray(mono, bool))


def sample_loop(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                load: LoadCase = LoadCase(), *, t, initial: str = "gross_slip"):
    """(psi, M) of the model's exact steady loop sampled at times t (periods) of psi = psi_a cos(2 pi
    t): psi in mrad, M in N mm (numpy). A test loop for `fit_loops` (add noise and offsets)."""
    t = np.asarray(t, float)
    ac = amplitude_cycle(shape, mu, psi_a_mrad, contacts, load, initial=initial)
    phase = np.mod(t, 1.0)
    forward = phase < 0.5  # psi decreasing from the top
    x = np.cos(2.0 * np.pi * t)
    u = np.where(forward, 0.5 * (1.0 - x), 0.5 * (1.0 + x))
    m = loop_model_moment(ac, jnp.asarray(forward), jnp.asarray(u))
    return float(psi_a_mrad) * x, np.asarray(m)


def sample_contact_loop(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                        load: LoadCase = LoadCase(), *, contact, component: str, t,
                        initial: str = "gross_slip"):
    """(disp in mm, force in N) of contact `contact` (0-2) of the model's exact steady loop at
    platform amplitude psi_a_mrad, sampled at times t (periods) of psi = psi_a cos(2 pi t): a test
    loop for `fit_loops` (add noise and offsets; centre: disp at the forward extreme is the model's
    d there, forward half first). Evaluated along the travel, tract by tract (numpy), not through
    the displacement inversion the fit uses."""
    if component not in COMPONENTS:
        raise ValueError(f"component must be tangential or normal; got {component!r}")
    t = np.asarray(t, float)
    ac = amplitude_cycle(shape, mu, psi_a_mrad, contacts, load, initial=initial)
    F_D = float(load.F_D)
    kt = float(np.broadcast_to(np.asarray(contacts.kt, float), (3,))[contact]) / F_D
    kn = float(np.broadcast_to(np.asarray(contacts.kn, float), (3,))[contact]) / F_D
    travel = 2.0 * float(travel_mm(psi_a_mrad, load.q_star))
    phase = np.mod(t, 1.0)
    forward = phase < 0.5
    x = np.cos(2.0 * np.pi * t)
    u = np.where(forward, 0.5 * (1.0 - x), 0.5 * (1.0 + x))

    def along(half, s0, tv):
        h = {k: np.asarray(getattr(half, k)) for k in ("dv", "N0", "T0", "dN", "dT", "dslip", "active")}
        out_T, out_N, out_S = np.zeros_like(tv), np.zeros_like(tv), np.zeros_like(tv)
        pos, s = 0.0, s0
        for j in np.nonzero(h["active"])[0]:
            L = h["dv"][j]
            sel = (tv >= pos) & ((tv <= pos + L) | (j == np.nonzero(h["active"])[0][-1]))
            dt = tv[sel] - pos
            out_T[sel] = h["T0"][j, contact] + h["dT"][j, contact] * dt
            out_N[sel] = h["N0"][j, contact] + h["dN"][j, contact] * dt
            out_S[sel] = s + h["dslip"][j, contact] * dt
            pos, s = pos + L, s + h["dslip"][j, contact] * L
        return out_T, out_N, out_S, s

    Tf, Nf, Sf, s_end = along(ac.forward, 0.0, u * travel)
    Tb, Nb, Sb, _ = along(ac.backward, s_end, u * travel)
    T, N, S = np.where(forward, Tf, Tb), np.where(forward, Nf, Nb), np.where(forward, Sf, Sb)
    if component == "tangential":
        return T / kt - S, T * F_D
    return N / kn, N * F_D
