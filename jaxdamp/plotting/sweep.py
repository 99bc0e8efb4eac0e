"""Files of a design sweep: heatmaps (PNG, matplotlib's Agg canvas, no global backend change) and the
data (sweep.npz with every array, sweep.json with the same numbers as lists plus metadata)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..batch import SweepResult
from ..paper.files import atomic_file, save_figure, write_text
from ..status import RESULTS

HEATMAPS = (("psi_bc", "psi_BC (mrad)"), ("k_im_bc", "k_Im,BC (N mm/mrad)"), ("w_M", "w_M"))
# The heatmaps' status classes; "not converged" also holds singular and ill-conditioned points.
STATUS = ("valid", "liftoff", "not converged", "b_R undefined")
FAMILY_MARKS = ("90L", "74L", "60sym", "74R", "90R", "45sym")


def status_codes(res: SweepResult) -> np.ndarray:
    """Per point, from the status: 0 valid, 1 liftoff, 2 not converged / singular /
    ill-conditioned, 3 no centring b_R (shape (n_mu, n_l, n_r))."""
    status = np.asarray(res.summary.status)
    code = np.where(status == RESULTS.ok, 0, np.where(status == RESULTS.liftoff, 1, 2))
    code[np.broadcast_to(~res.br_found, code.shape)] = 3
    return code


def _edges(v):
    v = np.asarray(v, float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def _family(res: SweepResult):
    from ..geometry import paper_tables

    shapes = paper_tables()["shapes"]
    lo_l, hi_l = res.theta_l.min(), res.theta_l.max()
    lo_r, hi_r = res.theta_r.min(), res.theta_r.max()
    return [(n, shapes[n]["theta_l"], shapes[n]["theta_r"]) for n in FAMILY_MARKS
            if lo_l <= shapes[n]["theta_l"] <= hi_l and lo_r <= shapes[n]["theta_r"] <= hi_r]


def heatmap_figure(res: SweepResult):
    """One column per mu; rows psi_BC, k_Im,BC, w_M (valid points only) and the status map."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    n_mu = res.mu.size
    fig = Figure(figsize=(3.6 * n_mu + 1.0, 12.0), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(HEATMAPS) + 1, n_mu, squeeze=False, sharex=True, sharey=True)
    xe, ye = _edges(res.theta_r), _edges(res.theta_l)
    codes = status_codes(res)
    family = _family(res)
    status_cmap = ListedColormap(["#2ca02c", "#d62728", "#ff7f0e", "#7f7f7f"])
    for row, (field, label) in enumerate(HEATMAPS):
        data = np.ma.masked_where(codes != 0, getattr(res.summary, field))
        finite = data.compressed()
        # Robust colour limits: vertical flanks reach far larger values than the rest of the map.
        vmin, vmax = np.percentile(finite, [1, 99]) if finite.size else (0.0, 1.0)
        for k in range(n_mu):
            ax = axes[row, k]
            ax.set_facecolor("#d9d9d9")  # masked (liftoff, not converged, no b_R): grey
            mesh = ax.pcolormesh(xe, ye, data[k], vmin=vmin, vmax=vmax, cmap="viridis")
            ax.set_title(f"{label}, mu = {res.mu[k]:g}", fontsize=9)
        fig.colorbar(mesh, ax=axes[row, :], shrink=0.9, extend="both")
    for k in range(n_mu):
        ax = axes[-1, k]
        ax.pcolormesh(xe, ye, codes[k], vmin=-0.5, vmax=3.5, cmap=status_cmap)
        ax.set_title(f"status, mu = {res.mu[k]:g}", fontsize=9)
        ax.set_xlabel("theta_R (deg)")
    handles = [Patch(color=c, label=s) for c, s in zip(status_cmap.colors, STATUS)]
    fig.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=8)
    for ax in axes.ravel():
        for name, t_l, t_r in family:
            ax.plot(t_r, t_l, "w^", ms=5, mec="k", mew=0.6)
            # Label towards the inside of the map, so that shapes on its edge (90L, 90R) keep their
            # names inside the panel.
            right = t_r > 0.5 * (xe[0] + xe[-1])
            top = t_l > 0.5 * (ye[0] + ye[-1])
            ax.annotate(name, (t_r, t_l), xytext=(-4 if right else 4, -4 if top else 4),
                        textcoords="offset points", fontsize=7, color="k",
                        ha="right" if right else "left", va="top" if top else "bottom",
                        bbox=dict(boxstyle="round,pad=0.1", fc="white", alpha=0.8, lw=0))
    for ax in axes[:, 0]:
        ax.set_ylabel("theta_L (deg)")
    br = "b_R/h_R centred at mu_max = %g" % res.mu_max if res.mu_max is not None else \
        "b_R/h_R = %g" % float(res.br_over_hr.flat[0])
    fig.suptitle(f"Design sweep: {br}, 2b_L/h_L = {res.bl2_over_hl:g}, kn = {res.kn:g}, "
                 f"kt = {res.kt:g} N/mm\n(grey: not a valid damper; triangles: the paper's shapes)",
                 fontsize=10)
    return fig


def sweep_arrays(res: SweepResult) -> dict:
    arrays = {"theta_l": res.theta_l, "theta_r": res.theta_r, "mu": res.mu,
              "br_over_hr": res.br_over_hr, "br_found": res.br_found, "br_inside": res.br_inside,
              "status": status_codes(res), "valid": res.status == RESULTS.ok}
    arrays.update({f: np.asarray(v) for f, v in res.summary._asdict().items()})
    return arrays


def _json_values(arrays: dict) -> dict:
    """Per-point arrays as JSON lists. A number of a point that is not a valid damper (liftoff, not
    converged, no b_R) does not exist: null, as are non-finite values; the npz keeps the raw arrays."""
    from ..batch import DesignSummary

    valid = np.asarray(arrays["valid"], bool)
    numbers = {f for f in DesignSummary._fields if f not in ("converged", "liftoff", "failed",
                                                             "half_cycles")}
    out = {}
    for k, v in arrays.items():
        a = np.asarray(v)
        if a.dtype.kind == "f":
            keep = np.isfinite(a) & (valid if k in numbers else True)
            out[k] = np.where(keep, a, None).tolist()
        else:
            out[k] = a.tolist()
    return out


def write_sweep(res: SweepResult, out: Path, extra: dict | None = None) -> list[Path]:
    """Write sweep.npz, sweep.json and sweep.png into out; return the paths.

    extra: more top-level entries of sweep.json (the CLI's status, inputs and summary)."""
    out.mkdir(parents=True, exist_ok=True)
    arrays = sweep_arrays(res)
    npz = out / "sweep.npz"
    with atomic_file(npz, "wb") as f:
        np.savez_compressed(f, **arrays)
    meta = dict(extra or {})
    meta.update({"axes": "per-point arrays are indexed [mu, theta_l, theta_r]",
                 "units": {"theta": "deg", "psi": "mrad", "k": "N mm/mrad", "kn_kt": "N/mm",
                           "w": "dimensionless (Appendix C work shape factors)"},
                 "status_codes": dict(enumerate(STATUS)), "mu_max": res.mu_max,
                 "bl2_over_hl": res.bl2_over_hl, "kn": res.kn, "kt": res.kt,
                 "counts": {s: int((arrays["status"] == i).sum()) for i, s in enumerate(STATUS)}})
    meta["data"] = _json_values(arrays)
    js = out / "sweep.json"
    write_text(js, json.dumps(meta, allow_nan=False))
    png = out / "sweep.png"
    save_figure(heatmap_figure(res), png, dpi=110)
    return [npz, js, png]


__all__ = ["HEATMAPS", "STATUS", "FAMILY_MARKS", "status_codes", "heatmap_figure", "sweep_arrays",
           "write_sweep"]
