"""`jaxdamp grad`: derivatives of the five numbers (and of k_Im at an amplitude) with respect to the
design variables, by forward- or reverse-mode AD through the solver."""

from __future__ import annotations

from . import common as C

# JSON key of each differentiated output and its field in jaxdamp.gradients' results.
JSON_OUTPUTS = (("psi_bc_mrad", "psi_bc"), ("k_im_bc", "k_im_bc"), ("k_re_bc", "k_re_bc"),
                ("psi_fs_mrad", "psi_fs"), ("k_re_fs", "k_re_fs"))
UNITS = ("derivative of the output (psi in mrad, k in N mm/mrad) per unit of the variable: per "
         "degree for theta_l/theta_r, per N/mm for kn/kt, per N for F_D, per mm for q_star and "
         "r_sin_beta")


def register(sub) -> None:
    from ..gradients import MODES

    p = sub.add_parser("grad", help="derivatives of psi_BC, k_Re,BC, k_Im,BC, psi_fs, k_Re,fs "
                                    "w.r.t. the angles, b_R/h_R, 2b_L/h_L, mu, kn, kt (AD)")
    C.add_design_args(p)
    p.add_argument("--psi-a", type=float, default=None, metavar="MRAD",
                   help="also differentiate k_Im at this amplitude, mrad, in [0, 1e9]")
    p.add_argument("--mode", choices=MODES, default="fwd",
                   help="AD mode: fwd (jax.jacfwd, default) or rev (jax.jacrev)")
    C.add_json_arg(p)
    p.set_defaults(func=run)


def _variables(d, exists: bool) -> dict:
    """A Design of derivatives as {variable: number or per-contact list} (None where the design
    does not exist as a damper)."""
    import numpy as np

    from ..gradients import by_name

    out = {}
    for name, value in by_name(d).items():
        arr = np.asarray(value, float)
        if not exists:
            out[name] = None if arr.ndim == 0 else [None] * arr.size
        else:
            out[name] = C.number(arr) if arr.ndim == 0 else [C.number(v) for v in arr]
    return out


def grad_payload(shape, mu, contacts, load, mode="fwd", psi_a_mrad=None) -> tuple[str, dict]:
    """(status, payload): one dict of derivatives per output keyed by variable, the values, flags.
    Derivatives and values of a design that lifts off (or whose system is singular) are None."""
    from ..gradients import five_numbers_jacobian, k_im_gradient_at, validate_psi_a
    from . import exported

    if psi_a_mrad is not None:
        validate_psi_a(psi_a_mrad)  # before the first Jacobian is computed
    # The Jacobian program is saved once (exported.call): a later process neither traces nor
    # lowers it (a reverse-mode trace took most of a repeat call's 4.5 s).
    runner = exported.Runner(f"grad_{mode}")

    jac = five_numbers_jacobian(shape, mu, contacts, load, mode, runner=runner)
    status = C.status_name(jac)
    exists = status not in ("liftoff", "singular", "ill_conditioned")
    payload = {key: _variables(getattr(jac.d, field), exists) for key, field in JSON_OUTPUTS}
    payload["values"] = {key: C.number(getattr(jac.values, field)) if exists else None
                         for key, field in JSON_OUTPUTS}
    if psi_a_mrad is not None:
        g = k_im_gradient_at(psi_a_mrad, shape, mu, contacts, load, mode, runner=runner)
        payload["k_im_at_psi_a"] = _variables(g.d, exists)
        payload["values"]["k_im_at_psi_a"] = C.number(g.k_im) if exists else None
        payload["psi_a_mrad"] = float(psi_a_mrad)
    payload.update(mode=mode, units=UNITS)
    return status, payload


def _cell(v) -> str:
    """A derivative for the text table: a number, or (R1, L1, L2) for per-contact stiffness."""
    if isinstance(v, list):
        return " (" + ", ".join("n/a" if x is None else f"{x:.4g}" for x in v) + ")"
    return f"{'n/a':>13}" if v is None else f"{v:13.5g}"


def run(args) -> int:
    from ..gradients import PARAMETERS

    contacts, load = C.contacts_from_args(args), C.load_from_args(args)  # --mu resolved here too
    shape = C.shape_from_args(args)
    status, payload = grad_payload(shape, args.mu, contacts, load, args.mode, args.psi_a)
    doc = C.document(status, payload, reason=C.status_reason(status, contacts, load),
                     shape=C.shape_echo(shape), mu=args.mu, contacts=C.contacts_echo(contacts),
                     load=C.load_echo(load))
    rows = [key for key, _ in JSON_OUTPUTS] + (["k_im_at_psi_a"] if args.psi_a is not None else [])
    lines = [f"Sensitivities ({args.mode}-mode AD), mu = {args.mu:g}, kn = {C.k_text(args.kn)}, kt = {C.k_text(args.kt)} "
             "N/mm; per degree for angles, per N/mm for kn/kt",
             f"{'d(output)/d(var)':>16}" + "".join(f"{p:>13}" for p in PARAMETERS)]
    for key in rows:
        d = payload[key]
        lines.append(f"{key:>16}" + "".join(_cell(d[p]) for p in PARAMETERS))
    if status != "ok":
        lines.append(f"WARNING: {status.replace('_', ' ')}: these derivatives do not describe a damper.")
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["JSON_OUTPUTS", "UNITS", "register", "grad_payload", "run"]
