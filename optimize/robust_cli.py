"""`jaxdamp optimize --objective peak:worst|peak:q95`: the robust response design on the command
line (see `jaxdamp_optimize.robust_objective`). Flags are added by `jaxdamp_optimize.cli.register`."""

from __future__ import annotations

from jaxdamp.cli import CliError, check_output_file, progress_bar, save_figure
from jaxdamp.cli.response_row import add_row_args

from .robust_objective import RobustSpec, optimize_robust, validate_spec
from .row_objective import CORNER_CHOICES

__all__ = ["add_robust_args", "robust_payload", "robust_text", "parse_force_range", "row_text"]


def add_robust_args(p) -> None:
    p.add_argument("--force-n", default="2:20", metavar="FMIN:FMAX",
                   help="peak objectives: modal force range in N, 0 < FMIN <= FMAX (default 2:20)")
    p.add_argument("--fd-spread", type=float, default=0.2,
                   help="peak objectives: relative F_D spread, in [0, 1) (default 0.2)")
    p.add_argument("--kn-range", type=float, default=2.0,
                   help="peak objectives: kn varies by this factor each way, in [1, 100] (default 2)")
    p.add_argument("--kt-range", type=float, default=2.0,
                   help="peak objectives: kt varies by this factor each way, in [1, 100] (default 2)")
    p.add_argument("--history", default="band", choices=("gross_slip", "band", "assembly"),
                   help="peak objectives: contact history, band (the larger peak of the gross-slip "
                        "and assembly histories; default: an optimum tuned to gross slip alone "
                        "was 1.95x worse from assembly), gross_slip (about half the cost) or, with "
                        "--modes, assembly (half the cost)")
    add_row_args(p)
    p.add_argument("--corners", default="nominal", choices=CORNER_CHOICES,
                   help="with --modes: the descent's contact stiffness, the nominal kn, kt "
                        "(default) or also every (kn, kt) corner of --kn-range, --kt-range (5x "
                        "the cost; the certification covers them either way)")
    p.add_argument("--references", action="store_true",
                   help="with --modes: also certify 60sym and the in-phase robust optimum on the "
                        "optimum's grid, for comparison (each costs what the optimum's "
                        "certification does: about 3 min on 2 cores for the example row)")


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
    spec = RobustSpec(parse_force_range(args.force_n), args.fd_spread, args.kn_range,
                      args.kt_range, args.history, kind)
    if args.modes is not None:
        return _row_payload(args, problem, spec)
    if (args.h_l is not None or args.engine_order != "all" or args.corners != "nominal"
            or args.references):
        raise CliError("--engine-order, --h-l, --corners and --references need --modes FILE (the "
                       "blade row)")
    spec = validate_spec(spec)
    if args.plot:
        check_output_file("--plot", args.plot, (".png", ".pdf", ".svg"))
    bar = progress_bar(args, total=5, desc="robust", unit="stage")
    try:
        res = optimize_robust(problem, spec, progress=lambda n: bar.update(1))
    finally:
        bar.close()
    designs = [res.best] + list(res.references)
    payload = {"objective_name": f"peak:{kind}", "units": "mm/N", "feasible": res.best.feasible,
               "status": res.best.status,
               "objective": res.objective_value, "spec": res.spec._asdict(),
               "mu_set": list(problem.mus), "kn": problem.kn, "kt": problem.kt,
               "free": list(problem.space.free), "grid_evaluations": res.grid_evaluations,
               "descent_evaluations": res.descent_evaluations,
               "designs": [{k: v for k, v in d._asdict().items() if k != "band_mm_per_n"}
                           for d in designs]}
    return _with_plot(args, payload, "plot_robust", designs)


def _with_plot(args, payload: dict, plot_name: str, designs) -> dict:
    """Draw the designs with robust_plot's `plot_name` into --plot (checked before the run)."""
    if args.plot:
        import matplotlib.pyplot as plt  # the CLI's main() has chosen the Agg backend

        from . import robust_plot

        ax = getattr(robust_plot, plot_name)(designs)
        save_figure(ax.figure, args.plot, dpi=120, bbox_inches="tight")
        plt.close(ax.figure)
        payload["plot"] = args.plot
    return payload


def _row_payload(args, problem, spec) -> dict:
    """`--modes`: the worst peak over the row's engine orders (`row_objective.optimize_row`)."""
    from jaxdamp import engine_orders_of
    from jaxdamp.modal_file import load_modal_family

    from .row_objective import FORCE_CHUNK, ROW_HISTORIES, optimize_row

    if spec.objective != "worst":
        raise CliError(f"--objective must be peak:worst with --modes; got peak:{spec.objective}")
    # The descent's forces: one row call's worth (each row call holds FORCE_CHUNK forces).
    spec = validate_spec(spec._replace(n_forces=FORCE_CHUNK), ROW_HISTORIES)
    if args.h_l is None:
        raise CliError("--h-l must be given with --modes: the damper's left flank length in "
                       "(0, 10000] mm")
    if args.plot:
        check_output_file("--plot", args.plot, (".png", ".pdf", ".svg"))
    family = load_modal_family(args.modes)
    orders = engine_orders_of(args.engine_order, family.n_blades)
    bar = progress_bar(args, total=4 if args.references else 3, desc="robust row", unit="stage")
    try:
        res = optimize_row(family, orders, args.h_l, problem, spec, corners=args.corners,
                           certify_references=args.references, progress=lambda n: bar.update(1))
    finally:
        bar.close()
    designs = [res.best] + list(res.references)
    payload = {"objective_name": "peak:worst", "units": "mm/N", "feasible": res.best.feasible,
               "status": res.best.status,
               "objective": res.objective_value, "spec": res.spec._asdict(),
               "modes": family.name or str(args.modes), "n_blades": family.n_blades,
               "engine_orders": orders, "h_l_mm": args.h_l, "corners": res.corners,
               "mu_set": list(problem.mus), "kn": problem.kn, "kt": problem.kt,
               "free": list(problem.space.free), "grid_evaluations": res.grid_evaluations,
               "descent_evaluations": res.descent_evaluations,
               "designs": [d._asdict() for d in designs]}
    return _with_plot(args, payload, "plot_row", designs)


def row_text(p: dict) -> str:
    s = p["spec"]
    lines = [f"ROBUST ROW peak:worst = {p['objective']:.5g} mm/N (the descent's smooth maximum), "
             f"{p['modes']} "
             f"({p['n_blades']} blades), engine orders {p['engine_orders'][0]}-"
             f"{p['engine_orders'][-1]}, h_L {p['h_l_mm']:g} mm, forces "
             f"{s['force_range_n'][0]:g}-{s['force_range_n'][1]:g} N, F_D +/-{s['fd_spread']:g}, kn x/÷"
             f"{s['kn_factor']:g}, kt x/÷{s['kt_factor']:g}, history {s['history']}, mu "
             + ",".join(f"{m:g}" for m in p["mu_set"]),
             "  re-evaluated at every engine order (worst A*/F over the grid, mm/N): "
             "band | gross slip | assembly, and where"]
    for d in p["designs"]:
        shape = ", ".join(f"{x:.4g}" for x in d["shape"])
        if not d["feasible"]:
            lines.append(f"  {d['name']:32} ({shape}): not certified: {d['reason']}")
            continue
        gs, asm = (max((x for x in d["worst_by_history"][h] if x is not None), default=None)
                   for h in ("gross_slip", "assembly"))
        nums = " | ".join("-" if x is None else f"{x:.4f}" for x in (d["worst"], gs, asm))
        w = d.get("worst_scenario")
        where = ("" if not w else f" (mu {w['mu']:g}, kn x{w['kn_factor']:.3g}, kt "
                 f"x{w['kt_factor']:.3g}, F_D {w['fd_n']:g} N, {w['force_n']:.3g} N, "
                 f"{w['history']})")
        lines.append(f"  {d['name']:32} ({shape}): {nums} at engine order "
                     f"{d['worst_engine_order']}{where}")
    if "plot" in p:
        lines.append(f"  plot written to {p['plot']}")
    return "\n".join(lines)


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
