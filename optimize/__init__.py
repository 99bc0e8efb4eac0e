"""Shape optimisation of underplatform dampers with optax, under the no-liftoff constraint.

    import jaxdamp as jd, jaxdamp_optimize as opt
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
search, heatmap), `reference` (60sym baseline, family table), `descent` (the feasible descent of
the response and robust objectives), `plot`, `cli` (`jaxdamp optimize`).
"""

from .amplitude_objective import k_im_at_amplitude as k_im_at_amplitude
from .amplitude_objective import robust_k_im as robust_k_im
from .check import DesignCheck as DesignCheck
from .check import active_constraints as active_constraints
from .check import check_design as check_design
from .design import DEFAULT_BOUNDS as DEFAULT_BOUNDS
from .design import DesignSpace as DesignSpace
from .design import VARIABLES as VARIABLES
from .design import design_of as design_of
from .design import design_space as design_space
from .design import unit_of as unit_of
from .grid import GridResult as GridResult
from .grid import grid_search as grid_search
from .grid import heatmap as heatmap
from .objectives import DEFAULT_OBJECTIVE as DEFAULT_OBJECTIVE
from .objectives import METRICS as METRICS
from .objectives import Objective as Objective
from .objectives import parse_objective as parse_objective
from .plot import plot_paths as plot_paths
from .problem import DEFAULT_MARGIN_PCT as DEFAULT_MARGIN_PCT
from .problem import DEFAULT_MIN_VERTEX_DEG as DEFAULT_MIN_VERTEX_DEG
from .problem import DEFAULT_MU_SET as DEFAULT_MU_SET
from .problem import Evaluation as Evaluation
from .problem import Problem as Problem
from .problem import evaluate as evaluate
from .problem import is_feasible as is_feasible
from .problem import make_problem as make_problem
from .reference import family_table as family_table
from .reference import make_scorer as make_scorer
from .solver import OptimizationResult as OptimizationResult
from .solver import SolverConfig as SolverConfig
from .solver import optimize as optimize


__all__ = ["k_im_at_amplitude", "robust_k_im", "DesignCheck", "active_constraints",
           "check_design", "DEFAULT_BOUNDS", "DesignSpace", "VARIABLES", "design_of",
           "design_space", "unit_of", "GridResult", "grid_search", "heatmap", "DEFAULT_OBJECTIVE",
           "METRICS", "Objective", "parse_objective", "plot_paths", "DEFAULT_MARGIN_PCT",
           "DEFAULT_MIN_VERTEX_DEG", "DEFAULT_MU_SET", "Evaluation", "Problem", "evaluate",
           "is_feasible", "make_problem", "family_table", "make_scorer", "OptimizationResult",
           "SolverConfig", "optimize"]
