"""Write notebooks/06_robust_design.ipynb and execute it (outputs kept).

Run from the repository root: PYTHONPATH=$PWD python scripts/make_notebook_06.py
(the optimisation result is read from benchmarks/results/robust_optimisation.json, written by
benchmarks/robust_optimisation.py; the notebook itself runs small Monte Carlo sizes only).
"""

import sys

from execute_notebooks import write_notebook  # scripts/ is on sys.path when this script runs
from nbformat.v4 import new_code_cell, new_markdown_cell


CONCLUSION = """\
## What changed

- **Exact curve:** the table of section 1 reproduces issue 25's numbers: the interpolated curve is
  16–27 % off in microslip, in both directions.
- **Force range and uncertainty:** the robust optimum's worst A*/F over 2–20 N and every scenario
  is 0.53 mm/N on the independent grid against 0.98 for 60sym and 0.66 for the previous (20 N,
  interpolated) optimum; its magnification is flat over the range where 60sym's rises at low force.
- **History:** optimised on the gross-slip history, the robust optimum's 95th percentile at 2 N
  roughly doubles on the upper edge of the history band (assembly history): a design for the
  band must be optimised with `--history band` (the objective supports it; its committed run is
  the gross-slip one)."""

CELLS = [
    new_markdown_cell("""\
# 6 · Robust damper design

The response optimiser of notebook 5 designs against the paper's interpolated k(ψ_a), at one
force, for the nominal contacts and one contact history. A blade meets a range of excitation
levels, F_D changes with speed, μ moves between 0.3 and 0.7, kn and kt come from one rig's
calibration, and in microslip the response depends on the contact history. This notebook shows
what changes when the optimiser (`jaxdamp_optimize.robust_objective`) sees

1. the **exact** curve (the steady cycle at each amplitude),
2. a **force range** (the dynamic magnification A*/F, mm/N, over 2–20 N),
3. the **uncertainty** (μ, F_D ± 20 %, kn and kt a factor 2 each way, per contact pair),
4. the **history** (gross slip against assembly).

Sizes here are small (hundreds of samples); the committed benchmark runs the full optimisation."""),
    new_code_cell("""\
import json, time
from pathlib import Path
import numpy as np
import jax, jax.numpy as jnp
import matplotlib.pyplot as plt
import jaxdamp as jd
from jaxdamp.response import design_peaks
from jaxdamp.uncertainty import Uncertainty, sample_scenarios, peak_distribution
from jaxdamp_optimize.robust_objective import reference_shapes, ROBUST_MU_SET
jd.enable_x64()
t_start = time.perf_counter()
shapes = {k: jd.DamperShape(*v, None) for k, v in reference_shapes().items()}
list(shapes)"""),
    new_markdown_cell("""\
## 1 · The exact curve against the paper's interpolation

Worst-case peak over the μ set at low forces, where the damper works in microslip."""),
    new_code_cell("""\
def worst_peak(shape, force, **kw):
    return max(float(design_peaks(shape, mu, force_n=force, **kw).peak_amplitude_mm) for mu in ROBUST_MU_SET)

print(f"{'design':40}{'F':>5}{'interp.':>9}{'exact gs':>10}{'exact asm':>10}  (mm)")
for name in ("60sym", "response optimum (20 N, interpolated)"):
    for force in (2.0, 5.0):
        a_i = worst_peak(shapes[name], force, method="interpolated")
        a_g = worst_peak(shapes[name], force)
        a_a = worst_peak(shapes[name], force, initial="assembly")
        print(f"{name:40}{force:5g}{a_i:9.3f}{a_g:10.3f}{a_a:10.3f}")"""),
    new_markdown_cell("""\
The interpolated curve is off in both directions in microslip, and neither history is always the
worst: a design tuned on the interpolated curve at one force is tuned on the wrong numbers.

## 2–3 · The robust optimum over the force range and the uncertainty

The committed benchmark (`benchmarks/robust_optimisation.py`, 4 design variables) minimised the
worst A*/F over 2–20 N, μ ∈ {0.3 … 0.7}, F_D ± 20 % and the kn, kt corners (smooth maximum,
forward-mode IFT gradients, strict no-liftoff), then re-evaluated every design independently: a
dense grid (9 μ × 3 kn × 3 kt × 3 F_D, F_D applied explicitly) at 50 forces, and 256 Monte Carlo
samples with kn and kt drawn per contact pair."""),
    new_code_cell("""\
res = Path("..") / "benchmarks" / "results" / "robust_optimisation.json"
if res.exists():
    b = json.loads(res.read_text())
    print(f"run: {b['seconds_total']:.0f} s on {b['machine']['cores']} cores, load {b['machine']['load_average_1min_at_start']:.1f}-{b['load_average_1min_at_end']:.1f}")
    print(f"{'design':40}{'grid worst':>11}{'MC worst':>10}{'MC q95':>9}  (mm/N)")
    for d in b["designs"]:
        if d["feasible"]:
            print(f"{d['name']:40}{d['worst_dense']:11.3f}{d['worst_mc']:10.3f}{d['q95_mc']:9.3f}")
        else:
            print(f"{d['name']:40}  infeasible in some scenario (damper status not ok)")
    robust = jd.DamperShape(*b["designs"][0]["shape"], None)
else:
    print("run benchmarks/robust_optimisation.py first")
    robust = shapes["response optimum (20 N, interpolated)"]"""),
    new_code_cell("""\
from IPython.display import Image
png = Path("..") / "docs" / "robust_optimisation.png"
Image(filename=str(png), width=640) if png.exists() else print("no figure yet")"""),
    new_markdown_cell("""\
## The peak distribution (Monte Carlo by vmap)

`jaxdamp.uncertainty` samples μ, per-pair kn and kt and F_D and recomputes the exact curve per
sample (the scaling law is exact only for F_D and a common contact scale). 200 samples here."""),
    new_code_cell("""\
scen = sample_scenarios(jax.random.PRNGKey(0), 200, Uncertainty(), jd.Contacts(), jd.LoadCase())
forces = np.array([2.0, 5.0, 20.0])
dists = {name: peak_distribution(s, scen, force_n=forces, limit_mm_per_n=0.5)
         for name, s in (("60sym", shapes["60sym"]), ("robust optimum", robust))}
fig, axes = plt.subplots(1, 3, figsize=(10, 3), sharey=True)
for j, ax in enumerate(axes):
    for name, d in dists.items():
        ax.hist(d.magnification[:, j], bins=25, alpha=0.5, label=name)
    ax.axvline(0.5, color="k", ls="--", lw=1)
    ax.set_title(f"F = {forces[j]:g} N"); ax.set_xlabel("A*/F (mm/N)")
axes[0].legend(fontsize=8); fig.tight_layout()
for name, d in dists.items():
    print(name, "q95", np.round(d.quantiles[-1], 3), "P(A*/F > 0.5)", d.exceedance)"""),
    new_markdown_cell("""\
## 4 · The history

The upper edge of the history band (the larger peak of the gross-slip and assembly histories,
`history="band"`) against gross slip alone, on the same samples (fewer, 60)."""),
    new_code_cell("""\
few = type(scen)(*(x[:60] for x in scen))
for name, s in (("60sym", shapes["60sym"]), ("robust optimum", robust)):
    g = peak_distribution(s, few, force_n=forces, history="gross_slip")
    h = peak_distribution(s, few, force_n=forces, history="band")
    print(f"{name:16} q95 gross slip {np.round(g.quantiles[-1], 3)}  band {np.round(h.quantiles[-1], 3)}")
print(f"notebook: {time.perf_counter() - t_start:.0f} s")"""),
    new_markdown_cell(CONCLUSION),
]


def main(execute=True):
    return write_notebook(CELLS, "06_robust_design.ipynb", execute_now=execute)


if __name__ == "__main__":
    sys.exit(main(execute="--no-execute" not in sys.argv))
