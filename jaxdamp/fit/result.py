"""The loop fit's result (`LoopFit`) and its uncertainty: which parameters the loops identify,
their covariance and CONFIDENCE intervals (`identify`), from the residuals' Jacobian at the
optimum. numpy only; `solve.py` runs the fit."""

from __future__ import annotations

from statistics import NormalDist
from typing import NamedTuple

import numpy as np

from ..status import RESULTS, number_repr, status_repr
from .loops import MomentLoop

__all__ = ["LoopFit", "identify", "z_value", "CONFIDENCE", "MAX_SPAN", "NULL_RCOND", "NULL_LOADING"]

MAX_SPAN = 4.0  # an interval wider than a factor 4 (hi / lo) is no measurement of the parameter
NULL_RCOND = 1e-7  # singular values below this fraction of the largest: null directions
NULL_LOADING = 0.1  # a parameter with a component above this in a null direction is in it
CONFIDENCE = 0.95


class LoopFit(NamedTuple):
    """The fitted contact parameters and their uncertainty (`fit_loops`).

    names: the parameters (mu, kn, kt per their grouping, then offset_0...); value, se, lo, hi:
    per parameter, NaN where not identifiable (mu dimensionless, kn, kt in N/mm, offsets in N mm;
    lo, hi: the CONFIDENCE interval); correlation: (p, p), NaN rows for the unidentified ones.
    identifiable: bool per parameter; why: per parameter, "" or the reason it is not identifiable.
    mu, kn, kt: the fitted values as the solver takes them (mu a number or (3,), kn, kt (3,) N/mm),
    including unidentified ones at the value the solver ended on (to run the model, not as results).
    """

    names: list
    value: np.ndarray
    se: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    correlation: np.ndarray
    identifiable: np.ndarray
    why: list
    mu: object
    kn: np.ndarray
    kt: np.ndarray
    offsets: np.ndarray  # per loop: N mm (moment loop) or N (contact loop)
    sigma: float  # residual standard deviation (robust stage, rescaled residuals), N mm or N; NaN
    # where moment and contact loops are fitted together (no common unit)
    rms: np.ndarray  # per loop, plain rms residual at the optimum (N mm or N)
    loops: list  # the MomentLoop or ContactLoop of each input
    fitted: list  # per loop, the model moment (N mm) or force (N), offset included, at each sample
    statuses: np.ndarray  # RESULTS code of each loop's model cycle at the optimum
    steps: list  # LM steps per stage
    history: list  # (stage, step, loss) as the solver went
    spec: tuple  # the FitSpec
    initial: str
    status: int  # RESULTS code: the first invalid model cycle's, else not_converged where the
    # solver stopped short of its tolerance, else ok
    held: list  # the names not identified (their values are where the solver ended, no result)
    monotone: np.ndarray  # per loop: False for a tangential contact loop whose model displacement
    # is not monotone along a half at the optimum (its force is then not a function of it there)

    def __repr__(self) -> str:
        """One or two lines: status by name, each contact parameter with its unit and standard
        error (or 'not identifiable'), the residual sd and the number of loops."""
        try:
            parts = []
            for n, v, se, ok in zip(self.names, np.asarray(self.value, float), np.asarray(self.se, float),
                                    np.asarray(self.identifiable, bool)):
                if n.startswith("offset"):
                    continue
                unit = "" if n.startswith("mu") else " N/mm"
                parts.append(f"{n}={v:.5g} ± {se:.2g}{unit}" if ok else f"{n}=not identifiable")
            loops = list(self.loops)
            unit = "N mm" if all(isinstance(lp, MomentLoop) for lp in loops) else "N"
            mixed = not loops or not np.isfinite(float(self.sigma))  # moment and contact loops: no sd
            tail = f"sigma={number_repr(self.sigma, '' if mixed else unit)}, loops={len(loops)}"
            body = ", ".join(parts + [tail])
        except Exception:  # noqa: BLE001 - a repr must not raise (a hand-built or traced LoopFit)
            body = "<unavailable>"
        return f"LoopFit(status={status_repr(self.status)}, {body})"

    def as_dict(self) -> dict:
        """Plain-Python view (floats, lists; None where a number does not exist)."""
        f = lambda v: None if v is None or not np.isfinite(v) else float(v)  # noqa: E731
        params = {}
        for i, n in enumerate(self.names):
            params[n] = {"value": f(self.value[i]), "se": f(self.se[i]), "lo": f(self.lo[i]),
                         "hi": f(self.hi[i]), "identifiable": bool(self.identifiable[i]),
                         "why": self.why[i] or None}
        return {"parameters": params, "correlation": [[f(v) for v in row] for row in self.correlation],
                "sigma_nmm": f(self.sigma), "rms_nmm": [f(v) for v in self.rms],
                "steps": self.steps,
                "status": RESULTS.name_of(self.status)}


def identify(jac, sigma2, names, n_phys):
    """(identifiable (p,) bool, why (p,) reasons, covariance (p, p), NaN for the unidentified) from
    the residuals' Jacobian (n, p) at the optimum and the residual variance sigma2. The first n_phys
    parameters are logs (their interval spans exp(2 z se)). A parameter with a component above
    NULL_LOADING in a direction whose singular value is below NULL_RCOND of the largest is not
    identifiable, nor is a log-parameter whose interval would span more than MAX_SPAN. The
    covariance is sigma2 (J^T J)^+ (pseudo-inverse with the null directions cut): for a parameter
    outside the null directions it is its full variance, the weakly determined directions
    included; nothing is held fixed."""
    p = jac.shape[1]
    ok = np.ones(p, bool)
    why = [""] * p
    _, s, vt = np.linalg.svd(jac, full_matrices=False)
    if not s[0] > 0.0:
        return ok & False, ["not identifiable: the loops carry no information on it (zero Jacobian)"] * p, \
            np.full((p, p), np.nan)
    for k in np.nonzero(s < NULL_RCOND * s[0])[0]:
        involved = np.nonzero(np.abs(vt[k]) > NULL_LOADING)[0]
        for j in involved:
            if ok[j]:
                others = [names[i] for i in involved if i != j]
                why[j] = ("not identifiable: the loops constrain only a combination of it"
                          + (f" with {', '.join(others)}" if others else " (it does not change them)")
                          + " (a null direction of the Jacobian)")
            ok[j] = False
    keep = s >= NULL_RCOND * s[0]
    vk = vt[keep]
    cov = sigma2 * (vk.T / s[keep] ** 2) @ vk
    se = np.sqrt(np.maximum(np.diag(cov), 0.0))
    z = z_value()
    for j in range(min(n_phys, p)):
        span = float(np.exp(min(2 * z * se[j], 700.0)))
        if ok[j] and span > MAX_SPAN:
            why[j] = (f"not identifiable from these loops: its {CONFIDENCE:.0%} interval would span a "
                      f"factor {span:.3g} (more than {MAX_SPAN:g})")
            ok[j] = False
    cov[~ok, :] = np.nan
    cov[:, ~ok] = np.nan
    return ok, why, cov


def z_value() -> float:
    """The standard normal quantile of the two-sided CONFIDENCE interval."""
    return NormalDist().inv_cdf(0.5 + CONFIDENCE / 2)
