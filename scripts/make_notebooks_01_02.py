"""Write notebooks/01_tour_60sym.ipynb and notebooks/02_family_comparison.ipynb.

They are written without outputs; scripts/execute_notebooks.py executes them in place.

Run from the repository root: python scripts/make_notebooks_01_02.py
"""

from pathlib import Path

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

ROOT = Path(__file__).resolve().parent.parent

SETUP = """\
import numpy as np
import matplotlib.pyplot as plt
import jaxdamp as jd
from jaxdamp import plotting as P
from jaxdamp.summary import analyse_cycle, moment_polyline, numeric_first_harmonic

plt.rcParams["figure.dpi"] = 56     # modest PNGs in the committed, executed notebook

jd.enable_x64()                     # the library's results are specified in float64
paper = jd.paper_tables()           # the paper's numbers, shipped with the package
contacts = jd.Contacts(jd.REFERENCE_KN, jd.REFERENCE_KT)   # N/mm, shared by R1, L1, L2
load = jd.LoadCase(F_D=1000.0, q_star=100.0)               # the paper's reference case
print(f"kn = {contacts.kn:g} N/mm, kt = {contacts.kt:g} N/mm")"""

TOUR = [
    new_markdown_cell("""\
# 1 · A tour of the direct method on 60sym

This notebook walks through M. M. Gola's paper *On comparing behavior and performance of
Underplatform Dampers according to shape* (§3) with jaxdamp, on its guide case **60sym**
(θL = θR = 60°, 2b_L = 0.8 h_L, b_R/h_R = 0.14):

1. the section and the full-slip statics that fix b_R (Fig. 7, Table 1);
2. the Base-Cycle by the direct piecewise-linear method: tracts and transitions (Table 2);
3. the force Base-Cycle, or equilibrium track (Fig. 10);
4. the moment Base-Cycle (Fig. 13), stretched cycles and their first harmonic (Fig. 14);
5. the complex stiffness and the five numbers (Fig. 15, Table B3.1);
6. the energy dissipated at each contact (Appendix C).

Units: lengths normalised to the damper height H (section), forces to F_D (statics) or in N,
displacements in mm, platform rotation ψ in mrad, stiffness k in N mm/mrad, energy in N mm."""),
    new_code_cell(SETUP),
    new_markdown_cell("""\
## 1. Section and full-slip statics

At cycle start (point 0) the left platform has just moved down relative to the right one and
every contact slips; at mid-cycle (point C) the motion is reversed. In both states the forces follow
from statics alone. The paper chooses b_R so that at the highest friction (μ = 0.7) the left
resultant lies equally far inside L1–L2 at both ends: 6.6 % from L1 and 6.5 % from L2 (Table 1)."""),
    new_code_cell("""\
shape = jd.family_shape("60sym")
print(shape)
for row in paper["table_1_60sym_resultant_distance"]["rows"]:
    st = jd.full_slip_statics(shape, row["mu"])
    print(f"mu = {row['mu']}: from L1 {float(st.start.resultant_pos_pct):5.2f} % (paper {row['dist_L1']}), "
          f"from L2 {100 - float(st.mid.resultant_pos_pct):5.2f} % (paper {row['dist_L2']}), "
          f"status: {jd.RESULTS.name_of(st.status)}")"""),
    new_code_cell("""\
fig = P.plot_section(shape, 0.7)   # the paper's Fig. 7a (cycle start) and 7b (mid-cycle)"""),
    new_markdown_cell("""\
The dotted lines of action of F_R1 and of the left resultant F_L = F_L1 + F_L2 meet on the line of
action of F_D (three-force equilibrium). `design_br` finds the centring b_R/h_R by bisection:"""),
    new_code_cell("""\
res = jd.design_br(shape, mu_max=0.7)
print(f"centring b_R/h_R = {float(res.br_over_hr):.4f} (paper, rounded: 0.14); "
      f"margin {float(res.margin_pct):.2f} % of L1-L2")"""),
    new_markdown_cell("""\
## 2. The Base-Cycle, tract by tract

Within a tract every contact keeps its state (stick, slip, back-slide), so the damper's
incremental equilibrium is a 3×3 linear system and all forces change linearly with the relative
platform displacement Δv. A tract ends in closed form when a sticking contact reaches its friction
limit. The half-cycle ends at gross slip; the motion reverses and the cycle is repeated until it
closes. The transitions chart below is the paper's Table 2."""),
    new_code_cell("""\
bc = jd.base_cycle(shape, 0.7, contacts, load)
print(f"status: {jd.RESULTS.name_of(bc.status)}, half-cycles run: {int(bc.half_cycles)}")
print(f"{'tract':8}{'dv (um)':>9}   R1         L1         L2")
for row in jd.transitions_chart(bc):
    print(f"{row['tract']:8}{1e3 * row['dv_mm']:9.1f}   {row['R1']:10} {row['L1']:10} {row['L2']:10}")
print("paper, Table 2:", paper["transitions"]["60sym"]["all_mu"])"""),
    new_markdown_cell("""\
## 3. The force Base-Cycle (equilibrium track)

Draw the force polygon with F_D = 1 from the origin upward; F_R1 starts at its tip and F_L closes
the polygon back to the origin. The tip of F_R1 (the tail of F_L) then travels a closed polygon
during the cycle: the equilibrium track (Fig. 10). Where L1 and L2 both slip (B-C, E-F) it runs on
the left friction angle; the dashed red loop is the tail of F_L1 (the secondary loop)."""),
    new_code_cell("""\
cycles = {mu: jd.base_cycle(shape, mu, contacts, load) for mu in (0.7, 0.5, 0.3)}
fig = P.plot_equilibrium_tracks(list(cycles.values()))"""),
    new_markdown_cell("""\
## 4. Moment Base-Cycle, stretched cycles, first harmonic

The platform moment is M_P = (F_R1,v − F_L,v)(q*/2 + r sin β) and the platform rotation
ψ_P = Δv/q*. Larger amplitudes than the Base-Cycle's stretch it with constant-moment full-slip
segments at both ends (Fig. 14). The first harmonic M ≈ M_0 + ψ_a(k_Re cos τ − k_Im sin τ) of the
piecewise-linear cycle is computed in closed form by `complex_stiffness`."""),
    new_code_cell("""\
fig = P.plot_moment_cycles(list(cycles.values()))"""),
    new_code_cell("""\
fig = P.plot_stretched_cycles(bc)   # Base-Cycle and psi_a = 3, 4, 6 mrad, as in Fig. 14"""),
    new_markdown_cell("""\
An independent check of the closed-form harmonics: sample the drawn polyline at ψ = ψ_a cos τ and
take plain Fourier sums."""),
    new_code_cell("""\
for psi_a in (3.0, 6.0):
    psi, M, names = moment_polyline(bc, psi_a)
    _, k_re_num, k_im_num = numeric_first_harmonic(psi, M, psi_a, n=1 << 14)
    k_re, k_im = (float(v) for v in jd.complex_stiffness(bc, psi_a, method="interpolated"))
    print(f"psi_a = {psi_a} mrad: closed form k_Re = {k_re:8.1f}, k_Im = {k_im:7.1f};  "
          f"sampled {k_re_num:8.1f}, {k_im_num:7.1f}  (points {' '.join(names)})")"""),
    new_markdown_cell("""\
## 5. Complex stiffness and the five numbers

Five numbers characterise a damper–platform coupling: ψ_fs and k_Re,fs (end of full stick),
ψ_BC, k_Re,BC and k_Im,BC (the Base-Cycle). Between ψ_fs and ψ_BC (microslip) the paper
interpolates linearly. Here they are next to the paper's Table B3.1."""),
    new_code_cell("""\
summaries = [analyse_cycle(c) for c in cycles.values()]
fig = P.plot_complex_stiffness(list(cycles.values()), summaries=summaries)"""),
    new_code_cell("""\
keys = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc")
print(f"{'mu':5}" + "".join(f"{k:>22}" for k in keys))
for row, s in zip(paper["table_B"]["60sym"], summaries):
    cells = [f"{s.numbers[k]:9.3f} ({100 * (s.numbers[k] / ref - 1):+5.2f} %)" for k, ref in zip(keys, row[1:])]
    print(f"{row[0]:<5}" + "".join(f"{c:>22}" for c in cells))
print("deviations from Table B3.1 in brackets")"""),
    new_markdown_cell("""\
## 6. Energy per contact

The work dissipated at a contact is ∫T d(slip); around the cycle the contact works add up to
∮M dψ = π ψ_a² k_Im. The work shape factors of Appendix C measure the full-slip dissipation per
contact: for 60sym, R1 takes exactly half, L1 about 2/3 of the rest and L2 about 1/3, at every μ."""),
    new_code_cell("""\
for mu, s in zip(cycles, summaries):
    n, e = s.numbers, s.energy_Nmm
    print(f"mu = {mu}: w_R1 {n['w_R1']:.4f} ({100 * n['w_R1'] / n['w_M']:.1f} %), "
          f"w_L1 {n['w_L1']:.4f}, w_L2 {n['w_L2']:.4f}, w_M {n['w_M']:.4f} = sum {n['w_R1'] + n['w_L1'] + n['w_L2']:.4f}")
    print(f"          energy per Base-Cycle (N mm): R1 {e['R1']:.2f}, L1 {e['L1']:.2f}, L2 {e['L2']:.2f}; "
          f"contacts {e['R1'] + e['L1'] + e['L2']:.3f} = moment {e['M']:.3f} = "
          f"pi psi^2 k_Im {np.pi * n['psi_bc_mrad'] ** 2 * n['k_im_bc'] / 1e3:.3f}")"""),
    new_markdown_cell("""\
At the Base-Cycle itself R1 of 60sym never slides (it only reaches its limit at the end of E-F);
its 50 % share is of the full-slip stretches that larger amplitudes add.

## 7. Scaling

Forces scale with F_D and displacements with F_D/k, so doubling F_D doubles ψ_fs and ψ_BC and
keeps k unchanged (the moment doubles too); M scales with q* and ψ with 1/q*."""),
    new_code_cell("""\
base = jd.five_numbers(bc)
double = jd.five_numbers(jd.base_cycle(shape, 0.7, contacts, jd.LoadCase(F_D=2000.0, q_star=100.0)))
print(f"psi_BC: {float(base.psi_bc):.4f} -> {float(double.psi_bc):.4f} mrad (x{float(double.psi_bc / base.psi_bc):.3f})")
print(f"k_Re,BC: {float(base.k_re_bc):.1f} -> {float(double.k_re_bc):.1f} N mm/mrad")"""),
    new_markdown_cell("""\
The whole family, the Table 11 scores and the report come from one command: `jaxdamp study`
(notebook 2 works through the same comparison)."""),
]

FAMILY = [
    new_markdown_cell("""\
# 2 · The 60sym family compared

The paper's §5–10: five shapes made by moving the vertex of the 60° isosceles triangle by quarters
of the base (90L, 74L, 60sym, 74R, 90R), each with b_R chosen to centre the left resultant at
μ = 0.7, compared at μ = 0.7, 0.5, 0.3 by their five numbers, their work shape factors and the
scores of Table 11. Everything below is computed here; the paper's values come from
`jd.paper_tables()`. Units: ψ in mrad, k in N mm/mrad, energy in N mm."""),
    new_code_cell(SETUP + """
from jaxdamp.paper.scoring import MARK_SYMBOLS, qualitative_findings, score_table"""),
    new_markdown_cell("""\
## The shapes (Fig. 18) and their cycle-start statics at μ = 0.7"""),
    new_code_cell("""\
names = list(jd.FAMILY)
fig, axes = plt.subplots(2, 3, figsize=(18, 13), layout="constrained")
for ax, name in zip(axes.ravel(), names):
    P.plot_section(jd.family_shape(name), 0.7, ax=ax, end="start")
axes[1, 2].set_visible(False)"""),
    new_markdown_cell("""\
74L at μ = 0.7 lifts off: with the family's b_R/h_R = 0.16 and the centroid as centre of mass, the
cycle-start resultant falls just outside L1–L2, so N_L2 < 0. jaxdamp reports it (`liftoff=True`)
instead of drawing a cycle.

## All Base-Cycles

One compiled solver serves all fifteen cases (same array shapes, so no recompilation)."""),
    new_code_cell("""\
import time
mus = (0.7, 0.5, 0.3)
t0 = time.perf_counter()
cycles = {(s, mu): jd.base_cycle(jd.family_shape(s), mu, contacts, load) for s in names for mu in mus}
summ = {key: analyse_cycle(bc) for key, bc in cycles.items()}
print(f"15 Base-Cycles and their summaries in {time.perf_counter() - t0:.1f} s (compilation included)")

keys = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc", "w_M")
results = {}
for (s, mu), cs in summ.items():
    entry = {k: (None if jd.RESULTS.stopped(cs.status) else cs.numbers[k])
             for k in keys + ("w_R1", "w_L1", "w_L2")}
    results.setdefault(s, {})[f"{mu:g}"] = entry | {"liftoff": cs.status == jd.RESULTS.liftoff,
                                                    "converged": cs.status == jd.RESULTS.ok}
print(f"{'shape':7}{'mu':>5}" + "".join(f"{k:>13}" for k in keys))
for s, per in results.items():
    for mu, e in per.items():
        cells = "".join(f"{'LIFTOFF' if e['liftoff'] else f'{e[k] + 0.0 if abs(e[k]) > 5e-4 else 0.0:.3f}':>13}"
                        for k in keys)
        print(f"{s:7}{mu:>5}{cells}")"""),
    new_markdown_cell("""\
## Side by side

Bars: our numbers; black ticks: the paper's Tables B3.1 (60sym), B4.1 (74R) and B5.1 (90R) — the
only ones its text preserves."""),
    new_code_cell("""\
cols = paper["table_B"]["columns"][1:]
key_of = dict(zip(cols, keys))
ref = {s: {f"{r[0]:g}": {key_of[c]: v for c, v in zip(cols, r[1:])} for r in paper["table_B"][s]}
       for s in ("60sym", "74R", "90R")}
fig = P.plot_family_comparison(results, paper=ref)"""),
    new_code_cell("""\
fig = P.plot_complex_stiffness([cycles[(s, 0.5)] for s in names], labels=names,
                               summaries=[summ[(s, 0.5)] for s in names])
fig.axes[0].set_title("μ = 0.5: complex stiffness of the family");"""),
    new_code_cell("""\
fig = P.plot_moment_cycles([cycles[(s, 0.5)] for s in names], labels=names, label_points=False)
fig.axes[0].set_title("μ = 0.5: moment Base-Cycles of the family");"""),
    new_markdown_cell("""\
## Table 11: scores from our numbers

The paper's rules (§10.1), for μ = 0.5 and 0.3: k_Re,init best if highest, ψ_BC best if lowest,
k_Re,BC best if highest, w_M best if highest; ψ_fs and k_Im,BC are not evaluated.
● best, ◐ second best, ○ worst."""),
    new_code_cell("""\
sc = score_table(results)
print(f"{'mu':5}{'indicator':24}" + "".join(f"{s:>14}" for s in names))
for mu in sc["mus"]:
    for key, label, _ in sc["indicators"]:
        cells = "".join(f"{sc['values'][mu][key][s]:>12.3f} {MARK_SYMBOLS[sc['marks'][mu][key][s]] or ' '}"
                        for s in names)
        print(f"{mu:5}{label:24}{cells}")
print(f"{'':5}{'best count':24}" + "".join(f"{sc['best_count'][s]:>14}" for s in names))
print(f"{'':5}{'worst count':24}" + "".join(f"{sc['worst_count'][s]:>14}" for s in names))"""),
    new_code_cell("""\
for f in qualitative_findings(results, sc):
    verdict = {True: "HOLDS", False: "DOES NOT HOLD", None: "not checked"}[f["holds"]]
    print(f"- {f['claim']}: {verdict}\\n    {f['evidence']}")"""),
    new_markdown_cell("""\
## Where the energy goes

Work shape factors (full slip, Appendix C) stacked per contact, and the energy dissipated per
Base-Cycle. 90L never slides on R1; 90R slides only on R1 and has the lowest w_M."""),
    new_code_cell("""\
energies = {s: {f"{mu:g}": summ[(s, mu)].energy_Nmm for mu in mus} for s in names}
fig = P.plot_energy(results, energies)"""),
    new_markdown_cell("""\
## 90R and the paper's two-iteration cycle

The paper's 90R values come from a cycle stopped after two iterations ("converge in two
iterations"; Table B5.1: "differences due to cycle convergence approximation"). Our converged
periodic cycle freezes onto a line (k_Im,BC ≈ 0). Stopping after two iterations leaves a non-zero
k_Im,BC that depends on where the iteration is stopped; the paper's 79 / 33 / 168 N mm/mrad are
values of this truncated kind, not of the converged cycle."""),
    new_code_cell("""\
from jaxdamp.cycle import MAX_PAIRS
shape90 = jd.family_shape("90R")
for pairs in (2, MAX_PAIRS):
    row = []
    for mu in mus:
        b = jd.base_cycle(shape90, mu, contacts, load, max_pairs=pairs)
        k_im = float(jd.five_numbers(b).k_im_bc)
        row.append(f"mu={mu}: k_Im,BC = {k_im if abs(k_im) > 0.05 else 0.0:6.1f} ({jd.RESULTS.name_of(b.status)})")
    print(f"max_pairs = {pairs:2}: " + ";  ".join(row))
print("paper Table B5.1:", [r[5] for r in paper["table_B"]["90R"]])"""),
]


def write(name, cells):
    nb = new_notebook(cells=cells)
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nb.metadata["language_info"] = {"name": "python"}
    path = ROOT / "notebooks" / name
    path.parent.mkdir(exist_ok=True)
    nbformat.write(nb, path)
    print("wrote", path)


if __name__ == "__main__":
    write("01_tour_60sym.ipynb", TOUR)
    write("02_family_comparison.ipynb", FAMILY)
