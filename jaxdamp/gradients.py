"""Sensitivities of the five numbers and of k_Im(psi_a) to the design variables, by automatic
differentiation through the jit-compiled direct solver, in forward (`jax.jacfwd`) or reverse
(`jax.jacrev`) mode. `outputs` is the pure function behind them: use it with `jax.grad`, `jax.vmap`
or your own jit (benchmarks/bench_batch.py times jax.grad of one output through it).

Derivatives are taken with respect to a whole `Design` and come back as Designs: theta_l, theta_r
(per degree), br_over_hr, bl2_over_hl, mu, kn and kt (per N/mm; kn, kt shared by R1, L1, L2 when
scalar, per contact when given as (3,) arrays) and the load (F_D per N, ...). Units of the
outputs: psi in mrad, k in N mm/mrad (see `jaxdamp --help`).

Within a fixed transition sequence the Base-Cycle is a smooth function of the design: every event
step is a closed-form ratio, and the solver guards its divisions and square roots (double where), so
the derivatives are exact, finite, and agree with central differences. Where the transition
sequence switches (a tract appears or vanishes, the longer half changes), the five numbers are
continuous with a kink and the derivative is that of the sequence the solver took at the point.
At liftoff or a failed cycle the numbers are not a damper's and the gradients are meaningless
(finite, but check `status`).

Cost (benchmarks/results/batch.json): the full forward-mode Jacobian of the five numbers costs about
as much as one forward evaluation, reverse mode a few times more; reverse mode compiles slowest.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_scalar
from .batch import map_batched
from .cycle import base_cycle_kernel
from .design import Design, as_design, check_batch
from .geometry import DamperShape
from .harmonics import UNITS as FIVE_NUMBER_UNITS
from .harmonics import FiveNumbers, complex_stiffness, five_numbers
from .params import Contacts, LoadCase
from .runtime import run_program
from .status import number_repr, status_repr

# The design variables that a derivative reports, with the Design field each one lives in.
PARAMETERS = ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "mu", "kn", "kt")
MODES = ("fwd", "rev")


def by_name(d: Design) -> dict:
    """A Design of derivatives as {parameter: value} over PARAMETERS plus F_D, q_star, r_sin_beta."""
    return {"theta_l": d.shape.theta_l, "theta_r": d.shape.theta_r,
            "br_over_hr": d.shape.br_over_hr, "bl2_over_hl": d.shape.bl2_over_hl, "mu": d.mu,
            "kn": d.contacts.kn, "kt": d.contacts.kt, "F_D": d.load.F_D, "q_star": d.load.q_star,
            "r_sin_beta": d.load.r_sin_beta}


class Outputs(NamedTuple):
    """The differentiated outputs: the five numbers and k_Im at the amplitude psi_a."""

    psi_fs: jnp.ndarray
    k_re_fs: jnp.ndarray
    psi_bc: jnp.ndarray
    k_re_bc: jnp.ndarray
    k_im_bc: jnp.ndarray
    k_im_at: jnp.ndarray


def _derivative_repr(d, output: str, unit: str) -> str:
    """'d k_im_bc/d mu=12.5 N mm/mrad, d k_im_bc/d theta_l=-3.1 N mm/mrad per deg' from a Design
    of derivatives (a repr must not raise: anything else reads '<unavailable>')."""
    try:
        return (f"d {output}/d mu={number_repr(d.mu, unit)}, "
                f"d {output}/d theta_l={number_repr(d.shape.theta_l, unit + ' per deg')}")
    except Exception:  # noqa: BLE001
        return f"d {output}=<unavailable>"


class FiveNumbersJacobian(NamedTuple):
    """values: the five numbers. d: FiveNumbers whose fields are Designs of derivatives,
    e.g. d.psi_bc.shape.theta_l = d psi_BC / d theta_L in mrad per degree (`by_name` flattens)."""

    values: FiveNumbers
    d: FiveNumbers
    status: jnp.ndarray  # RESULTS code of the Base-Cycle

    def __repr__(self) -> str:
        """Two lines at most: status by name, the five numbers with units, and two of the
        derivatives (of k_Im,BC by mu and theta_L); `by_name(jac.d.<output>)` lists them all."""
        try:
            values = ", ".join(f"{f}={number_repr(v, u)}" for f, v, u in
                               zip(FiveNumbers._fields, tuple(self.values)[:5], FIVE_NUMBER_UNITS))
            d = _derivative_repr(self.d.k_im_bc, "k_im_bc", "N mm/mrad")
        except Exception:  # noqa: BLE001 - a repr must not raise
            values, d = "<unavailable>", ""
        return f"FiveNumbersJacobian(status={status_repr(self.status)}, {values}; {d})"


class KImGradient(NamedTuple):
    """k_Im at psi_a (N mm/mrad) and its derivatives d (a Design)."""

    psi_a: jnp.ndarray
    k_im: jnp.ndarray
    d: Design
    status: jnp.ndarray  # RESULTS code of the Base-Cycle

    def __repr__(self) -> str:
        """One line: status by name, psi_a, k_Im with units and two of its derivatives."""
        return (f"KImGradient(status={status_repr(self.status)}, psi_a={number_repr(self.psi_a, 'mrad')}, "
                f"k_im={number_repr(self.k_im, 'N mm/mrad')}; "
                f"{_derivative_repr(self.d, 'k_im', 'N mm/mrad')})")


def outputs(design: Design, psi_a=0.0):
    """Pure, traceable: (Outputs, status) of one prepared Design, status the Base-Cycle's RESULTS
    code. Use inside your own jit/vmap/grad; psi_a in mrad."""
    bc = base_cycle_kernel(*design)
    nums = five_numbers(bc)
    _, k_im = complex_stiffness(bc, jnp.asarray(psi_a, float), method="interpolated")
    return Outputs(*nums.numbers(), k_im), bc.status


# Compiled once per mode and reused by every call (and by the tests): the five numbers and k_Im(psi_a)
# share one program, so asking for either costs the same compile.
def _with_values(design, psi_a):
    out, status = outputs(design, psi_a)
    return out, (out, status)


_value = jax.jit(outputs)
_jacobian = {"fwd": jax.jit(jax.jacfwd(_with_values, has_aux=True)),
             "rev": jax.jit(jax.jacrev(_with_values, has_aux=True))}


def _jac_fwd(design, psi_a):
    return _jacobian["fwd"](design, psi_a)


def _jac_rev(design, psi_a):
    return _jacobian["rev"](design, psi_a)


_BATCHED = {"fwd": _jac_fwd, "rev": _jac_rev}


def check_mode(mode):
    """One line naming `mode` and its choices, before any work."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}; got {mode!r}")


def validate_psi_a(psi_a_mrad):
    check_scalar("psi_a_mrad", psi_a_mrad, 0.0, 1e9, unit="mrad")


def collapse_shared_stiffness(d: Design, kn_shared: bool, kt_shared: bool) -> Design:
    """Sum per-contact stiffness derivatives (last axis) for stiffness given as one shared value
    (a prepared Design has kn, kt per pad)."""
    kn, kt = d.contacts
    return d._replace(contacts=Contacts(jnp.sum(kn, axis=-1) if kn_shared else kn,
                                        jnp.sum(kt, axis=-1) if kt_shared else kt))


def evaluate(shape, mu=None, contacts: Contacts = Contacts(), load: LoadCase = LoadCase(),
             psi_a_mrad=0.0) -> tuple[Outputs, jnp.ndarray]:
    """The differentiated outputs and the status of one design (the same program the gradients trace)."""
    design = as_design(shape, mu, contacts, load).prepared()
    validate_psi_a(psi_a_mrad)
    return _value(design, jnp.asarray(psi_a_mrad, float))


def _jac(shape, mu, contacts, load, psi_a, mode, runner=None):
    check_mode(mode)
    given = as_design(shape, mu, contacts, load)
    design = given.prepared()
    validate_psi_a(psi_a)
    program, args = _jacobian[mode], (design, jnp.asarray(psi_a, float))
    jac, (values, status) = run_program(program, args, runner)
    shared = (np.ndim(given.contacts.kn) == 0, np.ndim(given.contacts.kt) == 0)
    return values, Outputs(*(collapse_shared_stiffness(d, *shared) for d in jac)), status


def five_numbers_jacobian(shape: DamperShape | Design, mu=None, contacts: Contacts = Contacts(),
                          load: LoadCase = LoadCase(), mode: str = "fwd",
                          runner=None) -> FiveNumbersJacobian:
    """Derivatives of (psi_fs, k_Re,fs, psi_BC, k_Re,BC, k_Im,BC) with respect to every leaf of the
    Design (angles per degree, kn/kt per N/mm, F_D per N, ...), by forward ("fwd", jax.jacfwd) or
    reverse ("rev", jax.jacrev) mode AD. runner(program, args) -> outputs runs the compiled
    Jacobian program instead of a plain call (the CLI's saved programs)."""
    values, jac, status = _jac(shape, mu, contacts, load, 0.0, mode, runner)
    return FiveNumbersJacobian(FiveNumbers(*values[:5], status), FiveNumbers(*jac[:5], status),
                               status)


def k_im_gradient_at(psi_a_mrad, shape: DamperShape | Design, mu=None,
                     contacts: Contacts = Contacts(), load: LoadCase = LoadCase(),
                     mode: str = "fwd", runner=None) -> KImGradient:
    """k_Im (N mm/mrad) at platform rotation amplitude psi_a (mrad) and its derivatives.

    Below psi_BC this is the paper's linear microslip interpolation (zero below psi_fs), above it
    the exact first harmonic of the stretched cycle (see `jaxdamp.complex_stiffness`). runner: as
    in `five_numbers_jacobian`."""
    values, jac, status = _jac(shape, mu, contacts, load, psi_a_mrad, mode, runner)
    return KImGradient(jnp.asarray(psi_a_mrad, float), values.k_im_at, jac.k_im_at, status)


def batch_jacobian(designs: Design, psi_a=0.0, mode: str = "fwd", *, devices=None,
                   chunk_size: int | None = None, progress=None):
    """Jacobians of a batch of designs (a batched Design, e.g. from `jaxdamp.stack_designs`)
    through the one batching path (`jaxdamp.map_batched`): psi_a (mrad) is shared. Returns
    (jacobian, (values, status)) with Outputs-of-Design structure and a leading batch axis on every
    leaf (numpy)."""
    check_mode(mode)
    prepared = check_batch(designs)
    # one stiffness per design (a scalar or (n,)): its derivative is the sum over the pads
    shared = tuple(np.ndim(k) <= 1 for k in designs.contacts)
    validate_psi_a(psi_a)
    jac, aux = map_batched(_BATCHED[mode], prepared, jnp.asarray(psi_a, float), devices=devices,
                           chunk_size=chunk_size, progress=progress)
    return Outputs(*(collapse_shared_stiffness(d, *shared) for d in jac)), aux


__all__ = ["PARAMETERS", "MODES", "by_name", "Outputs", "FiveNumbersJacobian",
           "KImGradient", "outputs", "validate_psi_a", "evaluate", "five_numbers_jacobian",
           "k_im_gradient_at", "batch_jacobian", "collapse_shared_stiffness", "check_mode"]
