"""`jaxdamp statics`: full-slip contact forces at cycle start and mid-cycle (forces / F_D)."""

from __future__ import annotations

from . import common as C


def register(sub) -> None:
    p = sub.add_parser("statics", help="full-slip contact forces at cycle start and mid-cycle")
    C.add_shape_args(p)
    p.add_argument("--mu", type=float, required=True, help="friction coefficient, in (0, 5]")
    C.add_json_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..params import validate_mu
    from ..statics import full_slip_statics

    shape = C.shape_from_args(args)
    validate_mu(args.mu)
    st = full_slip_statics(shape, args.mu)
    status = C.status_name(st)
    solvable = status != "singular"

    def end(s):
        # forces of a singular system do not exist; a liftoff's forces do (they show the liftoff)
        ok = solvable
        return {"N": C.named(s.N) if ok else None, "T": C.named(s.T) if ok else None,
                "resultant_pos_pct": C.number(s.resultant_pos_pct) if ok else None}

    doc = C.document(status, {"start": end(st.start), "mid": end(st.mid), "liftoff": status == "liftoff",
                              "min_normal_over_fd": C.number(st.min_normal_over_fd) if solvable else None},
                     shape=C.shape_echo(shape), mu=args.mu)  # under "inputs"
    lines = [f"Full-slip statics, mu = {args.mu:g} (forces in units of F_D)",
             f"{'':12}{'N_R1':>9}{'N_L1':>9}{'N_L2':>9}{'T_R1':>9}{'T_L1':>9}{'T_L2':>9}  resultant (% L1->L2)"]
    for label, s in (("cycle start", st.start), ("mid-cycle", st.mid)):
        nums = "".join(f"{float(v):9.4f}" for v in list(s.N) + list(s.T))
        lines.append(f"{label:12}{nums}  {float(s.resultant_pos_pct):8.2f}")
    lines.append(f"min normal force / F_D = {float(st.min_normal_over_fd):.4f}; "
                 f"liftoff: {'YES' if status == 'liftoff' else 'no'}")
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["register", "run"]
