"""The row's designer's diagram: the worst peak over a blade row's engine orders against the
excitation force and against the damper's mass at the design speed (F_D = m Omega^2 R), the
picture a designer chooses the mass from.

The quasi-static contact problem is homogeneous in F_D and the amplitude on every path (tested
per engine order and history in tests/test_optimize_row.py and tests/test_row_diagram.py):
A*(F; s F_D) = s A*(F / s; F_D), and the platforms' rotation scales with it. So one row of peaks
at the nominal F_D, on the forces of the force curve and the forces F / s of the mass curve,
gives both curves: one call of `row_response`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._validate import check_range, check_values
from ..status import RESULTS, number_repr, status_repr
from .modes import ModalFamily
from .row import RowResponse, beyond_small_rotation, row_response

__all__ = ["RowDiagram", "row_diagram"]


class RowDiagram(NamedTuple):
    """The worst peak over the row, against the force (at the nominal F_D) and against F_D (at
    one force).

    force_n (n_f,): forces per blade, N; worst_vs_force_mm_per_n (n_f,): the largest A*/F over
    the engine orders whose peak is valid (NaN where none is); engine_order_vs_force (n_f,):
    where (-1 where none); status_vs_force (n_f,): the most severe status over the engine orders
    (`RESULTS.worst`: large_rotation where a peak turns the platforms beyond the small-rotation
    model). fd_factor (n_s,): F_D over the nominal F_D; force_at_fd_n: the force of the mass
    curve; worst_vs_fd_mm_per_n, engine_order_vs_fd, status_vs_fd (n_s,): the same at
    force_at_fd_n and F_D scaled by fd_factor. row: the `RowResponse` both were read from (at the
    nominal F_D, on the forces of both curves)."""

    force_n: np.ndarray
    worst_vs_force_mm_per_n: np.ndarray
    engine_order_vs_force: np.ndarray
    status_vs_force: np.ndarray
    fd_factor: np.ndarray
    force_at_fd_n: float
    worst_vs_fd_mm_per_n: np.ndarray
    engine_order_vs_fd: np.ndarray
    status_vs_fd: np.ndarray
    row: RowResponse

    def __repr__(self):
        return (f"RowDiagram(worst A*/F {number_repr(self.worst_vs_force_mm_per_n, 'mm/N')} over "
                f"{len(self.force_n)} forces, {number_repr(self.worst_vs_fd_mm_per_n, 'mm/N')} "
                f"over {len(self.fd_factor)} F_D factors at {self.force_at_fd_n:g} N, status "
                f"{status_repr(np.concatenate([self.status_vs_force, self.status_vs_fd]))})")


def _worst_at(row: RowResponse, columns, scale):
    """(worst A*/F (n,), its engine order (n,), the most severe status (n,)) over the row at the
    force columns `columns`, with F_D scaled by `scale` (n,): the peak there is scale times the
    row's at that column's force (module doc), and so is the platforms' rotation, which is
    checked again against the small-rotation limit at the scaled F_D."""
    status = np.asarray(row.status)[:, columns]
    # Every large_rotation peak was valid before its rotation was checked (`row_response`).
    base = np.where(status == RESULTS.large_rotation, RESULTS.ok, status)
    status = beyond_small_rotation(base, scale[None, :] * np.asarray(row.rotation_mrad)[:, columns])
    valid = np.asarray(RESULTS.valid(status))
    force = scale * np.asarray(row.force_n)[columns]
    mag = np.where(valid, scale[None, :] * np.asarray(row.peaks.peak_amplitude_mm)[:, columns]
                   / force[None, :], -np.inf)
    where = np.argmax(mag, axis=0)
    some = valid.any(axis=0)
    worst = np.where(some, mag[where, np.arange(mag.shape[1])], np.nan)
    orders = np.where(some, np.asarray(row.engine_order)[where], -1)
    return worst, orders, np.asarray(RESULTS.worst(status, axis=0))


def row_diagram(shape, mu=None, contacts=None, load=None, *, modes: ModalFamily, engine_orders,
                h_l_mm: float, force_n, fd_factor, force_at_fd_n: float,
                initial: str = "assembly", runner=None) -> RowDiagram:
    """The row's designer's diagram of one design (module doc): the worst peak A*/F over the
    engine orders at each force of force_n (N per blade, 1-D) at the design's F_D, and at
    force_at_fd_n (N) with F_D scaled by each factor of fd_factor (1-D, > 0). modes, engine_orders,
    h_l_mm, initial and runner as `row_response`'s, which checks them (ValueError naming the
    parameter and its range) before anything is compiled; one row of peaks on the union of the
    forces and force_at_fd_n / fd_factor."""
    forces = np.atleast_1d(check_values("force_n", force_n))
    check_range("fd_factor", fd_factor, 0.0, np.inf, lo_open=True, hi_open=True)
    factors = np.atleast_1d(np.asarray(fd_factor, float))
    if factors.ndim != 1 or factors.size == 0:
        raise ValueError(f"fd_factor must be a number or a 1-D sequence of numbers in (0, inf); "
                         f"got shape {np.shape(fd_factor)}")
    at = float(check_values("force_n", force_at_fd_n, "force_at_fd_n", max_ndim=0))
    every = np.unique(np.concatenate([forces, at / factors]))
    row = row_response(shape, mu, contacts, load, modes=modes, engine_orders=engine_orders,
                       force_n=every, h_l_mm=h_l_mm, initial=initial, runner=runner)
    by_force = _worst_at(row, np.searchsorted(every, forces), np.ones(forces.size))
    by_fd = _worst_at(row, np.searchsorted(every, at / factors), factors)
    return RowDiagram(forces, *by_force, factors, at, *by_fd, row)
