"""The optimiser's paths in the (theta_L, theta_R) plane over the grid-search heatmap."""

from __future__ import annotations

import numpy as np

from .grid import GridResult, heatmap


def plot_paths(result, grid: GridResult, ax=None, family=True, cmap="viridis"):
    """Heatmap of the best feasible objective over b_R/h_R (and 2b_L/h_L if free) on the level-0
    grid, with each start's accepted iterates, the optimum and the grid's best design.

    result: an OptimizationResult whose design space has theta_l and theta_r free. Returns the axes.
    """
    import matplotlib.pyplot as plt

    from jaxdamp import family_shape

    free = list(result.problem.space.free)
    if "theta_l" not in free or "theta_r" not in free:
        raise ValueError("plot_paths needs theta_l and theta_r among the free variables; "
                         f"got {free}")
    if tuple(grid.free) != tuple(free):
        raise ValueError(f"grid and result must share the design variables; got {grid.free} "
                         f"and {tuple(free)}")
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 5.4))
    xs, ys, Z = heatmap(grid, "theta_l", "theta_r")
    dx, dy = xs[1] - xs[0], ys[1] - ys[0]
    im = ax.imshow(np.ma.masked_invalid(Z), origin="lower", cmap=cmap, aspect="auto",
                   extent=[xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2])
    label = f"{result.objective_name} [{result.units}], best over the other variables"
    ax.figure.colorbar(im, ax=ax, label=label)
    ax.set_facecolor("0.85")  # no feasible design
    ix, iy = free.index("theta_l"), free.index("theta_r")
    colours = plt.get_cmap("tab10")
    for k, (name, path) in enumerate(result.paths.items()):
        if len(path) == 0:
            continue
        c = colours(k % 10)
        ax.plot(path[:, ix], path[:, iy], "-", color="white", lw=3.0, alpha=0.6)
        ax.plot(path[:, ix], path[:, iy], ".-", color=c, lw=1.4, ms=4)
        ax.plot(path[0, ix], path[0, iy], "o", mfc="none", mec=c, ms=8)
        ax.annotate(name, (path[0, ix], path[0, iy]), color=c, fontsize=8, fontweight="bold",
                    xytext=(4, 4), textcoords="offset points")
    if family:
        for name in ("90L", "74L", "60sym", "74R", "90R", "45sym"):
            s = family_shape(name)
            ax.plot(float(s.theta_l), float(s.theta_r), "x", color="black", ms=5)
    if grid.best_x is not None:
        ax.plot(grid.best_x[ix], grid.best_x[iy], "s", mfc="none", mec="orange", ms=10,
                label=f"grid best {grid.best_value:.4g} ({grid.evaluations} evaluations)")
    marker = "*" if result.feasible else "X"
    what = "optimum" if result.feasible else "least-violating (infeasible)"
    ax.plot(result.x[ix], result.x[iy], marker, color="black", mec="white", ms=14,
            label=f"{what} {result.objective:.4g} ({result.evaluations} evaluations)")
    ax.set_xlabel("theta_L [deg]")
    ax.set_ylabel("theta_R [deg]")
    ax.set_title("Optimiser paths over the grid-search heatmap (grey: no feasible design)",
                 fontsize=10)
    ax.legend(loc="lower left", fontsize=8)
    return ax


__all__ = ["plot_paths"]
