"""Full-slip statics: contact forces at the two full-slip ends of the cycle (normalised to F_D = 1)."""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from .linalg import generalized, solve3
from .geometry import DamperShape, full_slip_slide_rates, pad_geometry
from ._validate import RANGES, check_range, is_concrete, require_x64, traced
from .conventions import CENTRIFUGAL_LOAD, START_FRICTION_SIGNS
from .params import check_shape_and_mu
from .status import RESULTS, number_repr, status_repr


class FullSlipState(NamedTuple):
    """Contact forces (R1, L1, L2) on the damper, normalised to F_D, at one full-slip end."""

    N: jnp.ndarray  # normal forces (compressive > 0)
    T: jnp.ndarray  # tangential forces along the up-flank tangent
    resultant_pos_pct: jnp.ndarray  # left resultant from L1 (0) to L2 (100), % of L1-L2
    min_normal: jnp.ndarray
    solvable: jnp.ndarray  # False where the force lines make the statics singular


class FullSlipStatics(NamedTuple):
    """The full-slip statics at both ends of the cycle; `status` (RESULTS) is the one stored truth:
    `liftoff` where a normal force is <= 0 at either end, `singular` where the lines of action make
    the statics unsolvable."""

    start: FullSlipState  # cycle start, point 0
    mid: FullSlipState  # mid-cycle, point C
    min_normal_over_fd: jnp.ndarray
    status: jnp.ndarray  # RESULTS code

    def __repr__(self) -> str:
        return (f"FullSlipStatics(status={status_repr(self.status)}, "
                f"min_normal_over_fd={number_repr(self.min_normal_over_fd)})")


def contact_columns(shape: DamperShape):
    """Generalised unit normal (a_i) and tangent (c_i) vectors of each pad about D, (P, 3) each
    (`geometry.pad_geometry`: 3 pads for the curved-flat damper, 4 for a wedge), and the section
    geometry."""
    points, normals, tangents, geo = pad_geometry(shape)
    r = points - geo.D[..., None, :]
    return generalized(r, normals), generalized(r, tangents), geo


def full_slip_state(shape: DamperShape, mu, friction_signs) -> FullSlipState:
    """Statics with every contact at its friction limit T_i = s_i mu N_i.
    Unchecked, traceable (jit, vmap, grad); the checked form is `full_slip_statics`. Concrete
    inputs are checked as one design's (mu one number or one per pad)."""
    if not traced(shape, mu):
        check_shape_and_mu(shape, mu, n_pads=3)
    a, c, _ = contact_columns(shape)
    # Force on the damper per unit N: -n_i + s_i mu t_i; plus F_D = 1 upward at D.
    cols = -a + (friction_signs * mu)[:, None] * c
    N, ok = solve3(cols.T, -CENTRIFUGAL_LOAD)
    T = friction_signs * mu * N
    left = N[1] + N[2]
    safe = jnp.where(jnp.abs(left) > 1e-300, left, 1.0)
    pos = jnp.where(jnp.abs(left) > 1e-300, 100.0 * N[2] / safe, jnp.inf)
    return FullSlipState(N, T, pos, jnp.min(N), ok)


def statics_singular(shape: DamperShape, mu):
    """True (traceable) where the full-slip statics of either end cannot be solved: the design has
    no Base-Cycle, and every result of it reports `singular` (statics, cycles, amplitudes alike)."""
    start = full_slip_state(shape, mu, START_FRICTION_SIGNS)
    mid = full_slip_state(shape, mu, -START_FRICTION_SIGNS)
    return ~start.solvable | ~mid.solvable


@jax.jit
def statics_kernel(shape: DamperShape, mu) -> FullSlipStatics:
    start = full_slip_state(shape, mu, START_FRICTION_SIGNS)
    mid = full_slip_state(shape, mu, -START_FRICTION_SIGNS)
    min_n = jnp.minimum(start.min_normal, mid.min_normal)
    solvable = start.solvable & mid.solvable  # else min_n means nothing: singular, not liftoff
    status = RESULTS.first({RESULTS.singular: ~solvable, RESULTS.liftoff: solvable & (min_n <= 0.0)})
    return FullSlipStatics(start, mid, min_n, status)


def full_slip_statics(shape: DamperShape, mu) -> FullSlipStatics:
    """Full-slip contact forces at cycle start and mid-cycle, and the liftoff flag.

    A shape that lifts off is a valid result (liftoff=True), not an error.
    """
    require_x64()
    check_shape_and_mu(shape, mu)  # one design: a batch goes through vmap of statics_kernel
    return statics_kernel(shape, mu)


class WorkShapeFactors(NamedTuple):
    """Appendix C: W_i = F_D * dpsi * q*/2 * w_i for a full-slip stretch dpsi traversed both ways,
    and w_M for the platform moment (w_M = w_R1 + w_L1 + w_L2).

    One definition, evaluated on two different pairs of end states, so keep them apart:
    `full_slip_work_shape_factors` (statics) takes both ends at full slip (Appendix C as printed);
    `jaxdamp.work_shape_factors` (energy) takes the Base-Cycle's own gross-slip end states. They
    agree when gross slip is full slip and differ for frozen mechanisms (vertical flanks: 90L, 90R),
    where one contact stays stuck in gross slip."""

    w_R1: jnp.ndarray
    w_L1: jnp.ndarray
    w_L2: jnp.ndarray
    w_M: jnp.ndarray

    def __repr__(self) -> str:
        """One line (dimensionless factors; no status of their own: they go with the cycle's)."""
        parts = ", ".join(f"{f}={number_repr(v)}" for f, v in zip(self._fields, self))
        return f"WorkShapeFactors({parts})"


def full_slip_work_shape_factors(shape: DamperShape, mu) -> WorkShapeFactors:
    """Work shape factors (w_R1, w_L1, w_L2, w_M) from the full-slip forces (Appendix C, C.11-C.14).

    W_i = F_D * dpsi * q*/2 * w_i for a full-slip stretch of platform rotation dpsi traversed forward
    and back; w_M = |(f_Lv - f_R1v)^+ - (f_Lv - f_R1v)^-| and the identity w_M = sum w_i holds.
    Concrete inputs are checked (ValueError naming the parameter and its range; Float64Required in
    float32); traced ones pass to `full_slip_work_shape_factors_kernel`, the unchecked form.
    """
    require_x64()
    check_shape_and_mu(shape, mu)  # one design: a batch goes through vmap of statics_kernel
    return full_slip_work_shape_factors_kernel(shape, mu)


@jax.jit
def full_slip_work_shape_factors_kernel(shape: DamperShape, mu) -> WorkShapeFactors:
    """`full_slip_work_shape_factors` without input checks (traceable: jit, vmap, grad)."""
    st = statics_kernel(shape, mu)
    rates = full_slip_slide_rates(shape)
    # Appendix C's dv is the displacement of each platform end, half the relative one (C.10).
    w = 2.0 * mu * (st.start.N + st.mid.N) * rates
    _, _, geo = contact_columns(shape)
    w_m = jnp.abs(_left_minus_right_v(st.start, geo) - _left_minus_right_v(st.mid, geo))
    return WorkShapeFactors(w[0], w[1], w[2], w_m)


def _left_minus_right_v(state: FullSlipState, geo) -> jnp.ndarray:
    fy = -state.N * geo.normals[..., 1] + state.T * geo.tangents[..., 1]
    return fy[1] + fy[2] - fy[0]


class DesignResult(NamedTuple):
    """The design rule's b_R/h_R; `status` is `no_root` where no b_R/h_R in the bracket centres the
    resultant, `liftoff` where the centred resultant still leaves L1-L2 at mu_max, else `ok`."""

    br_over_hr: jnp.ndarray  # the centring b_R/h_R
    margin_pct: jnp.ndarray  # distance of the resultant from the nearer pad at both ends, % of L1-L2
    status: jnp.ndarray  # RESULTS code

    @property
    def found(self):
        """A root exists in the search bracket."""
        return self.status != RESULTS.no_root

    @property
    def inside(self):
        """The resultant lies inside L1-L2 at both ends (no liftoff at mu_max)."""
        return self.status == RESULTS.ok

    def __repr__(self) -> str:
        return (f"DesignResult(status={status_repr(self.status)}, "
                f"br_over_hr={number_repr(self.br_over_hr)}, "
                f"margin_pct={number_repr(self.margin_pct, '%')})")


def design_br(shape: DamperShape, mu_max=0.7, lo=-0.45, hi=0.45) -> DesignResult:
    """The paper's design rule (§3): the b_R/h_R that puts the left resultant equidistant from L1
    (cycle start) and L2 (mid-cycle) at mu_max, by bisection. `inside` is False where no b_R keeps
    the resultant inside L1-L2 (45sym at mu = 0.7)."""
    require_x64()
    check_shape_and_mu(shape, mu_max, "mu_max")
    low, high = RANGES["br_over_hr"][:2]  # the bracket: two b_R/h_R in their range, in order
    check_range("lo", lo, low, high)
    check_range("hi", hi, low, high)
    if is_concrete(lo) and is_concrete(hi) and not float(lo) < float(hi):
        raise ValueError(f"lo must be below hi (b_R/h_R); got lo {lo:g}, hi {hi:g}")
    return design_br_kernel(shape, mu_max, lo, hi)


@jax.jit
def design_br_kernel(shape, mu_max, lo, hi) -> DesignResult:
    def g(br):
        st = statics_kernel(shape._replace(br_over_hr=br), mu_max)
        return st.start.resultant_pos_pct + st.mid.resultant_pos_pct - 100.0

    g_lo, g_hi = g(lo), g(hi)
    found = jnp.sign(g_lo) * jnp.sign(g_hi) < 0

    def body(_, bracket):
        a, b, ga = bracket
        m = 0.5 * (a + b)
        gm = g(m)
        same = jnp.sign(gm) == jnp.sign(ga)
        return jnp.where(same, m, a), jnp.where(same, b, m), jnp.where(same, gm, ga)

    a, b, _ = jax.lax.fori_loop(0, 80, body, (jnp.asarray(lo, float), jnp.asarray(hi, float), g_lo))
    br = 0.5 * (a + b)
    margin = statics_kernel(shape._replace(br_over_hr=br), mu_max).start.resultant_pos_pct
    # Without a root br (and its margin) mean nothing: no_root, not liftoff.
    return DesignResult(br, margin, RESULTS.first({RESULTS.no_root: ~found,
                                                   RESULTS.liftoff: found & (margin <= 0.0)}))


__all__ = ["FullSlipState", "FullSlipStatics", "contact_columns", "full_slip_state",
           "statics_singular", "statics_kernel", "full_slip_statics", "WorkShapeFactors",
           "full_slip_work_shape_factors", "full_slip_work_shape_factors_kernel", "DesignResult",
           "design_br", "design_br_kernel"]
