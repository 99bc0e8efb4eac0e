"""Write notebooks/03_design_space_and_optimisation.ipynb.

The notebook is written without outputs; scripts/execute_notebooks.py executes it in place.

Run from the repository root: python scripts/make_notebook_03.py
"""

from pathlib import Path

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

ROOT = Path(__file__).resolve().parent.parent

CELLS = [
    new_markdown_cell("""\
# 3 · The design space and shape optimisation

The paper compares six hand-picked shapes. Here the shape itself is the unknown:

* **design variables** θL, θR ∈ [35°, 90°], b_R/h_R ∈ [−0.3, 0.4] (2b_L/h_L = 0.8 fixed, or free in
  [0.5, 0.9]);
* **constraint** (no liftoff, §3 of the paper, over the whole friction range μ ∈ {0.3, 0.5, 0.7}):
  at both full-slip ends *and* at every tract end point of the Base-Cycle, every normal force stays
  positive and the left resultant stays inside L1-L2 at least 5 % of L1-L2 from either pad; plus a
  geometric one, a vertex angle 180° − θL − θR ≥ 20° (as the wedge closes, w_M and ψ_BC diverge);
* **objective** (default): the worst case over μ of k_Im,BC, the damping at the Base-Cycle.

The constraint enters a PHR augmented Lagrangian; the inner loop is optax L-BFGS with projection onto
the bounds and Armijo backtracking, started from every shape of the paper's family. One
*evaluation* is one design over the whole μ set (statics and Base-Cycle at each μ, values and
forward-mode Jacobian), whether the optimiser or the brute-force grid asks for it."""),
    new_code_cell("""\
import time
import numpy as np
import matplotlib.pyplot as plt
import jaxdamp as jd
import jaxdamp_optimize as opt

jd.enable_x64()
plt.rcParams["figure.dpi"] = 56       # modest PNGs in the committed, executed notebook
problem = opt.make_problem()          # bounds, mu set, contacts, 5 % margin, 20 deg vertex angle
print(problem.space.bounds(), "mu set", problem.mus, "margin", problem.margin_pct, "%")"""),
    new_markdown_cell("""\
## 1. The constraint, in the paper's terms

The 60sym design rule (§3, Table 1) leaves the resultant 6.6 % / 6.5 % from the pads at μ = 0.7;
45sym with b_R/h_R = −0.20 (§4) is 2.94 % from L1 at cycle start and far beyond L2 at mid-cycle.
`check_design` re-checks a design by the public statics and Base-Cycle at every μ."""),
    new_code_cell("""\
from jaxdamp_optimize.constraints import LOCATIONS
for name in ("60sym", "74L"):
    c = opt.check_design(problem, opt.design.vector_of(problem.space, jd.family_shape(name)))
    print(f"{name}: feasible={c.feasible}, smallest resultant distance from a pad "
          f"{c.min_margin_pct:.2f} % of L1-L2, smallest normal force {c.min_normal:.4f} F_D")
    for i, mu in enumerate(problem.mus):
        print(f"   mu={mu}: distance from L1 at cycle start {c.dist_pct[i, 0, 0]:7.2f} %, "
              f"from L2 at mid-cycle {c.dist_pct[i, 1, 1]:7.2f} %, over the cycle "
              f"{c.dist_pct[i, 2].min():7.2f} %")"""),
    new_markdown_cell("""\
## 2. The design space by brute force

A coarse-to-fine grid: 15³ designs over the box, then two finer 7³ grids around the two best
feasible designs of the previous level. The heatmap shows, for each (θL, θR), the best worst-case
k_Im,BC over the feasible b_R/h_R (grey: no feasible b_R/h_R)."""),
    new_code_cell("""\
t0 = time.perf_counter()
grid = opt.grid_search("k_im_bc:worst", problem, points=15, levels=3, top=2, refine_points=7)
print(f"grid: {grid.evaluations} evaluations in {time.perf_counter() - t0:.1f} s "
      f"(including compilation); {grid.feasible[:15**3].mean():.0%} of the level-0 designs are feasible")
print("grid best:", dict(zip(grid.free, np.round(grid.best_x, 4))), f"-> {grid.best_value:.1f} N mm/mrad")
scorer, _ = opt.make_scorer(problem, opt.parse_objective("k_im_bc:worst"))
for row in opt.family_table(problem, scorer):
    print(f"  {row['shape']:6} worst-case k_Im,BC {row['objective']:8.1f}   feasible: {row['feasible']}")"""),
    new_markdown_cell("""\
## 3. Gradient-based optimisation from the paper's family"""),
    new_code_cell("""\
t0 = time.perf_counter()
res = opt.optimize("k_im_bc:worst", problem)
print(f"{time.perf_counter() - t0:.1f} s (including compilation)")
print("feasible:", res.feasible, "| optimum:", {k: round(v, 4) for k, v in res.shape.items()})
print(f"worst-case k_Im,BC = {res.objective:.1f} N mm/mrad (60sym: {res.baseline['objective']:.1f}); "
      f"achieved margin {res.min_margin_pct:.1f} %")
print("active constraints:", [a["constraint"] for a in res.active] or "none: the optimum is interior")
print(f"evaluations: optimiser {res.evaluations}, grid {grid.evaluations} "
      f"({grid.evaluations / res.evaluations:.0f}x more); objective ratio optimiser / grid = "
      f"{res.objective / grid.best_value:.4f}")
for s in res.starts:
    best = "no feasible design" if s.best_objective is None else f"{s.best_objective:8.1f}"
    print(f"  start {s.name:6} -> {best}  ({s.evaluations} evaluations{', pruned' if s.pruned else ''})")"""),
    new_code_cell("""\
fig, axs = plt.subplots(1, 2, figsize=(13, 5), gridspec_kw={"width_ratios": [1.25, 1]})
opt.plot_paths(res, grid, ax=axs[0])
for k, (name, hist) in enumerate(res.histories.items()):  # same colours as the paths
    ok = [h for h in hist if h["feasible"]]
    if ok:
        axs[1].plot([h["evaluations"] for h in ok], [h["objective"] for h in ok], ".-",
                    color=plt.get_cmap("tab10")(k), label=name)
axs[1].axhline(grid.best_value, color="orange", ls="--", label="grid best")
axs[1].axhline(res.baseline["objective"], color="gray", ls=":", label="60sym")
axs[1].set_xlabel("evaluations so far (all starts)")
axs[1].set_ylabel("worst-case k_Im,BC of feasible iterates [N mm/mrad]")
axs[1].set_title("convergence history")
axs[1].legend(fontsize=8)
fig.tight_layout()"""),
    new_markdown_cell("""\
The family starts fall into different basins: the k_Im,BC landscape has narrow valleys where the
transition sequence of the cycle changes, so multi-start matters. The winning basin is a tall,
narrow wedge with both flanks steep. The starts are pruned to the best two after 20 rounds.

## 4. Other objectives, and the active constraints

Minimising ψ_BC runs into a face of the box: with θR = 90° the right flank is vertical, the
mechanism freezes and ψ_BC jumps down (it grows without bound as θR → 90° from below), so the
optimiser searches within that face. Maximising w_M drives the wedge shut: the vertex-angle
constraint is active."""),
    new_code_cell("""\
for name in ("psi_bc:worst", "w_m:worst", "k_im_bc:mean"):
    r = opt.optimize(name, problem)
    print(f"{name:13} {r.objective:9.4g} {r.units:9} (60sym {r.baseline['objective']:.4g}) at "
          f"{ {k: round(v, 3) for k, v in r.shape.items()} }, {r.evaluations} evaluations")
    for a in r.active:
        print(f"      active: {a['constraint']} ({a['value']:.3f} {a['unit']})")"""),
    new_markdown_cell("""\
## 5. A constraint that cannot be met: 45sym at μ = 0.7 (§4)

With the angles fixed at 45°/45° only b_R/h_R is free. Moving R1 up pulls the mid-cycle resultant
back towards L2 but pushes the cycle-start resultant past L1, and the other way round: the
optimiser reports the problem as infeasible, with the reason, and returns no optimum."""),
    new_code_cell("""\
p45 = opt.make_problem(opt.design_space(("br_over_hr",), fixed={"theta_l": 45.0, "theta_r": 45.0}),
                       mus=(0.7,))
r45 = opt.optimize(problem=p45)
print("feasible:", r45.feasible)
print(r45.reason)"""),
]


def main():
    nb = new_notebook(cells=CELLS, metadata={
        "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
        "language_info": {"name": "python"}})
    out = ROOT / "notebooks" / "03_design_space_and_optimisation.ipynb"
    nbformat.write(nb, out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
