"""`jaxdamp optimize`: shape optimisation under the no-liftoff constraint.

A command of jaxdamp's CLI registered through the entry-point group `jaxdamp.commands`
(pyproject.toml: `optimize = "jaxdamp_optimize.cli:register"`), so jaxdamp itself never names it."""

from __future__ import annotations

from jaxdamp.cli import (CliError, add_contact_args, contacts_from_args, add_json_arg, add_progress_arg,
                         check_output_file, contacts_echo, document, emit, float_list, load_echo, save_figure,
                         progress_bar)

from .check import design_status
from .design import VARIABLES
from .robust_cli import add_robust_args


def _assignments(text: str | None, name: str) -> dict:
    out = {}
    for item in (text or "").split(","):
        if not item.strip():
            continue
        key, eq, val = item.partition("=")
        key = key.strip()
        if not eq:
            raise CliError(f"{name} entries must be NAME=VALUE; got {item!r}")
        try:
            out[key] = float(val)
        except ValueError:
            raise CliError(f"{name}: {key} needs a number; got {val!r}") from None
    return out


def payload_of(args) -> dict:
    """Run the optimisation described by parsed arguments; return the JSON payload."""
    from .design import design_space
    from .objectives import parse_objective
    from .problem import make_problem
    from .solver import SolverConfig, optimize

    contacts_from_args(args, shared=True)  # --kn/--kt or --contacts-from, checked
    fixed = _assignments(args.fix, "--fix")
    for key in fixed:
        if key not in VARIABLES:
            raise CliError(f"--fix names must be among {', '.join(VARIABLES)}; got {key!r}")
    # 2b_L/h_L is the paper's fixed 0.8 on one blade; over a row (--modes) it is free by default
    # (issue 61: the four shape variables; --fix bl2_over_hl=0.8 fixes it)
    row = getattr(args, "modes", None) is not None
    free = [v for v in VARIABLES if v not in fixed
            and (v != "bl2_over_hl" or args.free_bl2 or row)]
    if not free:
        raise CliError("every design variable is fixed: nothing to optimise")
    fixed_all = {k: v for k, v in fixed.items()}
    space = design_space(free, fixed=fixed_all)
    problem = make_problem(space, float_list(args.mu_set, "--mu-set"), args.kn, args.kt,
                           margin_pct=args.margin, min_vertex_deg=args.min_vertex_angle)
    if args.objective.startswith("peak:"):
        from .robust_cli import robust_payload

        return robust_payload(args, problem)
    weights = _assignments(args.weights, "--weights") or None
    config = SolverConfig(method=args.method, rounds=args.rounds)
    parse_objective(args.objective, weights)  # every input is checked before the work starts
    if args.grid_points < 2:
        raise CliError(f"--grid-points must be an integer >= 2; got {args.grid_points}")
    if args.plot:
        check_output_file("--plot", args.plot, (".png", ".pdf", ".svg"))
    bar = progress_bar(args, total=config.rounds, desc="optimize", unit="round")
    try:
        res = optimize(args.objective, problem, config=config, weights=weights,
                       progress=lambda rnd: bar.update(1))
    finally:
        bar.close()
    payload = {**res.shape, "objective_name": res.objective_name, "objective": res.objective,
               "units": res.units, "baseline": res.baseline, "feasible": res.feasible,
               "status": "ok" if res.feasible else design_status(res.check).name,
               "min_margin_pct": res.min_margin_pct, "margin_pct": problem.margin_pct,
               "min_vertex_deg": problem.min_vertex_deg,
               "mu_set": list(problem.mus), "kn": problem.kn, "kt": problem.kt,
               "evaluations": res.evaluations, "free": list(space.free), "reason": res.reason,
               "active_constraints": res.active, "method": config.method,
               "starts": [{"name": s.name, "best_objective": s.best_objective,
                           "evaluations": s.evaluations, "pruned": s.pruned} for s in res.starts],
               "history": res.history}
    if args.plot:
        import matplotlib.pyplot as plt  # the CLI's main() has chosen the Agg backend

        from .grid import grid_search

        from .plot import plot_paths

        grid = grid_search(res.objective_name, problem, points=args.grid_points, weights=weights)
        ax = plot_paths(res, grid)
        save_figure(ax.figure, args.plot, dpi=120, bbox_inches="tight")
        plt.close(ax.figure)
        payload["grid"] = {"best_objective": grid.best_value, "evaluations": grid.evaluations,
                           "best": None if grid.best_x is None else
                           dict(zip(space.free, map(float, grid.best_x)))}
        payload["plot"] = args.plot
    return payload


def _text(p: dict) -> str:
    shape = ", ".join(f"{k} = {p[k]:.4f}" for k in VARIABLES)
    head = "OPTIMUM" if p["feasible"] else "INFEASIBLE (no design returned as optimum)"
    lines = [f"{head}: {p['objective_name']} = {p['objective']:.6g} {p['units']} at {shape}",
             f"  baseline {p['baseline']['shape']}: {p['baseline']['objective']:.6g} {p['units']}",
             f"  mu set {', '.join(f'{m:g}' for m in p['mu_set'])}; required margin "
             f"{p['margin_pct']:g} % of L1-L2; achieved "
             + ("n/a" if p["min_margin_pct"] is None else f"{p['min_margin_pct']:.2f} %"),
             f"  evaluations: {p['evaluations']} (one = one design over the mu set, values and "
             f"gradients; method {p['method']})"]
    if p["reason"]:
        lines.append(f"  reason: {p['reason']}")
    if p["feasible"]:
        if p["active_constraints"]:
            lines.append("  active constraints:")
            lines += [f"    {a['constraint']}: {a['value']:.3f} {a['unit']}"
                      for a in p["active_constraints"]]
        else:
            lines.append("  active constraints: none (interior optimum)")
    for s in p["starts"]:
        best = "no feasible design" if s["best_objective"] is None else f"{s['best_objective']:.6g}"
        lines.append(f"  start {s['name']:6}: {best}  ({s['evaluations']} evaluations"
                     + (", pruned)" if s["pruned"] else ")"))
    if "grid" in p:
        g = p["grid"]
        lines.append(f"  grid search: best {g['best_objective']} with {g['evaluations']} "
                     f"evaluations; plot written to {p['plot']}")
    return "\n".join(lines)


def run(args) -> int:
    payload = payload_of(args)
    # infeasible: the returned design's worst cycle status, or liftoff where its cycles are ok but
    # the no-liftoff margins (every normal force positive, the left resultant inside L1-L2 with
    # the margin, at every mu of the set) fail (optimize.check.design_status, uncertified_status)
    doc = document(payload["status"], payload, contacts=contacts_echo(_contacts(args)),
                   load=load_echo(_load()))
    if payload["objective_name"].startswith("peak:"):
        from .robust_cli import robust_text, row_text

        emit(args, doc, (row_text if "modes" in payload else robust_text)(payload))
        return 0
    emit(args, doc, _text(payload))
    return 0


def _contacts(args):
    from jaxdamp import Contacts

    return Contacts(args.kn, args.kt)


def _load():
    from jaxdamp import LoadCase

    return LoadCase()  # make_problem's default: the reference load case


def register(sub):
    from .objectives import DEFAULT_OBJECTIVE
    from .problem import DEFAULT_MIN_VERTEX_DEG

    p = sub.add_parser(
        "optimize", help="shape optimisation under the no-liftoff constraint (optax)",
        description="Optimise theta_L, theta_R, b_R/h_R (optionally 2b_L/h_L) within theta in "
                    "[35, 90] deg, b_R/h_R in [-0.3, 0.4], 2b_L/h_L in [0.5, 0.9], keeping every normal "
                    "force positive and the left resultant inside L1-L2 with a margin, at both "
                    "full-slip ends and throughout the Base-Cycle, at every mu of the set. "
                    "Objectives NAME[:AGG]: NAME in k_im_bc (max), psi_bc (min), w_m (max), "
                    "combined; AGG in worst (default), mean, mu=X. Robust response objectives: "
                    "peak:worst, peak:q95 (A*/F over --force-n, --mu-set, --fd-spread, "
                    "--kn-range, --kt-range, --history).")
    p.add_argument("--objective", default=DEFAULT_OBJECTIVE,
                   help=f"objective NAME[:AGG] (default {DEFAULT_OBJECTIVE}: worst case of k_Im,BC over the mu set)")
    p.add_argument("--mu-set", default="0.3,0.5,0.7",
                   help="comma-separated friction coefficients, each in (0, 5] (default 0.3,0.5,0.7)")
    p.add_argument("--margin", type=float, default=5.0,
                   help="required distance of the left resultant from both pads, %% of L1-L2, in [0, 50) (default 5)")
    add_contact_args(p)
    p.add_argument("--min-vertex-angle", type=float, default=DEFAULT_MIN_VERTEX_DEG,
                   help="minimum vertex angle 180 - theta_L - theta_R, deg, in [0, 180) (default "
                        f"{DEFAULT_MIN_VERTEX_DEG:g}; w_M diverges as the wedge closes; 0 disables)")
    p.add_argument("--free-bl2", action="store_true",
                   help="make 2b_L/h_L a design variable too (the default with --modes; there "
                        "--fix bl2_over_hl=0.8 fixes it)")
    p.add_argument("--fix", default=None,
                   help="fix variables, e.g. theta_l=45,theta_r=45 (names: " + ", ".join(VARIABLES) + ")")
    p.add_argument("--weights", default=None,
                   help="combined-objective weights, e.g. k_im_bc=1,psi_bc=0.5,w_m=0 (default 1 each)")
    p.add_argument("--method", choices=("lbfgs", "adam"), default="lbfgs",
                   help="inner optax method (default lbfgs, projected, Armijo backtracking)")
    p.add_argument("--rounds", type=int, default=60, help="evaluation rounds per start (default 60)")
    p.add_argument("--plot", default=None, metavar="PNG",
                   help="also run the grid search and save the path plot over its heatmap")
    p.add_argument("--grid-points", type=int, default=15,
                   help="grid points per axis for --plot (default 15, then refined)")
    add_robust_args(p)
    add_json_arg(p)
    add_progress_arg(p)
    p.set_defaults(func=run)


__all__ = ["payload_of", "run", "register"]
