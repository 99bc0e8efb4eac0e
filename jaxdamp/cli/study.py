"""`jaxdamp study`: the paper's 60sym-family study (figures, tables, report, study.json)."""

from __future__ import annotations


from . import common as C
from . import exported


def register(sub) -> None:
    from ..paper.study import DEFAULT_SHAPES
    from ..plotting.drawing import MAX_FIGURE_PROCESSES

    p = sub.add_parser("study", help="the paper's 60sym-family study: figures, tables, report")
    p.add_argument("--out", default="study_out", help="output directory (default study_out)")
    p.add_argument("--shapes", default=",".join(DEFAULT_SHAPES),
                   help=f"comma-separated shape names (default {','.join(DEFAULT_SHAPES)})")
    p.add_argument("--mu", default="0.7,0.5,0.3", help="comma-separated friction coefficients (default 0.7,0.5,0.3)")
    p.add_argument("--kn", type=float, default=None, help="normal stiffness, N/mm (default: reference pair)")
    p.add_argument("--kt", type=float, default=None, help="tangential stiffness, N/mm (default: reference pair)")
    C.add_progress_arg(p)
    p.add_argument("--no-figures", action="store_true", help="skip the figures (numbers, tables, report only)")
    p.add_argument("--figure-processes", type=int, default=None, metavar="N",
                   help="worker processes drawing the figures while the study computes (default: one "
                        f"per core, at most {MAX_FIGURE_PROCESSES}; 0: draw in this process)")
    C.add_json_arg(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..params import Contacts, LoadCase
    from ..paper.study import check_study_inputs
    from ..plotting.study import run_study

    shapes = tuple(C.shape_name(s, "--shapes") for s in args.shapes.split(",") if s.strip())
    mus = C.float_list(args.mu, "--mu")
    kn, kt = check_study_inputs(shapes, mus, args.kn, args.kt)  # before the output path and any work
    if args.figure_processes is not None and args.figure_processes < 0:
        raise C.CliError(f"--figure-processes must be an integer in [0, inf); got {args.figure_processes}")
    out = C.check_output_dir("--out", args.out)
    # Every program through the saved-program cache: a repeat study neither traces nor lowers them
    # (tracing was ~29 s of a ~90 s repeat), and those shipped with the package serve a first one.
    summary = run_study(out, shapes, mus, kn, kt, progress=C.show_progress(args),
                        figures=not args.no_figures, figure_processes=args.figure_processes,
                        runner=exported.Runner("study"))
    crit = summary["paper_comparison"]["criterion"]
    lift = [f"{s} mu={m}" for s, per in summary["results"].items() for m, e in per.items() if e["liftoff"]]
    files = [out / "study.json", out / "report.md", out / "report.html"]
    lines = [f"wrote {', '.join(map(str, files))} ({len(summary['results'])} shapes, "
             f"{summary['meta']['runtime_s']:.1f} s)"]
    if crit["max_abs_dev_pct"] > 0:
        lines.append(f"Tables {'/'.join(crit['tables'])}: largest deviation {crit['max_abs_dev_pct']:.2f} % "
                     f"({'within' if crit['holds'] else 'OUTSIDE'} {crit['tol_pct']:g} %)")
    if lift:
        lines.append("LIFTOFF: " + ", ".join(lift))
    doc = C.document(summary["status"], {
        "results": summary["results"], "criterion": crit, "files": [str(f) for f in files],
        "runtime_s": summary["meta"]["runtime_s"]},
        shapes=list(shapes), mu=list(mus), contacts=C.contacts_echo(Contacts(kn, kt)),
        load=C.load_echo(LoadCase(*(summary["load"][k] for k in ("F_D", "q_star", "r_sin_beta")))))
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["register", "run"]
