"""k(psi_a) as a piecewise closed form: the steady cycle followed along the amplitude (issue 24).

For a fixed sequence of tracts (the contact states of every tract of every half, transient pairs
included) each tract's length is a closed-form event or the travel budget, and every force changes
linearly with travel, so the steady cycle's corners (the tract lengths dv and the platform moments
M0 at the tract starts; the moment rates dM are constant) are affine in psi_a on an interval of
amplitudes. k_Re and k_Im there are the first harmonic of a piecewise-linear loop whose corners
move linearly: a closed form of psi_a (`fourier.half_fourier`). Measured by a one-off script
(benchmarks/sequence_hypothesis.py, last in fc93a89; benchmarks/results/sequence_hypothesis.json):
second differences of the corners ~1e-15 of their scale within an interval of equal sequence.

`stiffness_curve` builds the curve of a batch of designs and one history from a few exact cycles
(probes), each with its derivative in psi_a by forward mode (`jax.jvp` through the per-amplitude
cycle `amplitude_kernel`, the reference method): a probe gives the affine model of its interval.
Two neighbouring probes belong to one interval when each model reproduces the other probe's k and
status; otherwise the break between them is found from the models themselves, where a tract's
affine length reaches zero (a tract leaving the left model or entering the right one), and
accepted only where both models give the same k there. A gap that neither test resolves gets a
probe in its middle (rounds, at most `max_rounds`); what is still unresolved then is marked
uncovered, and `sequence_curves` computes those amplitudes by plain cycles.
So a change of sequence the models do not see (a transient pair more or less, a change of the
preliminary halves of the assembly history) costs more probes, never a wrong number.

`StiffnessCurve.at(psi)` (pure JAX, differentiable w.r.t. psi_a; jit / vmap) gives k_Re, k_Im, the
status and whether the amplitude is covered. `refit_kernel` recomputes a curve's coefficients at
its probes for another design (same pieces), so that k at fixed amplitudes is differentiable
w.r.t. the design, forward and reverse.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .amplitude import MAX_PAIRS, MAX_TRACTS, amplitude_kernel
from .curves import (StiffnessCurves, check_curve_request, cycle_curves, flat_cycles, padded_index,
                     prepare_curves_inputs, stretched_curves)
from ._validate import check_int, require_x64
from .geometry import DamperShape
from .params import Contacts, LoadCase
from .conventions import travel_mm
from .fourier import half_fourier
from .geometry import platform_moment
from .runtime import batch_jit
from .status import RESULTS, number_repr, status_repr
from .tract import NO_EVENT

__all__ = ["StiffnessCurve", "CurvePoint", "stiffness_curve", "stiffness_curve_unchecked",
           "amplitude_curves", "CURVE_METHODS", "sequence_curves", "curve_at", "loop_stiffness", "corner_rows",
           "probe_kernel", "refit_kernel", "SAME_TOL", "MAX_ROUNDS"]

SAME_TOL = 1e-10  # k (relative to the larger |k| of two probes) within which two models agree
MAX_ROUNDS = 12  # rounds of midpoint probes for a gap that the models do not resolve
N_ROWS = 6  # corner rows: dv, M0, dM of the forward half, then of the backward half


class CurvePoint(NamedTuple):
    k_re: jnp.ndarray  # N mm/mrad (zero where the status is not ok / shakedown or not covered)
    k_im: jnp.ndarray
    status: jnp.ndarray  # RESULTS code (int32) of the piece
    covered: jnp.ndarray  # False: no verified piece here (compute by a plain cycle)


class StiffnessCurve(NamedTuple):
    """k(psi_a) of one design and history as pieces (a pytree; a batch has a leading design axis).

    Piece j holds on [start[j], start[j + 1]) (the first from -inf, unused pieces start at +inf):
    its corners are corners[j] + (psi - psi_ref[j]) * slopes[j], rows (dv, M0, dM) of the forward
    and of the backward half, MAX_TRACTS columns (mm, N mm, N mm per mm)."""

    start: jnp.ndarray  # (P,) mrad
    psi_ref: jnp.ndarray  # (P,) the probe amplitude of the piece, mrad
    corners: jnp.ndarray  # (P, 6, MAX_TRACTS)
    slopes: jnp.ndarray  # (P, 6, MAX_TRACTS) per mrad
    status: jnp.ndarray  # (P,) RESULTS codes (int32)
    covered: jnp.ndarray  # (P,) bool
    q_star: jnp.ndarray  # mm per rad of platform rotation (the load case's)
    psi_lo: jnp.ndarray  # the amplitude range the curve was built for, mrad
    psi_hi: jnp.ndarray
    cycles: jnp.ndarray  # exact cycles (probes) run to build it (int32)
    pairs: jnp.ndarray = None  # (P,) pairs of halves the piece's probe ran (int32)

    def __repr__(self) -> str:
        """One line: the amplitude range, the pieces in use and their statuses by name, the exact
        cycles run (a batch: over all its curves)."""
        try:
            used = np.isfinite(np.asarray(self.start, float))
            pieces = f"{int(used.sum())} of {used.size}"
            status = status_repr(np.asarray(self.status)[used])
        except Exception:  # noqa: BLE001 - a repr must not raise (traced curves)
            pieces, status = "<traced>", status_repr(self.status)
        return (f"StiffnessCurve(status={status}, psi_a={number_repr(self.psi_lo, 'mrad')} to "
                f"{number_repr(self.psi_hi, 'mrad')}, pieces={pieces}, cycles={number_repr(self.cycles)})")

    def at(self, psi_a) -> CurvePoint:
        """k at amplitude(s) psi_a (mrad) of a single curve (vmap it over a batch: `curve_at`)."""
        psi = jnp.asarray(psi_a, float)
        j = jnp.clip(jnp.sum(self.start[None, :] <= psi.reshape(-1, 1), axis=1) - 1, 0,
                     self.start.shape[0] - 1).reshape(psi.shape)
        rows = self.corners[j] + (psi - self.psi_ref[j])[..., None, None] * self.slopes[j]
        k_re, k_im = loop_stiffness(rows, psi, self.q_star)
        status = self.status[j]
        covered = self.covered[j]
        valid = RESULTS.valid(status) & covered
        zero = lambda v: jnp.where(valid, v, jnp.zeros_like(v))  # noqa: E731
        return CurvePoint(zero(k_re), zero(k_im), status, covered)


def curve_at(curve: StiffnessCurve, psi_a) -> CurvePoint:
    """`StiffnessCurve.at` of a batch of curves (leading design axis) at psi_a: (amplitudes,)
    shared or (designs, amplitudes). Unchecked, traceable: takes a `stiffness_curve` curve."""
    psi = jnp.asarray(psi_a, float)
    n = curve.start.shape[0]
    psi = jnp.broadcast_to(psi, (n,) + psi.shape[-1:])
    return jax.vmap(StiffnessCurve.at)(curve, psi)


def loop_stiffness(rows, psi_a, q_star):
    """(k_Re, k_Im) of the loop with corner rows (..., 6, MAX_TRACTS) at amplitude psi_a (mrad):
    the same closed form as the per-amplitude cycle's (`amplitude`), first harmonic by
    `fourier.half_fourier`. Broadcasts over leading axes."""
    psi = jnp.asarray(psi_a, float)
    ok = psi > 0.0
    psi = jnp.where(ok, psi, 1.0)
    a_dv = travel_mm(psi, q_star)

    def one(r, p, a):
        c1, s1 = half_fourier(r[0], r[1], r[2], a, 1.0)
        c2, s2 = half_fourier(r[3], r[4], r[5], a, -1.0)
        return (c1 + c2) / (jnp.pi * p), -(s1 + s2) / (jnp.pi * p)

    lead = rows.shape[:-2]
    flat = rows.reshape((-1,) + rows.shape[-2:])
    p = jnp.broadcast_to(psi, lead).reshape(-1)
    a = jnp.broadcast_to(a_dv, lead).reshape(-1)
    k_re, k_im = jax.vmap(one)(flat, p, a)
    return k_re.reshape(lead), k_im.reshape(lead)


def corner_rows(ac):
    """The loop's corner rows (6, MAX_TRACTS) of a steady cycle: dv, M0, dM of the forward half,
    then of the backward half (what `loop_stiffness` takes)."""
    f, b = ac.forward, ac.backward

    def rows(h):
        # Rows of tracts that did not run are zero: a masked scan keeps the end state there and a
        # while loop zeros, so unmasked they would differ by loop (and by how a tie resolved).
        # A row of zero length adds nothing to the loop's harmonics either way.
        def mom(N, T):
            return jnp.where(h.active, platform_moment(ac.shape, ac.load, N, T), 0.0)

        return [h.dv, mom(h.N0, h.T0), mom(h.dN, h.dT)]

    return jnp.stack(rows(f) + rows(b))


class Probe(NamedTuple):
    corners: jnp.ndarray  # (6, MAX_TRACTS)
    slopes: jnp.ndarray  # d corners / d psi_a (per mrad)
    k_re: jnp.ndarray
    k_im: jnp.ndarray
    status: jnp.ndarray
    cycles: jnp.ndarray
    seq_lo: jnp.ndarray  # the amplitudes (mrad) below / above psi_a where the first tract of the
    seq_hi: jnp.ndarray  # whole history (any half run) reaches zero length: the sequence changes


def _sequence_bounds(psi, dv, ddv):
    """(lo, hi): nearest roots below / above psi of the affine tract lengths dv + (p - psi) ddv."""
    live = (dv > 0.0) & (jnp.abs(ddv) * psi > 1e-13 * jnp.maximum(dv, 1e-300))
    r = jnp.where(live, psi - dv / jnp.where(live, ddv, 1.0), jnp.nan)
    above = live & (r > psi)
    below = live & (r < psi)
    return (jnp.max(jnp.where(below, r, -jnp.inf)), jnp.min(jnp.where(above, r, jnp.inf)))


def probe_kernel(shape, mu, contacts, load, psi_a, N_init=None, T_init=None, *,
                 initial="gross_slip", max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS,
                 loop: str = "while") -> Probe:
    """The exact cycle at psi_a (`amplitude_kernel`) with the derivative of its corners in psi_a
    (forward mode). loop="while" for values (forward mode passes a while loop); "scan" when the
    result is differentiated again in reverse mode w.r.t. the design."""

    def run(p):
        ac = amplitude_kernel(shape, mu, contacts, load, p, N_init, T_init, initial=initial,
                              max_tracts=max_tracts, max_pairs=max_pairs, loop=loop)
        return ((corner_rows(ac), ac.history_dv, ac.history_slack),
                (ac.k_re, ac.k_im, ac.status, ac.cycles))

    psi = jnp.asarray(psi_a, float)
    (rows, hist, slack), (d_rows, d_hist, d_slack), (k_re, k_im, status, cycles) = jax.jvp(
        run, (psi,), (jnp.ones_like(psi),), has_aux=True)
    valid = RESULTS.valid(status)
    d_rows = jnp.where(valid, d_rows, 0.0)
    rows = jnp.where(valid, rows, 0.0)
    # a tract leaving (its length reaches zero) or a new event entering (a slack reaches zero);
    # slacks measured from NO_EVENT are no events (their slope is zero)
    slack = jnp.where((hist > 0.0) & (slack < 0.5 * NO_EVENT), slack, 0.0)
    lo, hi = _sequence_bounds(psi, jnp.concatenate([hist.reshape(-1), slack.reshape(-1)]),
                              jnp.concatenate([d_hist.reshape(-1), d_slack.reshape(-1)]))
    return Probe(rows, d_rows, k_re, k_im, status, cycles, lo, hi)


@batch_jit(static_argnames=("initial", "max_tracts", "max_pairs"))
def _probes(shapes, mu, contacts, load, psi, N_init, T_init, initial, max_tracts, max_pairs):
    def one(s, m, c, ld, p, n0, t0):
        return probe_kernel(s, m, c, ld, p, n0, t0, initial=initial, max_tracts=max_tracts,
                            max_pairs=max_pairs)
    return jax.vmap(one)(shapes, mu, contacts, load, psi, N_init, T_init)


@batch_jit
def _model_k(corners, slopes, psi_ref, psi, q_star):
    """k of models (flat batch) at amplitudes psi."""
    rows = corners + (psi - psi_ref)[:, None, None] * slopes
    return loop_stiffness(rows, psi, q_star)


def stiffness_curve(designs, psi_lo=None, psi_hi=None, *, grid=None, initial="gross_slip",
                    N_init=None, T_init=None, n_probes: int = 5, max_rounds: int = MAX_ROUNDS,
                    max_probes: int = 64,
                    max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS) -> StiffnessCurve:
    """The piecewise closed-form k(psi_a) of a batch of designs on [psi_lo, psi_hi] (mrad).

    designs: (shapes, mu, contacts, load), every leaf with a leading design axis of the same size
    (concrete arrays; `curves.broadcast_designs` form). psi_lo, psi_hi: (designs,) or scalars.
    initial: "gross_slip", "assembly" or "explicit" (then N_init, T_init: (designs, 3)).
    grid: (designs, amplitudes), ascending, instead of psi_lo / psi_hi: the curve is wanted on
    these amplitudes only, so probes are taken on grid points and a gap with no grid point inside
    needs no resolving (every grid point is then covered, and no curve costs more cycles than its
    grid has points). Host-driven rounds of batched probes (one jit call per round for all
    designs). Returns a batch of StiffnessCurve (leading design axis; pieces padded to a common
    count).

    Every input is checked here (ValueError naming the parameter and its range; Float64Required
    in float32); `stiffness_curve_unchecked` takes inputs checked already."""
    require_x64()
    check_curve_request(designs, psi_lo, psi_hi, grid, initial, N_init, T_init)
    for name, count in (("max_tracts", max_tracts), ("max_pairs", max_pairs)):
        check_int(name, count, 1)
    check_int("n_probes", n_probes, 1)
    check_int("max_rounds", max_rounds, 0)
    check_int("max_probes", max_probes, 2)
    return stiffness_curve_unchecked(designs, psi_lo, psi_hi, grid=grid, initial=initial,
                                  N_init=N_init, T_init=T_init, n_probes=n_probes,
                                  max_rounds=max_rounds, max_probes=max_probes,
                                  max_tracts=max_tracts, max_pairs=max_pairs)


class _Prober(NamedTuple):
    """The batched probes of one `stiffness_curve_unchecked` call: the designs (numpy, leading design
    axis), their start states and q*, and the cycle options."""

    designs: tuple
    N0: np.ndarray
    T0: np.ndarray
    q_star: np.ndarray
    initial: str
    max_tracts: int
    max_pairs: int

    def run(self, design_idx, psi):
        """Probe records (numpy) for (design, psi) pairs, one batched call."""
        if design_idx.size == 0:
            return None
        idx = padded_index(np.arange(design_idx.size))
        d = design_idx[idx]
        sub = jax.tree_util.tree_map(lambda x: np.asarray(x)[d], self.designs)
        pr = _probes(*sub, jnp.asarray(psi[idx]), jnp.asarray(self.N0[d]),
                     jnp.asarray(self.T0[d]), self.initial, self.max_tracts, self.max_pairs)
        return {f: np.asarray(getattr(pr, f))[: design_idx.size] for f in Probe._fields}

    def model_k(self, recs, which, psi, designs_of):
        """k of the models of probes `which` (indices into recs) at psi."""
        if which.size == 0:
            return np.zeros(0), np.zeros(0)
        idx = padded_index(np.arange(which.size))
        w = which[idx]
        k_re, k_im = _model_k(jnp.asarray(recs["corners"][w]), jnp.asarray(recs["slopes"][w]),
                              jnp.asarray(recs["psi"][w]), jnp.asarray(psi[idx]),
                              jnp.asarray(self.q_star[designs_of[idx]]))
        return np.asarray(k_re)[: which.size], np.asarray(k_im)[: which.size]


def stiffness_curve_unchecked(designs, psi_lo=None, psi_hi=None, *, grid=None, initial="gross_slip",
                           N_init=None, T_init=None, n_probes: int = 5,
                           max_rounds: int = MAX_ROUNDS, max_probes: int = 64,
                           max_tracts: int = MAX_TRACTS,
                           max_pairs: int = MAX_PAIRS) -> StiffnessCurve:
    """`stiffness_curve` on inputs checked already (`curves.prepare_curves_inputs`): NOT checked
    here. The steps: the first probes of every design, rounds that resolve each gap between
    neighbouring probes (one piece, a break, or a new probe inside), then the pieces."""
    shapes, mu, contacts, load = designs
    n = int(np.shape(np.asarray(mu))[0])
    if grid is not None:
        grid = np.asarray(grid, float)
        grid = np.broadcast_to(grid, (n, grid.shape[-1]))
        psi_lo, psi_hi = grid[:, 0], grid[:, -1]
    lo = np.broadcast_to(np.asarray(psi_lo, float), (n,)).copy()
    hi = np.broadcast_to(np.asarray(psi_hi, float), (n,)).copy()
    q_star = np.broadcast_to(np.asarray(load.q_star, float), (n,))
    if initial == "explicit":
        N0 = np.asarray(N_init, float).reshape(n, 3)
        T0 = np.asarray(T_init, float).reshape(n, 3)
    else:
        N0 = T0 = np.zeros((n, 3))
    prober = _Prober((shapes, mu, contacts, load), N0, T0, q_star, initial, max_tracts, max_pairs)
    recs, order = _first_probes(prober, _first_amplitudes(n, lo, hi, grid, n_probes))
    # gap state per design: dict (left probe index) -> ("same" | ("break", b) | "open")
    resolved = [dict() for _ in range(n)]
    for rnd in range(max_rounds + 1):
        # the open gaps
        gaps = [(i, a, b) for i in range(n) for a, b in zip(order[i][:-1], order[i][1:])
                if a not in resolved[i]]
        if not gaps:
            break
        same, cand, pa, pb = _classify_gaps(prober, recs, gaps)
        new_d, new_p = _resolve_gaps(gaps, same, cand, pa, pb, resolved, order, grid,
                                     rnd == max_rounds, max_probes)
        if new_d:
            recs = _add_probes(prober, recs, order, new_d, new_p)
    return _assemble(recs, order, resolved, q_star, lo, hi)


def _first_amplitudes(n, lo, hi, grid, n_probes) -> list:
    """Per design the amplitudes of its first probes."""
    frac = np.geomspace(1.0, 2.0, n_probes) - 1.0 if n_probes > 1 else np.zeros(1)
    if grid is None:
        return [lo[i] + (hi[i] - lo[i]) * frac for i in range(n)]
    # on the distinct amplitudes (a grid may repeat its last value: no probe is wasted there)
    m_eff = np.sum(grid < grid[:, -1:], axis=1) + 1
    return [grid[i, np.unique(np.round(frac * (m_eff[i] - 1)).astype(int))] for i in range(n)]


def _first_probes(prober: _Prober, per: list):
    """All probes in flat arrays (appended per round), and per design a sorted list of probe
    indices."""
    d0 = np.concatenate([np.full(len(p), i) for i, p in enumerate(per)])
    p0 = np.concatenate(per)
    recs = prober.run(d0, p0)
    recs["psi"] = p0
    recs["design"] = d0
    ends = np.cumsum([len(p) for p in per])
    order = [list(range(e - len(p), e)) for e, p in zip(ends, per)]
    return recs, order


def _classify_gaps(prober: _Prober, recs, gaps):
    """(same: one piece spans the gap, cand: the break inside it (NaN where none), and the
    amplitudes of its ends) of every open gap (design, left probe, right probe)."""
    gi = np.array([g[0] for g in gaps])
    ga = np.array([g[1] for g in gaps])
    gb = np.array([g[2] for g in gaps])
    pa, pb = recs["psi"][ga], recs["psi"][gb]
    kscale = np.maximum.reduce([np.abs(recs["k_re"][ga]), np.abs(recs["k_im"][ga]),
                                np.abs(recs["k_re"][gb]), np.abs(recs["k_im"][gb])])
    tol = SAME_TOL * np.maximum(kscale, 1e-300)
    st_a, st_b = recs["status"][ga], recs["status"][gb]
    valid_a, valid_b = RESULTS.valid(st_a), RESULTS.valid(st_b)
    # 1. one piece: each model reproduces the other probe
    ra, ia = prober.model_k(recs, ga, pb, gi)
    rb, ib = prober.model_k(recs, gb, pa, gi)
    seq_ok = (recs["seq_hi"][ga] >= pb * (1 - 1e-12)) & (recs["seq_lo"][gb] <= pa * (1 + 1e-12))
    same = (st_a == st_b) & seq_ok & valid_a & (
        ~valid_a | ((np.abs(ra - recs["k_re"][gb]) <= tol) & (np.abs(ia - recs["k_im"][gb]) <= tol)
                    & (np.abs(rb - recs["k_re"][ga]) <= tol) & (np.abs(ib - recs["k_im"][ga]) <= tol)))
    # 2. a break where a tract's affine length reaches zero
    cand = np.full(len(gaps), np.nan)
    both = valid_a & valid_b & ~same
    if np.any(both):
        left = np.where(recs["seq_hi"][ga] < pb, recs["seq_hi"][ga], np.inf)
        right = np.where(recs["seq_lo"][gb] > pa, recs["seq_lo"][gb], -np.inf)
        for c in (left, right):
            use = both & np.isfinite(c) & np.isnan(cand)
            # the break must lie where both models still hold
            use &= (c <= left + 1e-12 * pb) & (c >= right - 1e-12 * pb)
            if not np.any(use):
                continue
            cc = np.where(use, c, pa)
            ka_r, ka_i = prober.model_k(recs, ga, cc, gi)
            kb_r, kb_i = prober.model_k(recs, gb, cc, gi)
            ok = use & (np.abs(ka_r - kb_r) <= tol) & (np.abs(ka_i - kb_i) <= tol)
            cand = np.where(ok, c, cand)
    return same, cand, pa, pb


def _resolve_gaps(gaps, same, cand, pa, pb, resolved, order, grid, last, max_probes):
    """Mark each gap one piece, a break or open (in `resolved`); (designs, amplitudes) of the new
    probes inside the others."""
    new_d, new_p = [], []
    for g, (i, a, b) in enumerate(gaps):
        if same[g]:
            resolved[i][a] = ("same",)
        elif np.isfinite(cand[g]):
            resolved[i][a] = ("break", float(cand[g]))
        elif last or not (pb[g] - pa[g] > 1e-13 * pb[g]) or len(order[i]) >= max_probes:
            resolved[i][a] = ("open",)
        elif grid is not None:
            inner = np.nonzero((grid[i] > pa[g]) & (grid[i] < pb[g]))[0]
            if inner.size == 0:
                resolved[i][a] = ("open",)
            else:
                new_d.append(i)
                new_p.append(grid[i, inner[inner.size // 2]])
        else:
            new_d.append(i)
            new_p.append(0.5 * (pa[g] + pb[g]))
    return new_d, new_p


def _add_probes(prober: _Prober, recs, order, new_d, new_p):
    """The records with the new probes appended, each inserted in its design's sorted order."""
    nd, npsi = np.array(new_d), np.array(new_p)
    more = prober.run(nd, npsi)
    base = recs["psi"].size
    more["psi"], more["design"] = npsi, nd
    recs = {f: np.concatenate([recs[f], more[f]]) for f in recs}
    for j, (i, p) in enumerate(zip(new_d, new_p)):
        lst = order[i]
        pos = int(np.searchsorted(recs["psi"][lst], p))
        lst.insert(pos, base + j)
    return recs


def _assemble(recs, order, resolved, q_star, lo, hi) -> StiffnessCurve:
    """The batch of StiffnessCurve from the probes and the resolved gaps (pieces padded to a
    common count, a multiple of 4)."""
    n = len(order)
    pieces = []
    for i in range(n):
        lst = order[i]
        pcs = [(-np.inf, lst[0], True)]
        for a, b in zip(lst[:-1], lst[1:]):
            how = resolved[i].get(a, ("open",))
            if how[0] == "same":
                continue
            if how[0] == "break":
                pcs.append((how[1], b, True))
            else:
                pcs.append((np.nextafter(recs["psi"][a], np.inf), a, False))
                pcs.append((recs["psi"][b], b, True))
        pieces.append(pcs)
    size = max(len(p) for p in pieces)
    size = -(-size // 4) * 4
    start = np.full((n, size), np.inf)
    ref_idx = np.zeros((n, size), int)
    covered = np.zeros((n, size), bool)
    for i, pcs in enumerate(pieces):
        for j, (s, r, c) in enumerate(pcs):
            start[i, j], ref_idx[i, j], covered[i, j] = s, r, c
        ref_idx[i, len(pcs):] = pcs[-1][1]
    cycles = np.array([len(order[i]) for i in range(n)], np.int32)
    return StiffnessCurve(jnp.asarray(start), jnp.asarray(recs["psi"][ref_idx]),
                          jnp.asarray(recs["corners"][ref_idx]), jnp.asarray(recs["slopes"][ref_idx]),
                          jnp.asarray(recs["status"][ref_idx].astype(np.int32)), jnp.asarray(covered),
                          jnp.asarray(q_star), jnp.asarray(lo), jnp.asarray(hi), jnp.asarray(cycles),
                          jnp.asarray(recs["cycles"][ref_idx].astype(np.int32)))


def refit_kernel(curve: StiffnessCurve, shape, mu, contacts, load, N_init=None, T_init=None, *,
                 initial="gross_slip", max_tracts: int = MAX_TRACTS,
                 max_pairs: int = MAX_PAIRS) -> StiffnessCurve:
    """One curve's coefficients recomputed at its probe amplitudes for (shape, mu, contacts, load)
    (pure JAX): the same pieces and breaks, the corners and slopes as functions of the design, so
    that `refit_kernel(curve, design...).at(psi)` is differentiable w.r.t. the design (forward and
    reverse) and equals `curve.at(psi)` at the design the curve was built for."""

    def one(p):
        return probe_kernel(shape, mu, contacts, load, p, N_init, T_init, initial=initial,
                            max_tracts=max_tracts, max_pairs=max_pairs, loop="scan")

    pr = jax.vmap(one)(curve.psi_ref)
    return curve._replace(corners=pr.corners, slopes=pr.slopes)


@jax.jit
def _evaluate(cur: StiffnessCurve, grid):
    """(CurvePoint, piece index) of a batch of curves on a (designs, amplitudes) grid."""
    j = jax.vmap(lambda c, p: jnp.clip(jnp.sum(c.start[None, :] <= p[:, None], axis=1) - 1, 0,
                                       c.start.shape[0] - 1))(cur, grid)
    return curve_at(cur, grid), j


CURVE_METHODS = ("cycles", "sequence")


def amplitude_curves(shapes: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                     load: LoadCase = LoadCase(), *, method: str = "cycles", initial="gross_slip",
                     max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS, runner=None,
                     n_probes: int = 5) -> StiffnessCurves:
    """k_Re, k_Im (N mm/mrad) of the steady cycles of many designs over an amplitude grid, in one
    batched call: StiffnessCurves with (designs, amplitudes) arrays. shapes / mu / contacts /
    load: every leaf with a leading design axis or a scalar shared by all; psi_a_mrad:
    (amplitudes,) shared or (designs, amplitudes), > 0; initial: "gross_slip" or "assembly".

    method: "cycles" (default) runs a steady cycle per (design, amplitude) by the direct method
    (`curves.cycle_curves`; traced inputs run `curves_kernel`; runner: the CLI's saved programs);
    "sequence" builds each design's piecewise closed form from n_probes exact cycles and reads k
    off it (`sequence_curves`: the same numbers to ~1e-12 of the k scale, fewer cycles on a fine
    grid; concrete inputs only)."""
    if method not in CURVE_METHODS:
        raise ValueError(f"method must be one of {', '.join(CURVE_METHODS)}; got {method!r}")
    for name, count in (("max_tracts", max_tracts), ("max_pairs", max_pairs), ("n_probes", n_probes)):
        check_int(name, count, 1)  # 0 failed inside with an IndexError
    if method == "sequence":
        if runner is not None:
            raise ValueError("runner: method 'sequence' runs host-driven rounds, not one program "
                             "(give runner=None, or method='cycles')")
        return sequence_curves(shapes, mu, psi_a_mrad, contacts, load, initial=initial,
                               max_tracts=max_tracts, max_pairs=max_pairs, n_probes=n_probes)
    return cycle_curves(shapes, mu, psi_a_mrad, contacts, load, initial=initial,
                        max_tracts=max_tracts, max_pairs=max_pairs, runner=runner)


def sequence_curves(shapes, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                    load: LoadCase = LoadCase(), *, initial="gross_slip",
                    max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS,
                    n_probes: int = 5, return_curve: bool = False):
    """`curves.amplitude_curves` (same arguments, same StiffnessCurves) by the piecewise closed
    form: per design one `stiffness_curve` on its amplitude grid (a few exact cycles), then k at
    every amplitude from the pieces; amplitudes no verified piece covers run as plain cycles, and
    from a gross-slip history the amplitudes above psi_BC take the stretched Base-Cycle exactly as
    `amplitude_curves` does. Equal to it to ~1e-12 of the k scale (benchmarks/sequence_check.py,
    tests/test_sequence.py). Concrete inputs only (host-driven); inside jit use `curves_kernel` or
    `refit_kernel` + `StiffnessCurve.at`. `cycles` is the pairs run by the probe of each point's
    piece. return_curve=True: (StiffnessCurves, the StiffnessCurve batch it was built from)."""
    designs, psi = prepare_curves_inputs(shapes, mu, contacts, load, psi_a_mrad, initial)
    size, n_amp = psi.shape
    order = np.argsort(psi, axis=1, kind="stable")
    grid = np.take_along_axis(psi, order, axis=1)
    use = None
    if initial == "gross_slip":
        # above psi_BC the stretched Base-Cycle is the steady cycle (as in amplitude_curves): the
        # curve is built on the amplitudes below only (those above repeat the last one below,
        # a gap with no amplitude inside costs nothing)
        k_st, kim_st, use, bc_pairs = (np.asarray(x) for x in stretched_curves(*designs,
                                                                               jnp.asarray(psi)))
        use_s = np.take_along_axis(use, order, axis=1)
        last = np.maximum(np.sum(~use_s, axis=1) - 1, 0)
        cap = np.take_along_axis(grid, last[:, None], axis=1)
        grid = np.where(use_s, cap, grid)
    cur = stiffness_curve_unchecked(designs, grid=grid, initial=initial, n_probes=n_probes,
                                 max_tracts=max_tracts, max_pairs=max_pairs)
    pt, j = _evaluate(cur, jnp.asarray(grid))
    pairs = np.take_along_axis(np.asarray(cur.pairs), np.asarray(j), axis=1)
    out = {f: np.empty((size, n_amp), dt) for f, dt in (("k_re", float), ("k_im", float),
                                                         ("status", np.int32), ("cycles", np.int32))}
    covered = np.empty((size, n_amp), bool)
    for f, v in (("k_re", pt.k_re), ("k_im", pt.k_im), ("status", pt.status), ("cycles", pairs)):
        np.put_along_axis(out[f], order, np.asarray(v), axis=1)
    np.put_along_axis(covered, order, np.asarray(pt.covered), axis=1)
    if use is not None:
        out["k_re"] = np.where(use, k_st, out["k_re"])
        out["k_im"] = np.where(use, kim_st, out["k_im"])
        out["status"] = np.where(use, RESULTS.ok, out["status"]).astype(np.int32)
        out["cycles"] = np.where(use, bc_pairs, out["cycles"]).astype(np.int32)
        covered |= use
    todo = np.nonzero(~covered.reshape(-1))[0]
    if todo.size:
        idx = padded_index(todo)
        design_of = idx // n_amp
        flat = jax.tree_util.tree_map(lambda x: x[design_of], designs)
        rerun = flat_cycles(*flat, psi.reshape(-1)[idx], initial, max_tracts, max_pairs)
        for f in out:
            v = out[f].reshape(-1)
            v[todo] = np.asarray(getattr(rerun, f))[: todo.size]
    res = StiffnessCurves(jnp.asarray(psi), *(jnp.asarray(out[f]) for f in
                                               ("k_re", "k_im", "status", "cycles")))
    return (res, cur) if return_curve else res
