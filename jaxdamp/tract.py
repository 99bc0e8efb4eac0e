"""The three-pad tract's rates in closed form (the engine's fast path for pads that may not open).

The step, its events and its state choice are the one tract engine's (`jaxdamp.engine`); this
module holds the contact states' codes and tolerances and the rates of the 8 stick/slip sets of
three closed pads by the all-stick reduction (`candidate_rates`, used by `engine.choose_closed`).

Within a tract the contact states are fixed, so the damper's incremental equilibrium is a 3x3 linear
system and every force changes at a constant rate per unit of relative platform displacement.
Notation (per contact i, generalised about D): a_i = B_i^T n_i (outward normal), c_i = B_i^T t_i
(up-flank tangent). With damper DOFs q and platform motion w_i:

    dN_i = kn_i (a_i.q' - n_i.w_i')            (normal spring, N > 0 in compression)
    stick: dT_i = -kt_i (c_i.q' - t_i.w_i')    (tangential spring)
    slip:  dT_i = s_i mu dN_i                  (on the limit line T = s_i mu N)
    sum_i (-dN_i a_i + dT_i c_i) = 0           (equilibrium of the rigid damper; F_D is constant)

Forces are normalised to F_D = 1, so stiffnesses enter as k / F_D (1/mm) and displacements are mm.
The right platform carries R1 and moves by dv; the left platform (L1, L2) is the reference.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .linalg import rowdot, solve3

STICK, SLIP, BACKSLIDE, OPEN = 0, 1, 2, 3
STATE_NAMES = ("stick", "slip", "backslide", "open")

# The 8 candidate state sets for 3 contacts, (8, 3) bool: bit i of row c set means contact i
# slips; candidate_rates and engine.choose_closed use this order.
# numpy, not jnp: a module-level JAX array would start the backend when jaxdamp is imported.
CANDIDATE_SETS = np.array([[(c >> i) & 1 for i in range(3)] for c in range(8)], dtype=bool)

LIMIT_TOL = 1e-10  # force (units of F_D) within which a contact counts as on its friction limit
RATE_TOL = 1e-9  # relative tolerance on rates (consistency checks, gross-slip detection)
NO_EVENT = 1e6  # mm: "no event in this tract"; finite so that masked arithmetic never makes NaN


class Mechanics(NamedTuple):
    """Everything a tract needs that does not change during the cycle (pytree of arrays).

    Besides the contact data it holds the all-stick system reduced once per design: every state set
    differs from all-stick by one rank-one term per slipping contact, c_i u_i^T with
    u_i = kt_i c_i + s_i mu kn_i a_i, so a tract's 3x3 solve reduces (Woodbury) to a solve in the
    slipping contacts only, with the design constants below. This replaces building and solving a
    3x3 stiffness for each of the 8 candidate state sets of every tract (benchmarks/bench_core.py).
    """

    a: jnp.ndarray  # (3, 3) generalised normals, rows per contact
    c: jnp.ndarray  # (3, 3) generalised tangents
    nw: jnp.ndarray  # (3,) n_i . w_i' per unit dv
    tw: jnp.ndarray  # (3,) t_i . w_i' per unit dv
    kn: jnp.ndarray  # (3,) normal stiffness / F_D, 1/mm
    kt: jnp.ndarray  # (3,) tangential stiffness / F_D, 1/mm
    mu: jnp.ndarray
    P: jnp.ndarray  # (3, 3) c_i . z_j with K0 z_j = c_j (K0: all-stick stiffness), mm per unit F_D
    Q: jnp.ndarray  # (3, 3) a_i . z_j
    gn0: jnp.ndarray  # (3,) normal gap rate of the all-stick tract, per unit of increasing dv
    gt0: jnp.ndarray  # (3,) tangential gap rate of the all-stick tract
    stick_ok: jnp.ndarray  # False where the all-stick stiffness K0 is singular


def make_mechanics(a, c, nw, tw, kn, kt, mu) -> Mechanics:
    """Mechanics of one design: contact data plus its all-stick reduction (one 3x3 solve)."""
    K0 = jnp.einsum("i,ij,ik->jk", kn, a, a) + jnp.einsum("i,ij,ik->jk", kt, c, c)
    r0 = jnp.einsum("i,ij->j", kn * nw, a) + jnp.einsum("i,ij->j", kt * tw, c)
    # One solve with four right-hand sides: the three tangents and the all-stick load.
    cols, ok = jax.vmap(solve3, in_axes=(None, 0))(K0, jnp.concatenate([c, r0[None]]))
    Z, x0 = cols[:3].T, cols[3]
    return Mechanics(a, c, nw, tw, kn, kt, jnp.asarray(mu, float), c @ Z, a @ Z, a @ x0 - nw,
                     c @ x0 - tw, ok[0])


def along(mech: Mechanics, direction) -> Mechanics:
    """The mechanics per unit travel in `direction` (+1 or -1 per unit dv): the platform motion
    and the all-stick gap rates, which are linear in it, times direction (exactly: a sign)."""
    return mech._replace(nw=direction * mech.nw, tw=direction * mech.tw,
                         gn0=direction * mech.gn0, gt0=direction * mech.gt0)


class TractRates(NamedTuple):
    dN: jnp.ndarray  # (3,) per unit of travel along the half-cycle's direction
    dT: jnp.ndarray
    dslip: jnp.ndarray  # sliding of the damper relative to the platform, along t_i
    ok: jnp.ndarray  # False where the tract's linear system is singular


def _rates(mech: Mechanics, m, signs, y, ok, direction) -> TractRates:
    """Rates of a tract from its slipping mask m (float, (..., 3)) and slip solution y."""
    per = lambda v: jnp.broadcast_to(v, y.shape)  # noqa: E731  one set (3,) or all 8 (8, 3)
    kn, kt = per(mech.kn), per(mech.kt)
    gn = direction * per(mech.gn0) + rowdot(y[..., None, :], mech.Q)
    gt = direction * per(mech.gt0) + rowdot(y[..., None, :], mech.P)
    dN = kn * gn
    dT = (1.0 - m) * (-kt * gt) + m * per(signs) * per(mech.mu) * dN
    # T = -kt (gt - slip) gives the slip rate; zero for stick contacts.
    dslip = m * (gt + dT / kt)
    return TractRates(dN, dT, dslip, ok & mech.stick_ok)


def _slip_system(mech: Mechanics, signs, direction):
    """A = I - W and g of the reduced system A_SS y_S = g_S of a slipping set S.

    With S, K_S = K0 - C_S U_S^T, so dq = dq0 + Z_S y_S with (I - W_SS) y_S = g_S,
    W_ij = u_i . z_j and g_i = u_i . dq0 - (rhs change)_i (`candidate_rates` solves it for every
    S in closed form)."""
    smu_kn = signs * mech.mu * mech.kn
    W = mech.kt[:, None] * mech.P + smu_kn[:, None] * mech.Q
    g = direction * (mech.kt * mech.gt0 + smu_kn * mech.gn0)
    return jnp.eye(3) - W, g


def plain_tract_rates(mech: Mechanics, slipping, signs, direction, solve=solve3) -> TractRates:
    """One state set's rates without the reduction: K_S and its load built contact by contact (the module
    docstring's equations) and solved by `solve(K, rhs) -> (x, ok)`. The reference that the reduced
    solve is tested against (tests/test_tract.py) and benchmarked against (benchmarks/bench_core.py).
    """
    m = slipping.astype(float)
    stick = 1.0 - m
    smu = signs * mech.mu * m
    a, c = mech.a, mech.c
    K = (jnp.einsum("i,ij,ik->jk", mech.kn, a, a)
         + jnp.einsum("i,ij,ik->jk", stick * mech.kt, c, c)
         - jnp.einsum("i,ij,ik->jk", smu * mech.kn, c, a))
    rhs = direction * (jnp.einsum("i,ij->j", mech.kn * mech.nw, a)
                       + jnp.einsum("i,ij->j", stick * mech.kt * mech.tw, c)
                       - jnp.einsum("i,ij->j", smu * mech.kn * mech.nw, c))
    dq, ok = solve(K, rhs)
    gn = a @ dq - direction * mech.nw
    gt = c @ dq - direction * mech.tw
    dN = mech.kn * gn
    dT = stick * (-mech.kt * gt) + smu * dN
    return TractRates(dN, dT, m * (gt + dT / mech.kt), ok)


_PAIRS = ((0, 1), (0, 2), (1, 2))


def _slip_solutions(A, g, rel_tol=1e-12):
    """y (8, 3) and ok (8,) for every candidate set (`CANDIDATE_SETS` order): A_SS y_S = g_S, y = 0 off
    S, in closed form per set size. ok follows `solve3`'s test |det| > rel_tol * prod(row norms),
    squared so that no square root is taken."""
    tol2 = rel_tol * rel_tol

    def div(num, det, ok):
        return jnp.where(ok, num / jnp.where(ok, det, 1.0), 0.0)

    d = jnp.diagonal(A)
    ok1 = d != 0.0  # a 1x1 system's row norm is |A_ii| itself: only an exact zero is singular
    y1 = div(g, d, ok1)
    pair = {}
    for i, j in _PAIRS:
        a, b, c, e = A[i, i], A[i, j], A[j, i], A[j, j]
        det = a * e - b * c
        ok = det * det > tol2 * (a * a + b * b) * (c * c + e * e)
        pair[i, j] = (div(e * g[i] - b * g[j], det, ok), div(a * g[j] - c * g[i], det, ok), ok)
    y3, ok3 = solve3(A, g, rel_tol)
    z = jnp.zeros_like(d[0])
    (p01i, p01j, o01), (p02i, p02j, o02), (p12i, p12j, o12) = (pair[p] for p in _PAIRS)
    y = jnp.stack([
        jnp.stack([z, z, z]), jnp.stack([y1[0], z, z]), jnp.stack([z, y1[1], z]),
        jnp.stack([p01i, p01j, z]), jnp.stack([z, z, y1[2]]), jnp.stack([p02i, z, p02j]),
        jnp.stack([z, p12i, p12j]), y3])
    ok = jnp.stack([jnp.array(True), ok1[0], ok1[1], o01, ok1[2], o02, o12, ok3])
    return y, ok


def candidate_rates(mech: Mechanics, signs, direction) -> TractRates:
    """The rates of all 8 candidate state sets at once (leading axis in `CANDIDATE_SETS` order),
    by the all-stick reduction (`_slip_system`): the engine's fast path for three closed pads."""
    A, g = _slip_system(mech, signs, direction)
    y, ok = _slip_solutions(A, g)
    return _rates(mech, CANDIDATE_SETS.astype(float), signs, y, ok, direction)


__all__ = ["STATE_NAMES", "CANDIDATE_SETS", "LIMIT_TOL", "RATE_TOL", "NO_EVENT", "Mechanics",
           "make_mechanics", "along", "TractRates", "plain_tract_rates", "candidate_rates"]
