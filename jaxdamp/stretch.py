"""The Base-Cycle stretched by full slip at both ends: the steady cycle at psi_a >= psi_BC.

Its moment halves, their exact first harmonic (k_Re, k_Im) and work, and psi_BC itself. Below
`jaxdamp.harmonics` (the five numbers, the paper's interpolation) and `jaxdamp.amplitude` (whose
curves take the stretched cycle above psi_BC from a gross-slip history). Sign conventions and units
as in `jaxdamp.harmonics`: psi in mrad, M in N mm, k in N mm/mrad.
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp

from .conventions import psi_mrad, stiffness_from_fourier, travel_mm
from .cycle import BaseCycle
from .half import Half
from .fourier import half_fourier
from .geometry import platform_moment


def moment(bc: BaseCycle, N, T):
    """Platform moment M_P (N mm) for contact forces N, T (units of F_D), last axis = contact.
    Unchecked, traceable (jit, vmap, grad): takes a BaseCycle (checked when it was made)."""
    return platform_moment(bc.shape, bc.load, N, T)


class MomentHalf(NamedTuple):
    dv: jnp.ndarray  # (nt + 1,) segment lengths in mm of relative travel; last = gross-slip stretch
    M0: jnp.ndarray  # (nt + 1,) moment at each segment start, N mm
    dM: jnp.ndarray  # (nt + 1,) moment rate, N mm per mm of travel


def moment_half(bc: BaseCycle, half: Half, total_dv) -> MomentHalf:
    """Segments of one half of the moment cycle, completed to total_dv by a full-slip stretch."""
    m0 = moment(bc, half.N0, half.T0)
    dm = moment(bc, half.dN, half.dT)
    stretch = jnp.maximum(total_dv - half.span, 0.0)
    m_end = moment(bc, half.N_end, half.T_end)
    return MomentHalf(jnp.append(half.dv, stretch), jnp.append(m0, m_end), jnp.append(dm, 0.0))


def _half_fourier(seg: MomentHalf, a_dv, branch):
    """`fourier.half_fourier` of a Base-Cycle half completed by its full-slip stretch."""
    return half_fourier(seg.dv, seg.M0, seg.dM, a_dv, branch, ends_at_extreme=True)


def _work(seg: MomentHalf, branch, q_star):
    """oint M dpsi over a half (N mm): exact trapezoid on linear segments; psi in rad."""
    m1 = seg.M0 + seg.dM * seg.dv
    return jnp.sum(0.5 * (seg.M0 + m1) * (-branch) * seg.dv / q_star)


def stretched_cycle(bc: BaseCycle, psi_a_mrad):
    """Moment halves of the cycle at amplitude psi_a >= psi_BC (full-slip stretches at both ends)."""
    total = 2.0 * travel_mm(psi_a_mrad, bc.load.q_star)
    return moment_half(bc, bc.forward, total), moment_half(bc, bc.backward, total)


def gross_slip_stiffness(bc: BaseCycle, psi_a_mrad):
    """(k_Re, k_Im, W) at psi_a >= psi_BC, from the stretched moment cycle.

    A zero amplitude (a cycle that was never run, e.g. liftoff at cycle start) gives zeros, with
    the division guarded so that no NaN reaches values or gradients."""
    valid = psi_a_mrad > 0.0
    psi = jnp.where(valid, psi_a_mrad, 1.0)
    fwd, bwd = stretched_cycle(bc, psi)
    a_dv = travel_mm(psi, bc.load.q_star)
    c1, s1 = _half_fourier(fwd, a_dv, 1.0)
    c2, s2 = _half_fourier(bwd, a_dv, -1.0)
    k_re, k_im = stiffness_from_fourier(c1 + c2, s1 + s2, psi)
    work = _work(fwd, 1.0, bc.load.q_star) + _work(bwd, -1.0, bc.load.q_star)
    zero = jnp.zeros_like(k_re)
    return jnp.where(valid, k_re, zero), jnp.where(valid, k_im, zero), jnp.where(valid, work, zero)


def base_cycle_amplitude(bc: BaseCycle):
    """psi_BC (mrad): half the larger of the two half-cycle spans, over q*."""
    return psi_mrad(jnp.maximum(bc.forward.span, bc.backward.span) / 2.0, bc.load.q_star)


__all__ = ["moment", "MomentHalf", "moment_half", "stretched_cycle", "gross_slip_stiffness",
           "base_cycle_amplitude"]
