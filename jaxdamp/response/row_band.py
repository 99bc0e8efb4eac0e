"""The band of peaks over every admissible contact history, per engine order of a blade row.

Every history's steady cycle at an amplitude starts from a statically admissible state at X(0) =
a X_r (`jaxdamp.band`), and those states do not depend on the amplitude: each sampled state s
(the polytope's vertices and n_samples random ones, `admissible.admissible_samples`) has its own
curve k_s. At resonance the peak equation is g(A) = A (eta k_b + 1e-3 r^2 Im k(r A)) - F = 0,
increasing in k_Im, so a history's first root lies between the first psi where some state has
g_s >= 0 (the lowest peak: the least of the states' first roots) and the first psi from which
every state has g_s >= 0 (at most the largest of the states' last up-crossings: the highest
peak; the two coincide where each g_s crosses once).

Each state's roots are searched in the damper's own amplitude psi_d: where the family has a
platform residual flexibility c the mode sees k / (1 + c k) at psi = psi_d |1 + c k(psi_d)|, both
explicit at psi_d (as `peaks.series_peaks`'s), so every evaluation is one steady cycle, in series
or not. The roots are bracketed on a table of TABLE_POINTS damper amplitudes (TABLE_DECADES below
the free blade's peak at the largest force: no damped peak lies above it, k_Im >= 0, and psi_d <=
psi), then each bracket is halved BISECTIONS times (in log psi_d), every state at its own
amplitudes. A state without a valid cycle at an amplitude is absent there (as from the band at
that amplitude, `band.band_kernel`); its psi there is bounded by psi_d times its extreme
|1 + c k| over the table. Every number is a cycle's at an amplitude it was computed at, nothing
is interpolated (a state's k_Im rises from zero, where it sticks, to the histories' within a few
per cent of psi: a table between such points is off by tens of per cent). The result is the bracket's outer end:
the highest peak is at most `peak_max_mm`, the lowest at least `peak_min_mm`, to `resolution`;
the highest is never above the free blade's peak F / (eta k_b), where a stuck state's root lies.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_int
from ..admissible import admissible_samples
from ..band import state_cycle
from ..runtime import batch_jit
from ..status import RESULTS, number_repr, status_repr
from .modes import ModalFamily, excited_nodal_diameter
from .row import flexible_row, outside_small_rotation, prepare_row, run_by_path_kind
from .stiffness import interpolated_damper

__all__ = ["RowBand", "row_band", "row_band_program", "check_band_family", "TABLE_POINTS",
           "TABLE_DECADES", "BISECTIONS"]

TABLE_POINTS = 24  # amplitudes of the band's table per engine order (log-spaced)
TABLE_DECADES = 3.0  # the table spans [psi_free 10^-3, psi_free], psi_free = r F_max / (eta k_b)
BISECTIONS = 6  # halvings of each root's bracket: a table step of 1.33 becomes 1.0045


class RowBand(NamedTuple):
    """The peak's bounds over every admissible contact history, per engine order (leading axis
    m) and force (second axis n_f).

    peak_max_mm / peak_min_mm: (m, n_f) the highest and the lowest peak tip amplitude any history
    can give (mm; the bracket's outer ends, module doc; peak_max_mm at most the free blade's
    peak F_tip / (eta k_b), a stuck damper's). resolution: (m, n_f, 2) the relative
    width of each final bracket (highest, lowest). status: (m, n_f) RESULTS code: the damper's
    design check (the in-phase Base-Cycle), an amplitude the band was computed at without any
    valid cycle (its status), or not_converged where a root lies below the table; large_rotation
    where the highest peak turns the platforms beyond the small-rotation model
    (`row.outside_small_rotation`).
    psi_table_mrad (m, TABLE_POINTS), k_im_table (m, TABLE_POINTS, 2): the damper's own amplitudes
    of the table (mrad; the platforms' where the family has no residual flexibility) and the
    lowest and highest k_Im of the states' cycles there (N mm/mrad, as the mode sees the damper;
    zero where no state gives a valid cycle). engine_order, nodal_diameter, force_n, elliptic:
    as `RowResponse`'s. n_samples: admissible states sampled besides the polytope's vertices
    (the same states at every amplitude)."""

    engine_order: np.ndarray
    nodal_diameter: np.ndarray
    force_n: np.ndarray
    peak_max_mm: np.ndarray
    peak_min_mm: np.ndarray
    resolution: np.ndarray
    status: np.ndarray
    psi_table_mrad: np.ndarray
    k_im_table: np.ndarray
    elliptic: np.ndarray
    n_samples: int

    def __repr__(self):
        return (f"RowBand({len(self.engine_order)} engine orders, A* from "
                f"{number_repr(self.peak_min_mm, 'mm')} to {number_repr(self.peak_max_mm, 'mm')}, "
                f"status {status_repr(self.status)})")


@functools.cache
def row_band_program(n_samples: int, residual: bool = False):
    """One compiled program per sample count: (shape, mu, contacts, load, modes, motions,
    tip_forces (m, n_f), key[, residuals (m,)]) -> (peak_max (m, n_f), peak_min, resolution
    (m, n_f, 2), status (m, n_f), table (m, P), k_Im's band on it (m, P, 2)), vmapped over the m
    engine orders of one path kind (each kind compiles once, as `row_program`)."""
    def run(shape, mu, contacts, load, modes, motions, tip_forces, key, *residuals):
        design_status = interpolated_damper(shape, mu, contacts, load).status
        T, real, P, n0 = admissible_samples(shape, mu, key, n_samples)

        def one(mode, motion, forces, *c):
            c = c[0] if c else 0.0

            def states_at(psi_d):  # (S,) each state at its own damper amplitude
                k_re, k_im, status = jax.vmap(lambda t, p: state_cycle(
                    shape, mu, contacts, load, p, t, P, n0, motion))(T, psi_d)
                k = (k_re + 1j * k_im) / (1.0 + c * (k_re + 1j * k_im))  # as the mode sees it
                psi = psi_d * jnp.abs(1.0 + c * (k_re + 1j * k_im))
                return psi, jnp.imag(k), real & RESULTS.valid(status), status

            def g(psi, k_im, force):  # the peak equation at A = psi / r (N)
                return psi / mode.r * (mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_im) - force

            top = mode.r * jnp.max(forces) / (mode.eta * mode.k_b)
            table = top * jnp.logspace(-TABLE_DECADES, 0.0, TABLE_POINTS)
            S = T.shape[0]
            psi_t, k_t, ok_t, st_t = jax.vmap(lambda p: states_at(jnp.full(S, p)))(table)  # (P, S)
            up = g(psi_t[None], k_t[None], forces[:, None, None]) >= 0.0  # (n_f, P, S)
            ok = jnp.broadcast_to(ok_t, up.shape)
            idx = jnp.arange(TABLE_POINTS)[None, :, None]
            # A state without a valid cycle at an amplitude is absent there, as from the band's
            # bounds at that amplitude (`band.band_kernel`): it counts as short of its root for
            # the lowest peak (the first amplitude where some state is up) and past it for the
            # highest (the first amplitude from which every state is up).
            first = jnp.min(jnp.where(ok & up, idx, TABLE_POINTS), axis=1)  # (n_f, S)
            last_down = jnp.max(jnp.where(ok & ~up, idx, -1), axis=1)
            hi_i = jnp.stack([first, last_down + 1])  # (2, n_f, S): lowest, highest peak's
            lo_i = hi_i - 1
            # psi at an amplitude without a valid cycle: psi_d times the state's least (for a
            # lower end) or largest (an upper end) |1 + c k| over its valid table points (1
            # without a residual flexibility); largest where the state sticks, at the table's
            # start
            ratio = psi_t / table[:, None]
            r_lo = jnp.min(jnp.where(ok_t, ratio, jnp.inf), axis=0)
            r_lo, r_hi = (jnp.where(jnp.isfinite(r), r, 1.0)[None, None, :] for r in
                          (r_lo, jnp.max(jnp.where(ok_t, ratio, -jnp.inf), axis=0)))
            cols = jnp.arange(S)

            def psi_at(i, r):  # (2, n_f, S) table indices, clipped
                i = jnp.clip(i, 0, TABLE_POINTS - 1)
                return jnp.where(ok_t[i, cols], psi_t[i, cols], table[i] * r)

            # none past the table: the root is the free peak itself (a stuck damper at the
            # largest force; no damped peak lies above it); none before it: the table's start
            beyond = top * (1.0 + 1e-9)
            hi_d = jnp.where(hi_i < TABLE_POINTS, table[jnp.minimum(hi_i, TABLE_POINTS - 1)], beyond)
            hi = jnp.where(hi_i < TABLE_POINTS, psi_at(hi_i, r_hi), beyond)
            lo_d = table[jnp.maximum(lo_i, 0)]
            lo = psi_at(lo_i, r_lo)
            absent_rises = jnp.array([False, True])[:, None, None]

            def halve(carry, _):
                lo_d, hi_d, lo, hi = carry
                mid = jnp.sqrt(lo_d * hi_d)
                psi_m, k_m, ok_m, _ = jax.vmap(jax.vmap(states_at))(mid)  # (2, n_f, S)
                rising = jnp.where(ok_m, g(psi_m, k_m, forces[None, :, None]) >= 0.0,
                                   absent_rises)
                return (jnp.where(rising, lo_d, mid), jnp.where(rising, mid, hi_d),
                        jnp.where(rising, lo, jnp.where(ok_m, psi_m, mid * r_lo)),
                        jnp.where(rising, jnp.where(ok_m, psi_m, mid * r_hi), hi)), None

            (lo_d, hi_d, lo, hi), _ = jax.lax.scan(halve, (lo_d, hi_d, lo, hi), None,
                                                   length=BISECTIONS)
            counted = jnp.any(ok_t, axis=0)[None, :]  # states with a valid cycle on the table
            low = jnp.argmin(jnp.where(counted, lo[0], jnp.inf), axis=1)  # (n_f,)
            high = jnp.argmax(jnp.where(counted, hi[1], -jnp.inf), axis=1)
            f = jnp.arange(forces.shape[0])
            # No history's peak lies above the free blade's, F / (eta k_b) (k_Im >= 0 and so is
            # Im k / (1 + c k)): a stuck state's root is exactly there, and its bracket's outer
            # end, up to `resolution` above it, is cut back to it.
            free = mode.r * forces / (mode.eta * mode.k_b)
            peak_min, peak_max = lo[0, f, low], jnp.minimum(hi[1, f, high], free)
            resolution = jnp.stack([hi[1, f, high] / lo[1, f, high],
                                    hi[0, f, low] / lo[0, f, low]], axis=1) - 1.0
            # per table amplitude the band's status: ok where a state's cycle is valid, else the
            # first real state's problem (as `band.band_kernel`'s)
            first_bad = st_t[:, jnp.argmax(real)]
            table_status = jnp.where(jnp.any(ok_t, axis=1), RESULTS.ok,
                                     jnp.where(jnp.any(real), first_bad, RESULTS.singular))
            below = jnp.any(counted & (first == 0), axis=1)  # a root below the table
            status = RESULTS.first({RESULTS.not_converged: below},
                                   RESULTS.combine(design_status, RESULTS.worst(table_status)))
            k_band = jnp.stack([jnp.min(jnp.where(ok_t, k_t, jnp.inf), axis=1),
                                jnp.max(jnp.where(ok_t, k_t, -jnp.inf), axis=1)], axis=1)
            k_band = jnp.where(jnp.any(ok_t, axis=1)[:, None], k_band, 0.0)
            return (peak_max / mode.r, peak_min / mode.r, resolution, status, table, k_band)

        return jax.vmap(one)(modes, motions, tip_forces, *residuals)

    return batch_jit(run)


def check_band_family(modes: ModalFamily, engine_orders) -> None:
    """ValueError naming loss_factor where an engine order's nodal diameter has none: the band's
    table ends at the free peak F / (eta k_b). (A nodal diameter the family lacks is
    `row_response`'s error.)"""
    for e in engine_orders:
        n, _ = excited_nodal_diameter(e, modes.n_blades)
        at = np.flatnonzero(np.asarray(modes.nodal_diameter) == n)
        if at.size and not float(modes.loss_factor[at[0]]) > 0.0:
            raise ValueError(f"loss_factor must be > 0 at nodal diameter {n} for the band (its "
                             f"table ends at the free peak F / (eta k_b)); got "
                             f"{float(modes.loss_factor[at[0]]):g}")


def row_band(shape, mu=None, contacts=None, load=None, *, modes: ModalFamily, engine_orders,
             force_n=(1.0,), h_l_mm: float, n_samples: int = 64, seed: int = 0,
             runner=None) -> RowBand:
    """Bounds of the peak tip response (mm) over every admissible contact history, per engine
    order and force (N per blade): `row_response`'s row (same arguments and checks) with the
    damper's band (module doc) instead of one history's curve. Every history's peak
    (`row_response` with initial "assembly" or "gross_slip") lies in [peak_min_mm, peak_max_mm].

    The band on a path is sampled: the admissible polytope's vertices and n_samples random
    admissible states (`admissible.admissible_samples`, the same at every amplitude; the in-phase
    band's trust-region refinement runs on the in-phase path only), so its bounds are inner
    bounds of the exact band's, tighter as n_samples grows. With a residual flexibility each
    state's peak is searched in its own amplitude (module doc), as cheap as without. Every excited nodal diameter needs a loss factor
    > 0 (the table's top is the free peak). runner: as `row_response`'s."""
    (shape, mu, contacts, load), forces, orders, scenes, tip, residual = prepare_row(
        shape, mu, contacts, load, modes, engine_orders, force_n, h_l_mm)
    check_int("n_samples", n_samples, 2)
    check_int("seed", seed, 0)
    check_band_family(modes, orders)
    flexible = flexible_row(residual)
    program = row_band_program(int(n_samples), flexible is not None)
    # padded by at most a quarter, from 1: a padded engine order or force costs as much as a real
    # one here (a minute or more for a row), against the seconds of a history's peaks
    rows = run_by_path_kind(program, (shape, mu, contacts, load), scenes, tip, flexible,
                            (jax.random.PRNGKey(seed),), runner, buckets=(1, 1, 4))
    peak_max, peak_min, resolution, status, table, k = (np.stack([r[i] for r in rows])
                                                        for i in range(6))
    cut = np.s_[:, :forces.size]
    status, _ = outside_small_rotation(status[cut], peak_max[cut], scenes)
    return RowBand(np.array(orders), np.array([s.nodal_diameter for s in scenes]), forces,
                   peak_max[cut], peak_min[cut], resolution[cut], status, table, k,
                   np.array([not s.straight for s in scenes]), int(n_samples))
