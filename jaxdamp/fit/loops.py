"""Measured loops, analysed (numpy, no JAX): turning points, centre, amplitude and the travel phase
of every sample of a moment loop (psi mrad, M N mm) or a per-contact loop (disp mm, force N), and
the loop's direction (the energy it encloses). What `jaxdamp.fit` says about loops, in its module
docstring, is done here; unusable data raise LoopError in one line."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..geometry import CONTACT_NAMES

__all__ = ["LoopError", "MomentLoop", "ContactLoop", "COMPONENTS", "MAX_DISP_MM",
           "MIN_SAMPLES_PER_HALF", "ZONE", "MIN_LOOP_AREA", "analyse_loop", "analyse_contact_loop",
           "loop_work", "loop_direction_error", "loop_pair"]

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



def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, stop) of the runs of True in mask."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]))


def loop_pair(loop, name: str) -> tuple:
    """A measured loop given as (psi_mrad, moment_nmm), checked as a pair (a lone array or text
    failed inside `analyse_loop`'s call with Python's argument errors)."""
    if isinstance(loop, (str, bytes)) or not hasattr(loop, "__len__") or len(loop) != 2:
        raise ValueError(f"loops: {name} must be a (psi_mrad, moment_nmm) pair of 1-D arrays, a "
                         f"MomentLoop or a ContactLoop; got {type(loop).__name__}"
                         f"{'' if not hasattr(loop, '__len__') else f' of length {len(loop)}'}")
    return tuple(loop)


def _numbers(values, name: str, label: str) -> np.ndarray:
    """A loop's column as a flat float array; LoopError naming it where it holds no numbers."""
    try:
        if isinstance(values, (str, bytes)):
            raise TypeError
        return np.asarray(values, float).reshape(-1)
    except (TypeError, ValueError):
        raise LoopError(f"{name}: {label} must be numbers; got {values!r:.60}") from None


def analyse_loop(psi, moment, name: str = "loop", *, columns=("psi_mrad", "moment_nmm"),
                 unit: str = "mrad", max_amplitude: float = 1e4) -> MomentLoop:
    """Turning points, centre, amplitude and travel phase of a measured (psi, M) series.

    LoopError (a ValueError, one line naming `name`) for: unequal lengths, a NaN or infinity, fewer
    than two points, a constant psi, no closed period (psi must go top-bottom-top or
    bottom-top-bottom), an amplitude outside (0, 1e4] mrad."""
    psi, moment = (_numbers(v, name, label) for v, label in zip((psi, moment), columns))
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
