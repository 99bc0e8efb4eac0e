"""The look shared by every figure: colours per mu and per contact, the psi axis label, the axes
row and the legend below it, the panel of a design that lifted off. Figures import these; a new
figure starts here so that it looks like the others."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib.pyplot as plt
import numpy as np

from ..status import RESULTS

__all__ = ["PSI_LABEL", "MU_COLORS", "CONTACT_COLORS", "mu_color", "as_numpy", "as_cycles",
           "axes_row", "finish_figure", "legend_below", "liftoff_panel", "cycle_panel",
           "shape_name"]

# psi_c: the centre of the rotation cycle (psi_P runs between psi_c - psi_a and psi_c + psi_a).
PSI_LABEL = "platform rotation about the cycle centre ψ_c: ψ_P − ψ_c (mrad)"
MU_COLORS = {0.7: "tab:blue", 0.5: "tab:orange", 0.3: "tab:green"}
CONTACT_COLORS = {"R1": "tab:red", "L1": "tab:blue", "L2": "tab:cyan"}


def mu_color(mu, k=0):
    """Colour of a friction coefficient, consistent across figures."""
    return MU_COLORS.get(round(float(mu), 6), f"C{3 + k % 7}")


def as_numpy(x):
    return np.asarray(x, dtype=float)


def as_cycles(cycles):
    """A BaseCycle, a sequence of them, or a mapping label -> BaseCycle, as a list."""
    if isinstance(cycles, Mapping):
        return list(cycles.values())
    if hasattr(cycles, "forward"):
        return [cycles]
    return list(cycles)


def axes_row(axes, n, size=(5.0, 4.6)):
    if axes is None:
        fig, axes = plt.subplots(1, n, figsize=(size[0] * n, size[1]), squeeze=False,
                                 layout="constrained")
        return fig, list(axes[0])
    axes = list(np.atleast_1d(axes).ravel())
    if len(axes) != n:
        raise ValueError(f"need {n} axes, got {len(axes)}")
    return axes[0].figure, axes


def finish_figure(fig):
    if fig.get_layout_engine() is None:
        fig.tight_layout()
    return fig


def legend_below(ax, ncol=2, fontsize=8):
    """Legend under the axes; on a figure this function created, one shared legend at the bottom."""
    fig = ax.figure
    if getattr(fig, "_jaxdamp_shared_legend", False):
        if not getattr(fig, "_jaxdamp_legend_done", False):
            fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=4,
                       fontsize=fontsize + 1)
            fig._jaxdamp_legend_done = True
        return
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=ncol, fontsize=fontsize,
              framealpha=0.9)




def liftoff_panel(ax, text):
    ax.set_xticks([])
    ax.set_yticks([])
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, fontsize=12,
            color="firebrick", bbox=dict(boxstyle="round", fc="mistyrose", ec="firebrick"))


def cycle_panel(ax, bc, title_suffix, xlabel, ylabel) -> bool:
    """Title ("shape, μ" + suffix) and axis labels of a panel showing one cycle; a cycle that lifted
    off gets the labelled empty panel instead, and True is returned."""
    mu = float(bc.mu)
    ax.set_title(f"{shape_name(bc.shape)}, μ = {mu:g}{title_suffix}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if RESULTS.stopped(bc.status):
        liftoff_panel(ax, f"μ = {mu:g}: {RESULTS.name_of(bc.status).upper()}\nno Base-Cycle")
        return True
    return False


def shape_name(shape):
    from ..geometry import paper_tables

    for name, s in paper_tables()["shapes"].items():
        if (np.isclose(float(shape.theta_l), s["theta_l"]) and np.isclose(float(shape.theta_r), s["theta_r"])
                and np.isclose(float(shape.br_over_hr), s["br_over_hr"])
                and np.isclose(float(shape.bl2_over_hl), s["bl2_over_hl"]) and shape.x_d is None):
            return name
    return (f"θL = {float(shape.theta_l):g}°, θR = {float(shape.theta_r):g}°, "
            f"b_R/h_R = {float(shape.br_over_hr):g}")
