"""Energy dissipated at each contact (exact integral of T d(slip)) and work shape factors."""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ._validate import check_scalar, traced
from .conventions import platform_arm, travel_mm
from .cycle import BaseCycle, check_base_cycle
from .half import Half
from .harmonics import base_cycle_amplitude, cycle_work, moment
from .statics import WorkShapeFactors
from .status import number_repr


def _half_energy(half: Half, total_dv, F_D):
    # Within a tract T is linear and the sliding rate constant: the trapezoid rule is exact.
    T1 = half.T0 + half.dT * half.dv[:, None]
    tracts = -0.5 * (half.T0 + T1) * half.dslip * half.dv[:, None]
    stretch = jnp.maximum(total_dv - half.span, 0.0)
    gross = -half.T_end * half.gross_dslip * stretch
    return F_D * (jnp.sum(tracts, axis=0) + gross)


class CycleEnergy(NamedTuple):
    contacts: jnp.ndarray  # (3,) N mm per cycle at R1, L1, L2
    moment: jnp.ndarray  # oint M dpsi, N mm per cycle

    def __repr__(self) -> str:
        return (f"CycleEnergy(contacts (R1, L1, L2)={number_repr(self.contacts, 'N mm')}, "
                f"moment={number_repr(self.moment, 'N mm')})")


def contact_energies(bc: BaseCycle, psi_a_mrad=None) -> CycleEnergy:
    """Energy dissipated per cycle (N mm) at each contact and by the platform moment, at amplitude
    psi_a >= psi_BC (default: the Base-Cycle; a smaller psi_a is read as psi_BC).
    Traceable (jit, vmap, grad): takes a BaseCycle (its numbers checked when it was made); a
    concrete psi_a_mrad is checked (one number in (0, 10000] mrad)."""
    check_base_cycle(bc)
    if psi_a_mrad is not None and not traced(psi_a_mrad):
        check_scalar("psi_a_mrad", psi_a_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    return _contact_energies(bc, psi_a_mrad)


@jax.jit
def _contact_energies(bc: BaseCycle, psi_a_mrad=None) -> CycleEnergy:
    psi = base_cycle_amplitude(bc) if psi_a_mrad is None else jnp.maximum(
        psi_a_mrad, base_cycle_amplitude(bc))
    total = 2.0 * travel_mm(psi, bc.load.q_star)
    w = _half_energy(bc.forward, total, bc.load.F_D) + _half_energy(bc.backward, total, bc.load.F_D)
    return CycleEnergy(w, cycle_work(bc, psi))


@jax.jit
def work_shape_factors(bc: BaseCycle) -> WorkShapeFactors:
    """Work shape factors of the Base-Cycle, from its own gross-slip end states (see
    `WorkShapeFactors`: equal to `full_slip_work_shape_factors` when gross slip is full slip; they
    differ for frozen mechanisms such as 90L). Unchecked, traceable (jit, vmap, grad): takes a
    BaseCycle (checked when it was made)."""
    f, b = bc.forward, bc.backward
    # Energy per mm of relative travel in the two gross-slip states, times 2 for the per-platform dv.
    w = -2.0 * (f.T_end * f.gross_dslip + b.T_end * b.gross_dslip)
    m_f = moment(bc, f.N_end, f.T_end)
    m_b = moment(bc, b.N_end, b.T_end)
    w_m = jnp.abs(m_b - m_f) / (bc.load.F_D * platform_arm(bc.load.q_star, bc.load.r_sin_beta))
    return WorkShapeFactors(w[0], w[1], w[2], w_m)


__all__ = ["CycleEnergy", "contact_energies", "work_shape_factors"]
