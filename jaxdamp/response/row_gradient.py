"""Derivatives of the row's peaks by the implicit function theorem at the roots the values found.

The row's peak search (`row.row_program`: a grid, bracketed roots, while loops) runs values only.
At each peak it found, with the damper's own amplitude psi_d (r A* without residual flexibility),
two equations hold (`modes` docstring; `residual.through_residual`):

    e1 = psi_d |1 + c k(psi_d)| - r A = 0
    e2 = A (eta k_b + 1e-3 r^2 Im[k / (1 + c k)](psi_d)) - F = 0

so that d(A, psi_d) = -J^-1 de/dtheta, with J = de/d(A, psi_d) a 2x2 matrix: one forward
derivative of one steady cycle per peak, in three directions at once (A, psi_d and the inputs'
tangent; the elliptic cycle's by the replay of its recorded choices, `loops.values_by_replay`).
The derivative program takes the roots as inputs, so it never traces the search: it compiles in a
fraction of the values program's time, and the values program is the response command's own
(saved by the CLI, shared by every caller). A root where the peak is not valid (any status but
ok, no root) has a zero derivative, never NaN.

`peak_amplitudes_at` is the traceable kernel (forward and reverse mode pass it); `row_gradient`
the checked entry point: the row's peaks and their Jacobian with respect to `VARIABLES`.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..runtime import LOOP_EMITTERS, batch_jit
from ..status import RESULTS
from .frf import dynamic_stiffness
from .peaks import PATH_REPEATS
from .row import RowResponse, flexible_row, prepare_row, row_of_prepared, run_by_path_kind
from .scene import BladeMode
from .stiffness import check_history, path_cycle_kernel

__all__ = ["VARIABLES", "RowGradient", "peak_equations", "peak_amplitudes_at", "row_gradient_program",
           "row_gradient"]

# The inputs the row's peaks are differentiated with respect to, in the Jacobian's last axis:
# the damper's shape (deg, deg, -, -), mu, F_D (N), the contact stiffnesses as factors on every
# pad's kn and kt (1 = as given) and the damper's size h_L (mm; every path but the in-phase one
# turns the platforms relative to each other, which the size sees).
VARIABLES = ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "mu", "F_D", "kn_factor",
             "kt_factor", "h_l")


def peak_equations(a, psi, shape, mu, contacts, load, mode: BladeMode, motion, force_n, c,
                   initial: str = "assembly", loop: str = "auto"):
    """(e1, e2) of the module docstring at peak amplitudes a (mm) and the damper's own amplitudes
    psi (mrad), arrays of one shape: zero at a peak. c: the residual flexibility (mrad per N mm;
    0 without). One steady cycle per amplitude (`path_cycle_kernel`; loop "auto": its derivative
    replays the recorded choices in a masked scan, every mode; "forward": in loops that stop
    where the cycle did, forward mode only). Unchecked, traceable."""
    k_re, k_im, _ = jax.vmap(lambda p: path_cycle_kernel(
        shape, mu, contacts, load, p, motion, initial, loop, PATH_REPEATS))(psi)
    k = k_re + 1j * k_im
    z = 1.0 + c * k
    seen = k / z  # what the mode sees through the residual flexibility
    _, im = dynamic_stiffness(mode, lambda _: (jnp.real(seen), jnp.imag(seen)), a)
    return psi * jnp.abs(z) - mode.r * a, a * im - force_n


def _solved(e_a, e_p, e_t, valid):
    """d(A, psi_d) = -J^-1 e_t from the equations' derivatives along A (e_a), psi_d (e_p) and an
    input (e_t), each a pair (e1, e2); zero where not valid or J is singular."""
    det = e_a[0] * e_p[1] - e_a[1] * e_p[0]
    good = valid & (det != 0)
    det = jnp.where(good, det, 1.0)
    da = -(e_p[1] * e_t[0] - e_p[0] * e_t[1]) / det
    dpsi = -(e_a[0] * e_t[1] - e_a[1] * e_t[0]) / det
    return jnp.where(good, da, 0.0), jnp.where(good, dpsi, 0.0)


def _at_roots(roots_mm, psi_d_mrad, valid):
    """(valid, A, psi_d) held constant, 1 where not valid (no division by zero downstream)."""
    valid = jax.lax.stop_gradient(jnp.asarray(valid, bool))
    return (valid, jnp.where(valid, jax.lax.stop_gradient(roots_mm), 1.0),
            jnp.where(valid, jax.lax.stop_gradient(psi_d_mrad), 1.0))


def peak_amplitudes_at(shape, mu, contacts, load, mode: BladeMode, motion, force_n, roots_mm,
                       psi_d_mrad, valid, initial: str = "assembly", residual=None):
    """(A* (n_f,), psi_d (n_f,)): the peaks `roots_mm` the values found at forces force_n (N) and
    the damper's own amplitude there (mrad; r A* where residual is None), returned as given, with
    derivatives by the implicit function theorem (module docstring) with respect to every other
    argument. valid (n_f,): where the peak holds (status ok and a root found); elsewhere the
    value and the derivative are zero. residual: the path's residual flexibility c (mrad per
    N mm) or None. Unchecked, traceable (jit, vmap, jvp, grad)."""
    valid, a0, p0 = _at_roots(roots_mm, psi_d_mrad, valid)
    inputs = (shape, mu, contacts, load, mode, motion, force_n, 0.0 if residual is None else residual)
    closed, consts = jax.closure_convert(
        lambda a, p, *i: peak_equations(a, p, *i, initial), a0, p0, *inputs)

    @jax.custom_jvp
    def roots(a, psi, consts, *inputs):
        return a, psi

    @roots.defjvp
    def roots_jvp(primals, tangents):
        a, psi, cs, *ins = primals
        d_ins = tangents[3:]  # arrays: custom_jvp instantiates symbolic zeros by default
        one, zero = jnp.ones_like(a), jnp.zeros_like(a)

        def equations(a_, p_, *i):
            return closed(a_, p_, *i, *cs)

        # J along A and psi_d (both directions in one program) apart from the inputs' tangent:
        # J holds no tangent, so the rule stays linear in them and reverse mode can transpose it.
        e1, e2 = jax.vmap(lambda da, dp: jax.jvp(equations, (a, psi, *ins),
                                                 (da, dp, *map(_zeros, ins)))[1])(
            jnp.stack([one, zero]), jnp.stack([zero, one]))
        e_t = jax.jvp(equations, (a, psi, *ins), (zero, zero, *d_ins))[1]
        return (a, psi), _solved((e1[0], e2[0]), (e1[1], e2[1]), e_t, valid)

    a, psi = roots(a0, p0, consts, *inputs)
    return jnp.where(valid, a, 0.0), jnp.where(valid, psi, 0.0)


def _zeros(tree):
    return jax.tree_util.tree_map(jnp.zeros_like, tree)


def with_variables(p, shape, mu, contacts, load):
    """(shape, mu, contacts, load) with `VARIABLES` p (9,) put in: the shape's four, mu, F_D, and
    kn, kt scaled by p[6], p[7] (h_L, p[8], is the path's: `Motion.h_l`)."""
    return (shape._replace(theta_l=p[0], theta_r=p[1], br_over_hr=p[2], bl2_over_hl=p[3]), p[4],
            contacts._replace(kn=p[6] * contacts.kn, kt=p[7] * contacts.kt),
            load._replace(F_D=p[5]))


def variables_of(shape, mu, load, h_l):
    """`VARIABLES` (9,) of a prepared design (contact factors 1) and damper size h_l (mm)."""
    return jnp.stack([jnp.asarray(v, float) for v in (
        shape.theta_l, shape.theta_r, shape.br_over_hr, shape.bl2_over_hl, mu, load.F_D, 1.0,
        1.0, h_l)])


@functools.cache
def row_gradient_program(initial: str = "assembly", residual: bool = False):
    """One compiled program per contact history: (shape, mu, contacts, load, modes, motions,
    tip forces (m, n_f), roots (m, n_f), psi_d (m, n_f), valid (m, n_f)[, residuals (m,)]) ->
    dA*/d`VARIABLES` (m, n_f, 9), vmapped over the engine orders of one path kind
    (`row.run_by_path_kind`). The equations' forward derivatives in ten directions at once (A,
    psi_d and the nine variables; `peak_amplitudes_at`'s rule, under jacfwd, would redo the
    first two per variable; forward mode only, so the cycles' replays stop where they ended
    instead of running PATH_REPEATS masked periods), then the 2x2 solve per peak and variable.
    Compiled with XLA's loop emitters (`runtime.LOOP_EMITTERS`: measured faster to compile)."""
    def run(shape, mu, contacts, load, modes, motions, tips, roots, psi, valid, *residuals):
        p0 = variables_of(shape, mu, load, motions.h_l[0])
        n = p0.size

        def one(mode, motion, force, a, s, ok, c=0.0):
            ok, a, s = _at_roots(a, s, ok)

            def along(da, dpsi, dp):
                return jax.jvp(lambda a_, s_, p: peak_equations(
                    a_, s_, *with_variables(p, shape, mu, contacts, load), mode,
                    motion._replace(h_l=p[8]), force, c, initial, "forward"), (a, s, p0),
                    (da, dpsi, dp))[1]

            zeros = jnp.zeros((n + 2,) + a.shape)
            ones_a, ones_s = zeros.at[0].set(1.0), zeros.at[1].set(1.0)
            e1, e2 = jax.vmap(along)(ones_a, ones_s, jnp.eye(n + 2, n, -2))
            return jax.vmap(lambda t1, t2: _solved((e1[0], e2[0]), (e1[1], e2[1]), (t1, t2),
                                                   ok)[0], out_axes=-1)(e1[2:], e2[2:])

        return jax.vmap(one)(modes, motions, tips, roots, psi, valid, *residuals)

    return batch_jit(run, cpu_options=LOOP_EMITTERS)


class RowGradient(NamedTuple):
    """`row_gradient`: the row's peaks and their derivatives.

    row: the `RowResponse`. d_peak_mm: (m, n_f, 9) dA*/d`VARIABLES` (mm per deg, per unit, per
    N, per unit factor, per mm), zero where the peak is not valid (`RESULTS.valid` of row.status); the
    derivative of the sequence of events the peak's cycle took (one-sided at a switch).
    variables: `VARIABLES`."""

    row: RowResponse
    d_peak_mm: np.ndarray
    variables: tuple

    def __repr__(self):
        d = np.asarray(self.d_peak_mm)
        top = np.max(np.abs(d), axis=(0, 1)) if d.size else np.zeros(len(self.variables))
        largest = ", ".join(f"{n} {x:.3g}" for n, x in zip(self.variables, top))
        return f"RowGradient({self.row!r}; largest |dA*/d|: {largest})"


def row_gradient(shape, mu=None, contacts=None, load=None, *, modes, engine_orders,
                 force_n=(1.0,), h_l_mm: float, initial: str = "assembly",
                 runner=None) -> RowGradient:
    """`row_response` (checked inputs, the same arguments) and dA*/d`VARIABLES` of every peak:
    the derivative program (`row_gradient_program`) at the roots it found. The modal data are
    held fixed."""
    check_history(initial)
    prepared = prepare_row(shape, mu, contacts, load, modes, engine_orders, force_n, h_l_mm)
    row = row_of_prepared(prepared, initial, runner)
    design, forces, _, scenes, tip, residual = prepared
    peaks = row.peaks
    valid = np.asarray(RESULTS.valid(peaks.status)) & (np.asarray(peaks.peak_amplitude_mm) > 0)
    psi = np.where(valid, np.asarray(peaks.psi_a_mrad), 0.0)
    flexible = flexible_row(residual)
    per_order = (np.asarray(peaks.peak_amplitude_mm), psi, valid)
    parts = run_by_path_kind(row_gradient_program(initial, flexible is not None), design, scenes,
                             tip, flexible, per_order=per_order, runner=runner)
    d = np.stack([np.asarray(p)[:forces.size] for p in parts])
    return RowGradient(row, d, VARIABLES)
