"""Sensitivities of the five numbers and of k_Im(psi_a) to the design variables, by automatic
differentiation through the jit-compiled direct solver, in forward (`jax.jacfwd`) or reverse
(`jax.jacrev`) mode. `outputs` is the pure function behind them: use it with `jax.grad`, `jax.vmap`
or your own jit (benchmarks/bench_batch.py times jax.grad of one output through it).

Design variables: theta_l, theta_r (per degree), br_over_hr, bl2_over_hl, mu, kn and kt (per N/mm;
kn, kt shared by R1, L1, L2 when scalar, per contact when given as (3,) arrays). Units of the
outputs: psi in mrad, k in N mm/mrad (see `jaxdamp --help`).

Within a fixed transition sequence the Base-Cycle is a smooth function of the design: every event
step is a closed-form ratio, and the solver guards its divisions and square roots (double where), so
the derivatives are exact, finite, and agree with central differences. Where the transition
sequence switches (a tract appears or vanishes, the longer half changes), the five numbers are
continuous with a kink and the derivative is that of the sequence the solver took at the point.
At liftoff or a failed cycle the numbers are not a damper's and the gradients are meaningless
(finite, but check the flags).

Cost (benchmarks/results/batch.json): the full forward-mode Jacobian of the five numbers costs about
as much as one forward evaluation, reverse mode a few times more; reverse mode compiles slowest.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .cycle import _base_cycle
from .geometry import DamperShape, validate_shape
from .harmonics import FiveNumbers, complex_stiffness, five_numbers
from .params import Contacts, LoadCase, validate_contacts, validate_load, validate_mu

PARAMETERS = ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "mu", "kn", "kt")
MODES = ("fwd", "rev")


class DesignVariables(NamedTuple):
    """The differentiable inputs of a Base-Cycle (a pytree; also the structure of every gradient)."""

    theta_l: jnp.ndarray  # deg
    theta_r: jnp.ndarray  # deg
    br_over_hr: jnp.ndarray
    bl2_over_hl: jnp.ndarray
    mu: jnp.ndarray
    kn: jnp.ndarray  # N/mm, scalar or (3,) for (R1, L1, L2)
    kt: jnp.ndarray  # N/mm


class Outputs(NamedTuple):
    """The differentiated outputs: the five numbers and k_Im at the amplitude psi_a."""

    psi_fs: jnp.ndarray
    k_re_fs: jnp.ndarray
    psi_bc: jnp.ndarray
    k_re_bc: jnp.ndarray
    k_im_bc: jnp.ndarray
    k_im_at: jnp.ndarray


class Flags(NamedTuple):
    converged: jnp.ndarray
    liftoff: jnp.ndarray
    failed: jnp.ndarray


class FiveNumbersJacobian(NamedTuple):
    """values: the five numbers. d: FiveNumbers whose fields are DesignVariables of derivatives,
    e.g. d.psi_bc.theta_l = d psi_BC / d theta_L in mrad per degree."""

    values: FiveNumbers
    d: FiveNumbers
    converged: jnp.ndarray
    liftoff: jnp.ndarray
    failed: jnp.ndarray


class KImGradient(NamedTuple):
    """k_Im at psi_a (N mm/mrad) and its derivatives d (DesignVariables)."""

    psi_a: jnp.ndarray
    k_im: jnp.ndarray
    d: DesignVariables
    converged: jnp.ndarray
    liftoff: jnp.ndarray
    failed: jnp.ndarray


def design_variables(shape: DamperShape, mu, contacts: Contacts = Contacts()) -> DesignVariables:
    """The design variables of (shape, mu, contacts) as float arrays."""
    f = lambda v: jnp.asarray(v, float)  # noqa: E731
    return DesignVariables(f(shape.theta_l), f(shape.theta_r), f(shape.br_over_hr),
                           f(shape.bl2_over_hl), f(mu), f(contacts.kn), f(contacts.kt))


def outputs(dv: DesignVariables, psi_a=0.0, load: LoadCase = LoadCase(), x_d=None):
    """Pure, traceable: (Outputs, Flags) of one design. Use inside your own jit/vmap/grad.

    x_d (centre of mass, held fixed, not differentiated) is None for the triangle's centroid.
    """
    shape = DamperShape(dv.theta_l, dv.theta_r, dv.br_over_hr, dv.bl2_over_hl, x_d)
    load = LoadCase(*(jnp.asarray(v, float) for v in load))
    bc = _base_cycle(shape, dv.mu, Contacts(dv.kn, dv.kt), load)
    nums = five_numbers(bc)
    _, k_im = complex_stiffness(bc, jnp.asarray(psi_a, float), method="interpolated")
    return Outputs(*nums, k_im), Flags(bc.converged, bc.liftoff, bc.failed)


# Compiled once per mode and reused by every call (and by the tests): the five numbers and k_Im(psi_a)
# share one program, so asking for either costs the same compile.
def _with_values(dv, psi_a, load, x_d):
    out, flags = outputs(dv, psi_a, load, x_d)
    return out, (out, flags)


_value = jax.jit(outputs)
_jacobian = {"fwd": jax.jit(jax.jacfwd(_with_values, has_aux=True)),
             "rev": jax.jit(jax.jacrev(_with_values, has_aux=True))}


def _checked(shape, mu, contacts, load, mode):
    """Validated design variables with kn, kt always per contact (3,): one compiled program serves
    shared and per-contact stiffness (a shared value's derivative is the sum over contacts)."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}; got {mode!r}")
    validate_shape(shape)
    validate_mu(mu)
    validate_contacts(contacts)
    validate_load(load)
    x_d = None if shape.x_d is None else jnp.asarray(shape.x_d, float)
    dv = design_variables(shape, mu, contacts)
    if dv.kn.shape not in ((), (3,)) or dv.kt.shape not in ((), (3,)):
        raise ValueError("kn and kt must be scalars or per-contact arrays of shape (3,)")
    return dv._replace(kn=jnp.broadcast_to(dv.kn, (3,)), kt=jnp.broadcast_to(dv.kt, (3,))), x_d


def _collapse(d: DesignVariables, kn_shared: bool, kt_shared: bool) -> DesignVariables:
    """Sum per-contact stiffness derivatives (last axis) for stiffness given as one shared value."""
    return d._replace(kn=jnp.sum(d.kn, axis=-1) if kn_shared else d.kn,
                      kt=jnp.sum(d.kt, axis=-1) if kt_shared else d.kt)


def evaluate(shape: DamperShape, mu, contacts: Contacts = Contacts(), load: LoadCase = LoadCase(),
             psi_a_mrad=0.0) -> tuple[Outputs, Flags]:
    """The differentiated outputs and flags of one design (the same program the gradients trace)."""
    dv, x_d = _checked(shape, mu, contacts, load, "fwd")
    _check_psi_a(psi_a_mrad)
    return _value(dv, jnp.asarray(psi_a_mrad, float), load, x_d)


def _check_psi_a(psi_a_mrad):
    from ._validate import check_range

    check_range("psi_a_mrad", psi_a_mrad, 0.0, 1e9, unit="mrad")


def _jac(shape, mu, contacts, load, psi_a, mode):
    dv, x_d = _checked(shape, mu, contacts, load, mode)
    _check_psi_a(psi_a)
    psi_a = jnp.asarray(psi_a, float)
    jac, (values, flags) = _jacobian[mode](dv, psi_a, load, x_d)
    shared = (np.ndim(contacts.kn) == 0, np.ndim(contacts.kt) == 0)
    return values, Outputs(*(_collapse(d, *shared) for d in jac)), flags


def five_numbers_jacobian(shape: DamperShape, mu, contacts: Contacts = Contacts(),
                          load: LoadCase = LoadCase(), mode: str = "fwd") -> FiveNumbersJacobian:
    """Derivatives of (psi_fs, k_Re,fs, psi_BC, k_Re,BC, k_Im,BC) with respect to the design
    variables, by forward ("fwd", jax.jacfwd) or reverse ("rev", jax.jacrev) mode AD."""
    values, jac, flags = _jac(shape, mu, contacts, load, 0.0, mode)
    return FiveNumbersJacobian(FiveNumbers(*values[:5]), FiveNumbers(*jac[:5]), *flags)


def k_im_gradient_at(psi_a_mrad, shape: DamperShape, mu, contacts: Contacts = Contacts(),
                     load: LoadCase = LoadCase(), mode: str = "fwd") -> KImGradient:
    """k_Im (N mm/mrad) at platform rotation amplitude psi_a (mrad) and its derivatives.

    Below psi_BC this is the paper's linear microslip interpolation (zero below psi_fs), above it
    the exact first harmonic of the stretched cycle (see `jaxdamp.complex_stiffness`)."""
    values, jac, flags = _jac(shape, mu, contacts, load, psi_a_mrad, mode)
    return KImGradient(jnp.asarray(psi_a_mrad, float), values.k_im_at, jac.k_im_at, *flags)


_batched = {mode: jax.jit(jax.vmap(_jacobian[mode], in_axes=(0, None, None, None))) for mode in MODES}


def batch_jacobian(dv: DesignVariables, psi_a=0.0, load: LoadCase = LoadCase(), mode: str = "fwd"):
    """Jacobians of a batch of designs under vmap: every field of dv has a leading batch axis
    (kn, kt: (n,) or (n, 3)); psi_a (mrad) and load are shared. Returns (jacobian, (values, flags))
    with Outputs-of-DesignVariables structure and a leading batch axis on every leaf."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}; got {mode!r}")
    dv = DesignVariables(*(jnp.asarray(v, float) for v in dv))
    n = {int(v.shape[0]) for v in dv if v.ndim}
    if len(n) != 1 or any(v.ndim == 0 for v in dv):
        raise ValueError("every design variable needs the same leading batch axis")
    shared = (dv.kn.ndim == 1, dv.kt.ndim == 1)
    size = n.pop()
    dv = dv._replace(kn=jnp.broadcast_to(dv.kn.reshape(size, -1), (size, 3)),
                     kt=jnp.broadcast_to(dv.kt.reshape(size, -1), (size, 3)))
    validate_shape(DamperShape(*dv[:4]))
    validate_mu(dv.mu)
    validate_contacts(Contacts(dv.kn, dv.kt))
    validate_load(load)
    _check_psi_a(psi_a)
    jac, aux = _batched[mode](dv, jnp.asarray(psi_a, float), load, None)
    return Outputs(*(_collapse(d, *shared) for d in jac)), aux


# ---------------------------------------------------------------- CLI: jaxdamp grad
JSON_OUTPUTS = (("psi_bc_mrad", "psi_bc"), ("k_im_bc", "k_im_bc"), ("k_re_bc", "k_re_bc"),
                ("psi_fs_mrad", "psi_fs"), ("k_re_fs", "k_re_fs"))


def _as_json(d: DesignVariables) -> dict:
    import numpy as np

    out = {}
    for name, value in d._asdict().items():
        arr = np.asarray(value, float)
        out[name] = float(arr) if arr.ndim == 0 else [float(v) for v in arr]
    return out


def grad_payload(shape, mu, contacts, load=LoadCase(), mode="fwd", psi_a_mrad=None) -> dict:
    """The `jaxdamp grad --json` document: one dict of derivatives per output, keyed by variable."""
    jac = five_numbers_jacobian(shape, mu, contacts, load, mode)
    payload = {key: _as_json(getattr(jac.d, field)) for key, field in JSON_OUTPUTS}
    payload["values"] = {key: float(getattr(jac.values, field)) for key, field in JSON_OUTPUTS}
    if psi_a_mrad is not None:
        g = k_im_gradient_at(psi_a_mrad, shape, mu, contacts, load, mode)
        payload["k_im_at_psi_a"] = _as_json(g.d)
        payload["values"]["k_im_at_psi_a"] = float(g.k_im)
        payload["psi_a_mrad"] = float(psi_a_mrad)
    payload.update(mode=mode, converged=bool(jac.converged), liftoff=bool(jac.liftoff),
                   failed=bool(jac.failed),
                   units="derivative of the output (psi in mrad, k in N mm/mrad) per unit of the "
                         "variable: per degree for theta_l/theta_r, per N/mm for kn/kt")
    return payload


def cmd_grad(args):
    from .cli import emit, shape_from_args

    shape = shape_from_args(args)
    payload = grad_payload(shape, args.mu, Contacts(args.kn, args.kt),
                           LoadCase(args.fd, args.q, args.r_sin_beta), args.mode, args.psi_a)
    rows = [key for key, _ in JSON_OUTPUTS] + (["k_im_at_psi_a"] if args.psi_a is not None else [])
    head = f"{'d(output)/d(var)':>16}" + "".join(f"{p:>13}" for p in PARAMETERS)
    lines = [f"Sensitivities ({args.mode}-mode AD), mu = {args.mu:g}, kn = {args.kn:g}, kt = {args.kt:g} "
             "N/mm; per degree for angles, per N/mm for kn/kt", head]
    for key in rows:
        d = payload[key]
        lines.append(f"{key:>16}" + "".join(f"{d[p]:13.5g}" for p in PARAMETERS))
    flags = [name for name in ("liftoff", "failed") if payload[name]]
    if not payload["converged"]:
        flags.append("not converged")
    if flags:
        lines.append("WARNING: " + ", ".join(flags) + ": these derivatives do not describe a damper.")
    emit(args, payload, "\n".join(lines))


def register_cli(sub) -> None:
    from .cli import add_contact_args, add_load_args, add_shape_args

    p = sub.add_parser("grad", help="derivatives of psi_BC, k_Re,BC, k_Im,BC, psi_fs, k_Re,fs "
                                    "w.r.t. the angles, b_R/h_R, 2b_L/h_L, mu, kn, kt (AD)")
    add_shape_args(p)
    p.add_argument("--mu", type=float, required=True, help="friction coefficient, > 0")
    add_contact_args(p)
    add_load_args(p)
    p.add_argument("--psi-a", type=float, default=None,
                   help="also differentiate k_Im at this amplitude, mrad")
    p.add_argument("--mode", choices=MODES, default="fwd",
                   help="AD mode: fwd (jax.jacfwd, default) or rev (jax.jacrev)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=cmd_grad)
