"""`jaxdamp design-br`: the b_R/h_R that centres the left resultant at mu_max (the paper's §3 rule).

b_R/h_R is what this command computes, so it takes no --br (a custom shape is --theta-l/--theta-r)."""

from __future__ import annotations

from . import common as C


def register(sub) -> None:
    p = sub.add_parser("design-br", help="the b_R/h_R that centres the left resultant at mu_max (§3)")
    C.add_shape_args(p, with_br=False)
    p.add_argument("--mu-max", type=float, default=0.7,
                   help="highest friction coefficient, in (0, 5] (default 0.7)")
    C.add_json_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..params import validate_mu
    from ..statics import design_br

    shape = C.shape_from_args(args, need_br=False)
    validate_mu(args.mu_max, "mu_max")
    res = design_br(shape, args.mu_max)
    # no root: b_R does not exist; liftoff: it exists but every b_R lifts off at mu_max
    status = C.status_name(res)
    found, inside = status != "no_root", status == "ok"
    echo = C.shape_echo(shape)
    echo.pop("br_over_hr")
    doc = C.document(status, {"br_over_hr": C.number(res.br_over_hr) if found else None,
                              "found": found, "margin_pct": C.number(res.margin_pct) if found else None,
                              "inside": inside},
                     shape=echo, mu_max=args.mu_max)
    if not found:
        text = f"no b_R/h_R in [-0.45, 0.45] centres the left resultant at mu_max = {args.mu_max:g}"
    else:
        text = (f"b_R/h_R = {float(res.br_over_hr):.4f} centres the left resultant at mu_max = "
                f"{args.mu_max:g}: {float(res.margin_pct):.2f} % of L1-L2 from the nearer pad at both ends"
                + ("" if inside else "  (OUTSIDE L1-L2: no b_R avoids liftoff)"))
    C.emit(args, doc, text)
    return 0


__all__ = ["register", "run"]
