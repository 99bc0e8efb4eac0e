"""`jaxdamp optimize --objective peak:worst|peak:q95`: the robust response design on the command
line (see `jaxdamp_optimize.robust_objective`). Flags are added by `jaxdamp_optimize.cli.register`."""

from __future__ import annotations

from jaxdamp.cli import CliError, check_output_file, progress_bar, save_figure

from .robust_objective import RobustSpec, optimize_robust, validate_spec

__all__ = ["add_robust_args", "robust_payload", "robust_text", "parse_force_range"]


def add_robust_args(p) -> None:
    p.add_argument("--force-n", default="2:20", metavar="FMIN:FMAX",
                   help="peak objectives: modal force range in N, 0 < FMIN <= FMAX (default 2:20)")
    p.add_argument("--fd-spread", type=float, default=0.2,
                   help="peak objectives: relative F_D spread, in [0, 1) (default 0.2)")
    p.add_argument("--kn-range", type=float, default=2.0,
                   help="peak objectives: kn varies by this factor each way, in [1, 100] (default 2)")
    p.add_argument("--kt-range", type=float, default=2.0,
                   help="peak objectives: kt varies by this factor each way, in [1, 100] (default 2)")
    p.add_argument("--history", default="band", choices=("gross_slip", "band"),
                   help="peak objectives: contact history, band (the larger peak of the gross-slip "
                        "and assembly histories; default: an optimum tuned to gross slip alone "
                        "was 1.95x worse from assembly) or gross_slip (about half the cost)")


def parse_force_range(text: str) -> tuple[float, float]:
    parts = str(text).split(":")
    try:
        vals = [float(x) for x in parts]
    except ValueError:
        raise CliError(f"--force-n must be FMIN:FMAX in N with 0 < FMIN <= FMAX; got {text!r}") from None
    if len(vals) == 1:
        vals = vals * 2
    if len(vals) != 2 or not 0 < vals[0] <= vals[1]:
        raise CliError(f"--force-n must be FMIN:FMAX in N with 0 < FMIN <= FMAX; got {text!r}")
    return vals[0], vals[1]


def robust_payload(args, problem) -> dict:
    """Check every flag, run the robust optimisation, return the JSON payload."""
    kind = args.objective.split(":", 1)[1]
    spec = validate_spec(RobustSpec(parse_force_range(args.force_n), args.fd_spread, args.kn_range,
                                    args.kt_range, args.history, kind))
    if args.plot:
        check_output_file("--plot", args.plot, (".png", ".pdf", ".svg"))
    bar = progress_bar(args, total=5, desc="robust", unit="stage")
    try:
        res = optimize_robust(problem, spec, progress=lambda n: bar.update(1))
    finally:
        bar.close()
    designs = [res.best] + list(res.references)
    payload = {"objective_name": f"peak:{kind}", "units": "mm/N", "feasible": res.best.feasible,
               "objective": res.objective_value, "spec": res.spec._asdict(),
               "mu_set": list(problem.mus), "kn": problem.kn, "kt": problem.kt,
               "free": list(problem.space.free), "grid_evaluations": res.grid_evaluations,
               "descent_evaluations": res.descent_evaluations,
               "designs": [{k: v for k, v in d._asdict().items() if k != "band_mm_per_n"}
                           for d in designs]}
    if args.plot:
        import matplotlib.pyplot as plt  # the CLI's main() has chosen the Agg backend

        from .robust_plot import plot_robust

        ax = plot_robust(designs)
        save_figure(ax.figure, args.plot, dpi=120, bbox_inches="tight")
        plt.close(ax.figure)
        payload["plot"] = args.plot
    return payload


def robust_text(p: dict) -> str:
    s = p["spec"]
    lines = [f"ROBUST {p['objective_name']} = {p['objective']:.5g} mm/N (descent), forces "
             f"{s['force_range_n'][0]:g}-{s['force_range_n'][1]:g} N, F_D +/-{s['fd_spread']:g}, kn x/÷"
             f"{s['kn_factor']:g}, kt x/÷{s['kt_factor']:g}, history {s['history']}, mu "
             + ",".join(f"{m:g}" for m in p["mu_set"]),
             "  independent re-evaluation (A*/F, mm/N): dense grid worst | MC worst | MC q95"]
    for d in p["designs"]:
        shape = ", ".join(f"{x:.4g}" for x in d["shape"])
        nums = (f"not certified: {d['reason']}" if not d["feasible"] else
                f"{d['worst_dense']:.4f} | {d['worst_mc']:.4f} | {d['q95_mc']:.4f}")
        lines.append(f"  {d['name']:40} ({shape}): {nums}")
    if "plot" in p:
        lines.append(f"  plot written to {p['plot']}")
    return "\n".join(lines)
