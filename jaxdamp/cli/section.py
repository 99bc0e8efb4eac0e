"""`jaxdamp section`: the section with pads, D, R and the full-slip lines of action (Fig. 7)."""

from __future__ import annotations

from . import common as C

SUFFIXES = (".png", ".pdf", ".svg")


def register(sub) -> None:
    p = sub.add_parser("section", help="plot the section with pads, D, R and full-slip lines of action (Fig. 7)")
    C.add_shape_args(p)
    p.add_argument("--mu", type=float, required=True, help="friction coefficient, in (0, 5]")
    p.add_argument("--end", choices=("start", "mid", "both"), default="both",
                   help="cycle start, mid-cycle or both panels (default both)")
    p.add_argument("--out", default="section.png", help="image file (.png, .pdf, .svg; default section.png)")
    C.add_json_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..params import validate_mu
    from ..plotting import plot_section
    from ..statics import full_slip_statics

    shape = C.shape_from_args(args)
    validate_mu(args.mu)
    out = C.check_output_file("--out", args.out, SUFFIXES)
    # The figure draws the full-slip statics; the status is theirs (liftoff: 74L at mu 0.7).
    status = C.status_name(full_slip_statics(shape, args.mu))
    fig = plot_section(shape, args.mu, end=args.end)
    C.save_figure(fig, out, dpi=110)
    import matplotlib.pyplot as plt

    plt.close(fig)
    doc = C.document(status, {"files": [str(out)]}, shape=C.shape_echo(shape), mu=args.mu)
    C.emit(args, doc, f"wrote {out}")
    return 0


__all__ = ["SUFFIXES", "register", "run"]
