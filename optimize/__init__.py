"""Shape optimisation of underplatform dampers with optax, under the no-liftoff constraint.

    import jaxdamp as jd, optimize as opt
    jd.enable_x64()
    res = opt.optimize()                        # robust (worst over mu = 0.3, 0.5, 0.7) k_Im,BC
    res.feasible, res.shape, res.objective, res.active, res.evaluations
    grid = opt.grid_search(problem=res.problem)  # brute-force reference over the same bounds
    opt.plot_paths(res, grid)

Modules: `design` (variables, bounds, unit box, projection), `objectives` (named objectives and
their aggregation over mu), `constraints` (margins g >= 0 from the statics and the Base-Cycle),
`problem` (batched, compiled evaluators; what one evaluation is), `augmented` (PHR augmented
Lagrangian), `solver` (optax L-BFGS / Adam inner loop, multi-start, history), `check` (final
re-check by the public API, active constraints, infeasibility reasons), `grid` (brute-force
search, heatmap), `reference` (60sym baseline, family table), `plot`, `cli` (`jaxdamp optimize`).
"""

from .check import DesignCheck, active_constraints, check_design
from .design import DEFAULT_BOUNDS, VARIABLES, DesignSpace, design_space
from .grid import GridResult, grid_search, heatmap
from .objectives import DEFAULT_OBJECTIVE, METRICS, Objective, parse_objective
from .plot import plot_paths
from .problem import (DEFAULT_MARGIN_PCT, DEFAULT_MIN_VERTEX_DEG, DEFAULT_MU_SET, Evaluation,
                      Problem, evaluate, is_feasible, make_problem)
from .reference import family_table, make_scorer
from .solver import OptimizationResult, SolverConfig, optimize

__all__ = [name for name, value in dict(globals()).items()
           if not name.startswith("_") and not isinstance(value, type(__import__("sys")))]
