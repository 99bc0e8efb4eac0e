"""The paper's family as reference: the 60sym baseline (objective normaliser) and the family table."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from jaxdamp import family_shape

from .design import VARIABLES
from .objectives import Objective, combined_refs, reported_value, score
from .problem import Problem, evaluate_shapes, is_feasible, min_margin_pct

BASELINE = "60sym"
FAMILY_NAMES = ("90L", "74L", "60sym", "74R", "90R", "45sym")


class Scorer(NamedTuple):
    """How to turn metrics into the optimiser's normalised score (maximise)."""

    objective: Objective
    mus: tuple
    refs: np.ndarray  # combined-objective normalisers (baseline mean of each metric)
    scale: float  # |baseline score|: the optimiser sees score / scale
    baseline_value: float  # the baseline's objective, as reported (metric units)

    def score(self, metrics):
        """Aggregated score (maximise) in the objective's units; metrics (..., n_mu, 3)."""
        return np.asarray(score(self.objective, metrics, self.mus, self.refs))

    def value(self, metrics):
        """The objective as reported (e.g. psi_BC in mrad)."""
        return np.asarray(reported_value(self.objective, self.score(metrics)))

    def value_of_score(self, score_value):
        """Reported value of an (unnormalised) score."""
        return float(reported_value(self.objective, score_value))


def shape_vector(name: str) -> np.ndarray:
    s = family_shape(name)
    return np.array([float(getattr(s, n)) for n in VARIABLES])


def evaluate_family(problem: Problem, names=FAMILY_NAMES):
    """Evaluation of complete family shapes (their own 2b_L/h_L) over the problem's mu set."""
    return evaluate_shapes(problem, np.array([shape_vector(n) for n in names]))


def make_scorer(problem: Problem, objective: Objective) -> tuple[Scorer, int]:
    """Scorer normalised by the 60sym baseline; also returns the evaluations it used (1)."""
    ev = evaluate_family(problem, (BASELINE,))
    metrics = ev.metrics[0]
    refs = combined_refs(metrics)
    raw = float(score(objective, metrics, problem.mus, refs))
    scale = abs(raw) if abs(raw) > 1e-9 else 1.0
    return Scorer(objective, problem.mus, refs, scale, float(reported_value(objective, raw))), 1


def family_table(problem: Problem, scorer: Scorer, names=FAMILY_NAMES) -> list[dict]:
    """Objective and feasibility (same mu set and margin) of each family shape."""
    ev = evaluate_family(problem, names)
    feas = is_feasible(ev)
    values = scorer.value(ev.metrics)
    margins = min_margin_pct(ev)
    return [{"shape": n, "objective": float(v), "feasible": bool(f), "min_margin_pct": float(m)}
            for n, v, f, m in zip(names, values, feas, margins)]


__all__ = ["BASELINE", "FAMILY_NAMES", "Scorer", "shape_vector", "evaluate_family", "make_scorer",
           "family_table"]
