"""Named objectives and their aggregation over the friction set.

Metrics (computed together for every design and every mu of the set):

- ``k_im_bc``: k_Im at the Base-Cycle, N mm/mrad (maximise: damping at the Base-Cycle);
- ``psi_bc``: psi_BC, mrad (minimise: reach gross slip early, the paper's §3);
- ``w_m``: full-slip work shape factor w_M (maximise; Appendix C, from the full-slip statics).

An objective is ``NAME[:AGG]`` where NAME is a metric or ``combined`` and AGG is

- ``worst`` (default): the worst case over the mu set (min of a maximised metric, max of a
  minimised one), taken exactly: its gradient is that of the worst mu (a projected subgradient
  step at ties; the optimiser's decaying step handles the kink);
- ``mean``: the mean over the mu set;
- ``mu=X``: the value at one friction coefficient X (which must belong to the mu set, since the
  constraint is always imposed over the whole set).

``combined`` is the weighted sum  sum_i w_i s_i m_i / ref_i  with s_i = +1 (maximise) or -1
(minimise) and ref_i the 60sym baseline's mean of metric i over the mu set (dimensionless, to be
maximised); the default weights are 1 for each metric.

Internally every objective becomes a *score* to maximise, normalised by the magnitude of the
baseline's score so that the optimiser sees O(1) numbers whatever the units (k_Im is thousands of
N mm/mrad).
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

METRICS = ("k_im_bc", "psi_bc", "w_m")
SENSE = {"k_im_bc": 1.0, "psi_bc": -1.0, "w_m": 1.0}  # +1 maximise, -1 minimise
METRIC_UNITS = {"k_im_bc": "N mm/mrad", "psi_bc": "mrad", "w_m": "-"}
AGGREGATES = ("worst", "mean", "mu")
DEFAULT_OBJECTIVE = "k_im_bc:worst"
DEFAULT_WEIGHTS = {"k_im_bc": 1.0, "psi_bc": 1.0, "w_m": 1.0}


class Objective(NamedTuple):
    name: str  # canonical name, e.g. "k_im_bc:worst", "combined:mean", "psi_bc:mu=0.5"
    metric: str  # a METRICS entry or "combined"
    aggregate: str  # "worst", "mean" or "mu"
    mu: float | None  # for aggregate == "mu"
    weights: tuple  # ((metric, weight), ...) for combined

    @property
    def sense(self) -> float:
        """+1 if the reported value is maximised, -1 if minimised."""
        return 1.0 if self.metric == "combined" else SENSE[self.metric]

    @property
    def units(self) -> str:
        return "-" if self.metric == "combined" else METRIC_UNITS[self.metric]


def parse_objective(name: str = DEFAULT_OBJECTIVE, weights: dict | None = None) -> Objective:
    """Parse NAME[:AGG]; raises ValueError naming the valid choices."""
    if not isinstance(name, str) or not name:
        raise ValueError(f"objective must be a string NAME[:AGG]; got {name!r}")
    metric, _, agg = name.strip().partition(":")
    metric = metric.strip().lower()
    agg = (agg.strip() or "worst").lower()
    if metric not in METRICS + ("combined",):
        raise ValueError(f"objective NAME must be one of {', '.join(METRICS + ('combined',))}; "
                         f"got {metric!r}")
    mu = None
    if agg.startswith("mu="):
        try:
            mu = float(agg[3:])
        except ValueError:
            raise ValueError(f"objective aggregate mu=X needs a number X; got {agg!r}") from None
        if not (np.isfinite(mu) and mu > 0):
            raise ValueError(f"objective aggregate mu=X needs X > 0; got {agg!r}")
        agg, canon = "mu", f"{metric}:mu={mu:g}"
    elif agg in ("worst", "mean"):
        canon = f"{metric}:{agg}"
    else:
        raise ValueError(f"objective aggregate must be worst, mean or mu=X; got {agg!r}")
    w = ()
    if metric == "combined":
        given = dict(DEFAULT_WEIGHTS if weights is None else weights)
        for key, val in given.items():
            if key not in METRICS:
                raise ValueError(f"combined weights must name metrics among {', '.join(METRICS)}; "
                                 f"got {key!r}")
            if not (np.isfinite(val) and val >= 0):
                raise ValueError(f"combined weight {key} must be a finite number >= 0; got {val!r}")
        if not any(v > 0 for v in given.values()):
            raise ValueError("combined weights must include at least one positive weight")
        w = tuple((k, float(given.get(k, 0.0))) for k in METRICS)
    elif weights is not None:
        raise ValueError(f"weights apply to the combined objective only, not {metric!r}")
    return Objective(canon, metric, agg, mu, w)


def mu_index(objective: Objective, mus) -> int | None:
    if objective.aggregate != "mu":
        return None
    mus = np.asarray(mus, float)
    hit = np.nonzero(np.isclose(mus, objective.mu, rtol=0, atol=1e-12))[0]
    if hit.size == 0:
        raise ValueError(f"objective mu={objective.mu:g} must be one of the mu set "
                         f"{', '.join(f'{m:g}' for m in mus)}")
    return int(hit[0])


def per_mu_scores(objective: Objective, metrics, refs=None):
    """Score per mu (..., n_mu) to maximise, in the objective's own units (sense applied).

    metrics: (..., n_mu, len(METRICS)). refs: (len(METRICS),) normalisers for combined.
    """
    metrics = jnp.asarray(metrics)
    if objective.metric != "combined":
        return SENSE[objective.metric] * metrics[..., METRICS.index(objective.metric)]
    w = jnp.asarray([dict(objective.weights)[k] * SENSE[k] for k in METRICS])
    refs = jnp.ones(len(METRICS)) if refs is None else jnp.abs(jnp.asarray(refs))
    return jnp.sum(metrics * jnp.broadcast_to(w / refs, metrics.shape), axis=-1)


def aggregate(objective: Objective, scores, mus):
    """Aggregate per-mu scores (..., n_mu) -> (...,): worst case (exact min), mean, or one mu."""
    if objective.aggregate == "worst":
        return jnp.min(scores, axis=-1)
    if objective.aggregate == "mean":
        return jnp.mean(scores, axis=-1)
    return scores[..., mu_index(objective, mus)]


def score(objective: Objective, metrics, mus, refs=None):
    """The aggregated score (maximise), in the objective's units with the sense applied."""
    return aggregate(objective, per_mu_scores(objective, metrics, refs), mus)


def reported_value(objective: Objective, score_value):
    """The objective as reported: the metric's own value (e.g. psi_BC in mrad, not its negative)."""
    return objective.sense * score_value if objective.metric != "combined" else score_value


def combined_refs(baseline_metrics):
    """Normalisers of the combined objective: the baseline's mean of each metric over the mu set."""
    refs = np.mean(np.asarray(baseline_metrics, float), axis=-2)
    return np.where(np.abs(refs) > 1e-12, refs, 1.0)


__all__ = ["METRICS", "SENSE", "METRIC_UNITS", "AGGREGATES", "DEFAULT_OBJECTIVE",
           "DEFAULT_WEIGHTS", "Objective", "parse_objective", "mu_index", "per_mu_scores",
           "aggregate", "score", "reported_value", "combined_refs"]
