"""The band of peaks over every admissible contact history, per engine order of a blade row.

At every amplitude the damper's band (`jaxdamp.band.band_kernel` with the path's motion, and in
series with the path's residual flexibility where the family has one: every statically admissible
state at X(0) = a X_r, sampled) bounds k_Im of every history's steady cycle. At resonance the peak
equation is g(A) = A (eta k_b + 1e-3 r^2 k_Im(r A)) - F = 0, and a smaller k_Im gives a larger
first root: the first roots of g with the band's lowest and highest k_Im bracket the peak of every
history. Each is bracketed on a table of TABLE_POINTS amplitudes (TABLE_DECADES below the free
blade's peak at the largest force: no damped peak lies above it, k_Im >= 0), then the bracket is
halved BISECTIONS times (in log A) with the band computed at its middle. Every number is the
band's at an amplitude it was computed at, nothing is interpolated (the band's lower k_Im rises
from zero, where a stuck state is admissible, to the histories' within a few per cent of psi:
a table between such points is off by tens of per cent). The result is the bracket's outer end:
the highest peak is at most `peak_max_mm`, the lowest at least `peak_min_mm`, to `resolution`.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_int
from ..band import band_kernel
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
    can give (mm; the bracket's outer ends, module doc). resolution: (m, n_f, 2) the relative
    width of each final bracket (highest, lowest). status: (m, n_f) RESULTS code: the damper's
    design check (the in-phase Base-Cycle), an amplitude the band was computed at without any
    valid cycle (its status), or not_converged where a root lies below the table; large_rotation
    where the highest peak turns the platforms beyond the small-rotation model
    (`row.outside_small_rotation`).
    psi_table_mrad (m, TABLE_POINTS), k_im_table (m, TABLE_POINTS, 2): the band's lowest and
    highest k_Im on the table (N mm/mrad, as the mode sees the damper; zero where no state gives
    a valid cycle). engine_order, nodal_diameter, force_n, elliptic: as `RowResponse`'s.
    n_samples: admissible states sampled per amplitude besides the polytope's vertices."""

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

        def one(mode, motion, forces, *c):
            def band_at(psi):
                b = band_kernel(shape, mu, contacts, load, psi, key, n_samples=n_samples, steps=0,
                                motion=motion, residual=c[0] if c else None)
                ok = b.status == RESULTS.ok
                return jnp.where(ok, b.bounds[2:], 0.0), b.status

            def g(psi, k_im, force):  # the peak equation at A = psi / r (N)
                return psi / mode.r * (mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_im) - force

            top = mode.r * jnp.max(forces) / (mode.eta * mode.k_b)
            table = top * jnp.logspace(-TABLE_DECADES, 0.0, TABLE_POINTS)
            k_table, st_table = jax.vmap(band_at)(table)  # (P, 2): k_Im min, max
            G = g(table[None, None, :], k_table.T[None], forces[:, None, None])  # (n_f, 2, P)
            up = G >= 0.0
            first = jnp.argmax(up, axis=-1)  # the first table point at or past the root
            # none: the root is the free peak itself (a stuck damper at the largest force)
            hi = jnp.where(jnp.any(up, axis=-1), table[first], top * (1.0 + 1e-9))
            lo = jnp.where(first > 0, table[jnp.maximum(first - 1, 0)], table[0])
            below = jnp.any(up, axis=-1) & (first == 0)
            bad = RESULTS.worst(st_table)

            def halve(carry, _):
                lo, hi, bad = carry
                mid = jnp.sqrt(lo * hi)
                k_mid, st_mid = jax.vmap(jax.vmap(band_at))(mid)  # (n_f, 2, 2), (n_f, 2)
                rising = g(mid, jnp.stack([k_mid[:, 0, 0], k_mid[:, 1, 1]], axis=1),
                           forces[:, None]) >= 0.0
                bad = RESULTS.combine(bad, st_mid)
                return (jnp.where(rising, lo, mid), jnp.where(rising, mid, hi), bad), None

            bad = jnp.broadcast_to(bad, lo.shape)
            (lo, hi, bad), _ = jax.lax.scan(halve, (lo, hi, bad), None, length=BISECTIONS)
            status = RESULTS.first({RESULTS.not_converged: below},
                                   RESULTS.combine(design_status, bad))
            status = RESULTS.worst(status, axis=1)
            return hi[:, 0] / mode.r, lo[:, 1] / mode.r, hi / lo - 1.0, status, table, k_table

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
    admissible states per table amplitude (`jaxdamp.band.band_kernel`; the in-phase band's
    trust-region refinement runs on the in-phase path only), so its bounds are inner bounds of
    the exact band's, tighter as n_samples grows. Every excited nodal diameter needs a loss factor
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
