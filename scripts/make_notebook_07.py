"""Write notebooks/07_row_robust_design.ipynb and execute it (outputs kept).

Run from the repository root: PYTHONPATH=$PWD python scripts/make_notebook_07.py
(the optimisation result is read from benchmarks/results/row_optimisation.json, written by
benchmarks/row_optimisation.py; the notebook itself re-evaluates two designs at nominal values).
"""

import sys

from execute_notebooks import write_notebook  # scripts/ is on sys.path when this script runs
from nbformat.v4 import new_code_cell, new_markdown_cell

CELLS = [
    new_markdown_cell("""\
# 7 · Robust design over a blade row

Notebook 6 optimised the damper for one illustrative blade mode at nodal diameter 0 (in-phase
platforms). A bladed disk has one mode per nodal diameter, and engine order e excites nodal
diameter e mod N with its own interblade phase angle: the damper between two blades then moves
on a straight path (nodal diameters 0 and N/2) or an ellipse (all others), and the mode's tip
stiffness, frequency and platform motion change with the nodal diameter (docs/blade.md).

Here the design question is the one a turbine designer asks: **which shape lowers the worst
resonance over every engine order**, over the force range, μ, F_D, kn, kt and the contact history.
The optimiser is `jaxdamp_optimize.row_objective.optimize_row`
(`jaxdamp optimize --objective peak:worst --modes FILE --engine-order ... --h-l MM`); the disk is
the example shipped with the package (24 blades, nodal diameters 0 … 12)."""),
    new_code_cell("""\
import json, time
from pathlib import Path
import numpy as np
import matplotlib.pyplot as plt
import jaxdamp as jd
from jaxdamp.modal_file import load_modal_family
from jaxdamp_optimize.design import shape_of_vector
from jaxdamp_optimize.robust_plot import plot_row
from jaxdamp_optimize.row_objective import RowCertified
jd.enable_x64()
t_start = time.perf_counter()
family = load_modal_family("example")
print(family.n_blades, "blades; nodal diameters", [int(n) for n in family.nodal_diameter])
print("frequencies (Hz):", np.round(family.frequency_hz, 1))"""),
    new_markdown_cell("""\
## The committed optimisation

The example file carries the disk's platform residual flexibility: the damper sits in series with
what the modes left out of the reduction move at the platforms (docs/blade.md).
`benchmarks/row_optimisation.py` ran the optimiser over every engine order 0 … 12 (h_L = 10 mm):
a 2-point grid on each of θ_L, θ_R, b_R/h_R and 2b_L/h_L plus the two reference shapes, then
descent steps from the best of them along optax's L-BFGS direction on the gradient of the smooth
maximum (`jaxdamp.row_gradient`: each peak's derivative by the implicit function theorem), each
kept only where the design is feasible (the no-liftoff design rule at every μ, a valid peak in
every scenario) and the smooth maximum falls. Each design was then re-evaluated at every engine order from
gross slip and from assembly separately, over μ 0.3/0.5/0.7, kn and kt 0.5/1/2 × nominal and F_D
0.8/1/1.2 × nominal (applied explicitly), at 4 forces over 2–20 N."""),
    new_code_cell("""\
res = Path("..") / "benchmarks" / "results" / "row_optimisation.json"
b = json.loads(res.read_text())
print(f"run: {b['seconds_total'] / 60:.0f} min on {b['machine']['cores']} cores; "
      f"{b['grid_evaluations']} grid designs, {b['descent_evaluations']} descent evaluations, "
      f"{b['accepted_steps']} accepted steps")
print("smooth maximum after each accepted step (mm/N):",
      ", ".join(f"{v:.4f}" for _, _, v in b["descent_history"]))
designs = [RowCertified(**d) for d in b["designs"]]
print(f"{'design':34}{'band':>8}{'gross slip':>11}{'assembly':>10}  worst EO  (A*/F, mm/N)")
for d in designs:
    if not d.feasible:
        print(f"{d.name:34}  not certified: {d.reason}")
        continue
    gs, asm = (max(x for x in d.worst_by_history[h] if x is not None) for h in ("gross_slip", "assembly"))
    print(f"{d.name:34}{d.worst:8.3f}{gs:11.3f}{asm:10.3f}  {d.worst_engine_order}")
w = designs[0].worst_scenario
print("the optimum's worst peak binds at", w)"""),
    new_code_cell("""\
ax = plot_row(designs)
ax.figure.set_size_inches(7.5, 4.2)
plt.show()"""),
    new_markdown_cell("""\
## One row, recomputed

The optimum and 60sym at nominal values (μ 0.5, the default contacts and F_D) from assembly, at
three forces per blade: `jaxdamp.row_response`, the function behind `jaxdamp response --modes`.
The first call builds the row's programs (about two minutes on two cores)."""),
    new_code_cell("""\
forces = np.array([2.0, 5.0, 20.0])
rows = {d.name: jd.row_response(shape_of_vector(np.asarray(d.shape)), 0.5, modes=family,
                                engine_orders=list(range(13)), force_n=forces, h_l_mm=10.0)
        for d in designs[:2]}
fig, axes = plt.subplots(1, 3, figsize=(10, 3.2), sharey=True)
for j, ax in enumerate(axes):
    for name, r in rows.items():
        ax.plot(r.engine_order, r.peaks.peak_amplitude_mm[:, j] / forces[j], "o-", ms=3, label=name)
    r = next(iter(rows.values()))
    ax.plot(r.engine_order, r.free_peak_mm[:, j] / forces[j], "k:", lw=1, label="no damper")
    ax.set_title(f"F = {forces[j]:g} N"); ax.set_xlabel("engine order"); ax.grid(alpha=0.3)
axes[0].set_ylabel("A*/F (mm/N)"); axes[0].legend(fontsize=7)
plt.tight_layout(); plt.show()"""),
    new_markdown_cell("""\
## What the row shows

- At the highest nodal diameter the platforms barely move relative to each other, and at the
  lowest force with a stiff contact every design's damper sticks there: the worst case over this
  row and force range is the bare blade's peak (1.81 mm/N), whatever the shape.
- Below that, the shape decides: 60sym's worst peak is 1.81-1.94 mm/N at every engine order,
  the robust designs' rises from 0.80 at engine order 0 to 1.75 at 11.
- The in-phase robust optimum of notebook 6 was already a good row design: the row optimiser's
  L-BFGS steps moved it by 0.2-0.3 deg, trading 0.5-1 % at engine orders 0-4 for 0.5-1 % at
  5-11; a derivative-free search with ten times its evaluations found nothing better
  (docs/robust.md, "Over a blade row").
- Every peak of the row over 2-20 N turns the platforms by at most about 30 mrad, inside the
  small-rotation model (the path parameter psi_a is ten times that off nodal diameter 0: it is not
  a rotation). A lighter damper does not lower the row's worst peak, a heavier one sticks at
  nodal diameter 12: docs/robust.md, "The damper's mass"."""),
    new_code_cell("""\
print(f"notebook ran in {time.perf_counter() - t_start:.0f} s")"""),
]


def main(execute: bool = True) -> int:
    return write_notebook(CELLS, "07_row_robust_design.ipynb", execute_now=execute)


if __name__ == "__main__":
    sys.exit(main(execute="--no-execute" not in sys.argv))
