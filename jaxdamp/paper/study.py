"""The paper's study of the 60sym family as one command: `jaxdamp study`.

Writes into the output directory:
- `study.json`: {"results": {shape: {mu: {psi_fs_mrad, k_re_fs, psi_bc_mrad, k_re_bc, k_im_bc, w_R1,
  w_L1, w_L2, w_M, status, liftoff, converged}}}, "contacts": {kn, kt}, ...} with mu keys "0.7",
  "0.5", "0.3" (numbers are null for a case that lifts off: it has no cycle; liftoff and converged
  are read from status), plus the load case, the paper
  comparison, the Table 11 scores, the checked findings and the run time; "stiffness_band":
  {shape: {mu: exact k(psi_a) from both named initial states, the band over all admissible initial
  states, the paper's interpolation and its largest gap to the band}}; "peak_response": the peak
  blade response A* and its frequency at PEAK_FORCES_N for the default BladeMode;
  "platform_claim": 60sym against a wedge over the interblade phase angle (`claim.py`);
- `figures/*.png`, `tables/*.csv`, `report.md` and `report.html`.

Every jit-compiled function is compiled once and reused across shapes and mu (same array shapes).
"""

from __future__ import annotations

import csv
import json
import math
import time
from pathlib import Path

import numpy as np

from .. import __version__
from ..runtime import run_program, side_by_side
from ..status import RESULTS
from .claim import platform_claim
from .files import atomic_file, write_text

SCHEMA_VERSION = 2  # study.json: 2 adds "status", "schema_version", "jaxdamp_version"

DEFAULT_SHAPES = ("90L", "74L", "60sym", "74R", "90R")
DEFAULT_MU = (0.7, 0.5, 0.3)
CONTRACT_KEYS = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc", "w_R1", "w_L1", "w_L2", "w_M")
PAPER_TABLES = (("B3.1", "60sym"), ("B4.1", "74R"), ("B5.1", "90R"))
CRITERION_TABLES = ("B3.1", "B4.1")
CRITERION_TOL_PCT = 2.0
TABLE_B_KEYS = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc")
NOTE_90R = ("90R: our converged periodic cycle has k_Im,BC ≈ 0 (the mechanism freezes; only R1 slides "
            "and the cycle closes onto a line). The paper's 79 / 33 / 168 N mm/mrad come from a cycle "
            "stopped after two iterations (its Table 9: 'all converge in two iterations, the second "
            "is represented'; Table B5.1: 'differences due to cycle convergence approximation'), so "
            "those k_Im deviations are expected. So are the larger ψ_fs deviations at μ = 0.5 and 0.3: there "
            "the paper's ψ_fs lies below its ψ_BC, while the first tract of our converged cycle runs "
            "straight to gross slip (ψ_fs = ψ_BC). Table B5.1 is not part of the 2 % criterion.")


def mu_key(mu) -> str:
    """The key of a friction coefficient in the study's JSON (0.7 -> "0.7")."""
    return f"{float(mu):g}"


def _state_text(row) -> str:
    if row.get("stretch"):
        return "full slip"
    parts = []
    for c in ("R1", "L1", "L2"):
        st = row[c]
        if st == "slip":
            parts.append(c)
        elif st == "backslide":
            parts.append(f"{c} bs")
        elif st == "open":
            parts.append(f"{c} open")
    return " ".join(parts) if parts else "—"


def paper_transitions(tables: dict, shapes, mus) -> dict:
    """The paper's transitions charts (where its text gives them) as one line per shape and mu."""
    tr = tables.get("transitions", {})
    out = {}
    for s in shapes:
        entry = tr.get(s)
        if not entry:
            continue
        per = {}
        for m in mus:
            chart = entry.get(m, entry.get("all_mu"))
            if chart is None:
                per[m] = entry.get("note", "—")
                continue
            per[m] = "; ".join(f"{k}: {(' '.join(v) or '—') if isinstance(v, list) else v}"
                               for k, v in chart.items())
        out[s] = per
    return out


def paper_comparison(results: dict, tables: dict) -> dict:
    """Our five numbers next to Tables B3.1 (60sym), B4.1 (74R), B5.1 (90R), with deviations in %."""
    table_b = tables["table_B"]
    comp, worst = [], 0.0
    for name, shape in PAPER_TABLES:
        if shape not in results:
            continue
        rows = []
        for row in table_b[shape]:
            mu = mu_key(row[0])
            if mu not in results[shape]:
                continue
            ours = {k: results[shape][mu][k] for k in TABLE_B_KEYS}
            ref = dict(zip(TABLE_B_KEYS, row[1:]))
            dev = {k: None if ours[k] is None else 100.0 * (ours[k] - ref[k]) / ref[k] for k in TABLE_B_KEYS}
            if name in CRITERION_TABLES:
                worst = max([worst] + [abs(v) if v is not None else float("inf") for v in dev.values()])
            rows.append({"mu": mu, "ours": ours, "paper": ref, "dev_pct": dev})
        comp.append({"table": name, "shape": shape, "rows": rows, "note": NOTE_90R if shape == "90R" else ""})
    present = [t["table"] for t in comp if t["table"] in CRITERION_TABLES]
    return {"tables": comp, "criterion": {"tables": list(CRITERION_TABLES), "tol_pct": CRITERION_TOL_PCT,
                                          "max_abs_dev_pct": worst,
                                          "holds": bool(present) and worst <= CRITERION_TOL_PCT}}


def paper_values(tables=None):
    """{shape: {mu: {key: value}}} from the Appendix B tables, for the family figure."""
    tables = _tables() if tables is None else tables
    return {s: {mu_key(r[0]): dict(zip(TABLE_B_KEYS, r[1:])) for r in rows}
            for s, rows in tables["table_B"].items() if s in tables["shapes"]}


def compute_cases(shapes, mus, contacts, load, progress=None):
    """BaseCycles and their summaries for every shape x mu (the jitted solver compiles once)."""
    from ..charts import transitions_chart
    from ..cycle import base_cycle
    from ..geometry import family_shape
    from ..summary import analyse_cycle, section_data

    cycles, summaries, statics, transitions = {}, {}, {}, {}
    table1 = {mu_key(r["mu"]): r for r in _tables()["table_1_60sym_resultant_distance"]["rows"]}
    for name in shapes:
        shape = family_shape(name)
        for mu in mus:
            m = mu_key(mu)
            bc = base_cycle(shape, float(mu), contacts, load)
            cycles.setdefault(name, {})[m] = bc
            summaries.setdefault(name, {})[m] = analyse_cycle(bc)
            _, st = section_data(shape, float(mu))
            statics.setdefault(name, {})[m] = {
                "dist_L1": float(st.start.resultant_pos_pct), "dist_L2": 100.0 - float(st.mid.resultant_pos_pct),
                "liftoff": bool(RESULTS.stopped(st.status)), "paper": table1.get(m) if name == "60sym" else None}
            transitions.setdefault(name, {})[m] = None if RESULTS.stopped(bc.status) else [
                {"tract": r["tract"], "slip": _state_text(r), "dv_um": 1e3 * r["dv_mm"]}
                for r in transitions_chart(bc)]
            if progress is not None:
                progress.update(1)
    return cycles, summaries, statics, transitions


def _tables():
    from ..geometry import paper_tables

    return paper_tables()


def result_entry(s) -> dict:
    """One study.json entry (the contract: psi in mrad, k in N mm/mrad, w_* dimensionless work
    shape factors); numbers are null when the cycle stopped part-way (liftoff, a failed solve).
    `status` is the truth; the file's `liftoff` and `converged` (a valid, periodic cycle) are read
    from it for the report's tables."""
    entry = {k: (None if RESULTS.stopped(s.status) else s.numbers[k]) for k in CONTRACT_KEYS}
    entry["liftoff"] = bool(s.status == RESULTS.liftoff)
    entry["converged"] = bool(RESULTS.valid(s.status))
    entry["status"] = RESULTS(s.status).name
    return entry


# CSV column names of the five numbers, with their units (the study.json keys of k carry none:
# k is in N mm/mrad throughout, as "units" in study.json says).
CSV_NAMES = {"psi_fs_mrad": "psi_fs_mrad", "k_re_fs": "k_re_fs_Nmm_per_mrad", "psi_bc_mrad": "psi_bc_mrad",
             "k_re_bc": "k_re_bc_Nmm_per_mrad", "k_im_bc": "k_im_bc_Nmm_per_mrad"}


def write_tables(out: Path, summary: dict) -> list[str]:
    """CSV tables: five numbers, work shape factors, scores, transitions, paper comparison."""
    out.mkdir(parents=True, exist_ok=True)
    res = summary["results"]
    files = []

    def write(name, header, rows):
        with atomic_file(out / name, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            w.writerows(rows)
        files.append(name)

    write("five_numbers.csv", ["shape", "mu", *(CSV_NAMES[k] for k in TABLE_B_KEYS), "liftoff", "converged"],
          [[s, m, *[e[k] for k in TABLE_B_KEYS], e["liftoff"], e["converged"]] for s, per in res.items()
           for m, e in per.items()])
    en = summary["energies"]
    write("work_shape_factors.csv", ["shape", "mu", "w_R1", "w_L1", "w_L2", "w_M", "W_R1_Nmm", "W_L1_Nmm",
                                     "W_L2_Nmm", "W_M_Nmm"],
          [[s, m, e["w_R1"], e["w_L1"], e["w_L2"], e["w_M"],
            *[None if e["liftoff"] else en[s][m][k] for k in ("R1", "L1", "L2", "M")]]
           for s, per in res.items() for m, e in per.items()])
    sc = summary["scores"]
    write("scores.csv", ["mu", "indicator", "shape", "value", "mark"],
          [[mu, key, s, v, sc["marks"][mu][key].get(s, "")] for mu in sc["mus"]
           for key, _, _ in sc["indicators"] for s, v in sc["values"][mu][key].items()]
          + [["all", "best_count", s, n, ""] for s, n in sc["best_count"].items()]
          + [["all", "worst_count", s, n, ""] for s, n in sc["worst_count"].items()])
    write("transitions.csv", ["shape", "mu", "tract", "slipping", "dv_um"],
          [[s, m, t["tract"], t["slip"], t["dv_um"]] for s, per in summary["transitions"].items()
           for m, tr in per.items() for t in (tr or [])])
    write("paper_comparison.csv", ["table", "shape", "mu", "quantity", "paper", "ours", "deviation_pct"],
          [[t["table"], t["shape"], r["mu"], CSV_NAMES[k], r["paper"][k], r["ours"][k], r["dev_pct"][k]]
           for t in summary["paper_comparison"]["tables"] for r in t["rows"] for k in TABLE_B_KEYS])
    return files


# ---------------------------------------------------------------- k(psi_a): exact, band, interpolation
BAND_AMPLITUDES = 9  # band amplitudes per design, from BAND_LO_FS psi_fs to BAND_HI_BC psi_BC
BAND_SAMPLES = 64  # admissible initial states sampled per amplitude, before the refinement
BAND_LO_FS = 0.2
BAND_HI_BC = 1.5
CURVE_PER_BAND = 4  # exact curves: this many intervals per band interval (band points included)
NAMED_STATES = ("gross_slip", "assembly")
GAP_ROUNDING = 1e-9  # relative: a gap below this times the band's bound is rounding, reported as 0


def _num(v):
    """A JSON number: None for NaN / inf."""
    v = float(v)
    return v if math.isfinite(v) else None


def _nums(a):
    return [_num(v) for v in np.asarray(a, float).ravel()]


def interpolation_gap(psi, k, lo, hi) -> dict:
    """Largest distance (N mm/mrad) of the interpolated k (at the amplitudes psi, mrad) outside the
    band [lo, hi] (0 inside), the amplitude where it occurs, the side, and the gap in % of the band
    bound it passes. None-valued when no amplitude has a band."""
    k, lo, hi = (np.asarray(x, float) for x in (k, lo, hi))
    ok = np.isfinite(k) & np.isfinite(lo) & np.isfinite(hi)
    if not ok.any():
        return {"gap": None, "pct": None, "psi_a_mrad": None, "side": None}
    below, above = np.where(ok, lo - k, -np.inf), np.where(ok, k - hi, -np.inf)
    gap = np.maximum(np.maximum(below, above), 0.0)
    # A gap at the rounding level of the bound (the interpolation is exact beyond psi_BC) is none.
    gap = np.where(gap <= GAP_ROUNDING * np.maximum(np.abs(lo), np.abs(hi)), 0.0, gap)
    gap = np.where(ok, gap, -np.inf)
    i = int(np.argmax(gap))
    side = "inside" if gap[i] <= 0 else ("below" if below[i] >= above[i] else "above")
    bound = lo[i] if side == "below" else hi[i]
    pct = 100.0 * gap[i] / abs(bound) if abs(bound) > 0 else None
    return {"gap": float(gap[i]), "pct": None if pct is None else float(pct),
            "psi_a_mrad": float(psi[i]), "side": side}


def amplitude_grids(bc, n_amplitudes=BAND_AMPLITUDES):
    """(psi_fs, psi_BC, curve amplitudes, band amplitudes) in mrad of one Base-Cycle: the curve grid
    runs from BAND_LO_FS psi_fs to BAND_HI_BC psi_BC and holds the band grid as every
    CURVE_PER_BAND-th point."""
    from ..harmonics import five_numbers

    nums = five_numbers(bc)
    psi_fs, psi_bc = float(nums.psi_fs), float(nums.psi_bc)
    psi = np.linspace(BAND_LO_FS * psi_fs, BAND_HI_BC * psi_bc, CURVE_PER_BAND * (n_amplitudes - 1) + 1)
    return psi_fs, psi_bc, psi, psi[::CURVE_PER_BAND]


def exact_curves(shapes, mus, psi, contacts, load, runner=None) -> dict:
    """{initial: (k_re, k_im, status)} with (designs, amplitudes) arrays: the exact steady cycles
    of every design from both named initial states, in one batched call per state (one compiled
    kernel for the whole study); psi in mrad, k in N mm/mrad, NaN where the status is not valid.
    runner(program, args) -> outputs runs each compiled program instead of a plain call (the CLI
    passes its saved-program cache); so in every function below."""
    import jax

    from ..sequence import amplitude_curves

    stacked = jax.tree_util.tree_map(lambda *x: np.stack([np.asarray(v, float) for v in x]), *shapes)
    out = {}
    for initial in NAMED_STATES:
        cv = amplitude_curves(stacked, np.asarray(mus, float), np.asarray(psi), contacts, load,
                              initial=initial, runner=runner)
        st = np.asarray(cv.status)
        ok = np.asarray(RESULTS.valid(st))
        out[initial] = (np.where(ok, np.asarray(cv.k_re), np.nan),
                        np.where(ok, np.asarray(cv.k_im), np.nan), st)
    return out


def widen_band_to_named_states(bounds, named):
    """(bounds widened to hold the named states' k, how many bounds that moved): bounds (amplitudes,
    4) k_re_min, k_re_max, k_im_min, k_im_max (N mm/mrad, NaN where no sample was valid); named: per
    named state (k_re, k_im) on the same amplitudes (NaN where its cycle is not valid). A named
    value counts as outside only beyond the band's own rounding, `band.CONFIRM_TOL` of the k scale
    (the largest |k| here): a k_Im of 0 +- 1e-10 against a bound of 0 +- 1e-10 is the same number,
    whatever the compile options."""
    from ..band import CONFIRM_TOL

    bounds = np.array(bounds, float)
    values = [np.abs(bounds)] + [np.abs(np.asarray(k, float)) for pair in named for k in pair]
    finite = np.concatenate([v[np.isfinite(v)] for v in values])
    tol = CONFIRM_TOL * (finite.max() if finite.size else 0.0)
    missed = 0
    for pair in named:
        for j, k in enumerate(pair):
            k = np.asarray(k, float)
            have = np.isfinite(k)
            lo_b, hi_b = bounds[:, 2 * j], bounds[:, 2 * j + 1]
            out_lo = have & ~(k >= lo_b - tol)  # NaN bound (no valid sample) counts as outside
            out_hi = have & ~(k <= hi_b + tol)
            missed += int(out_lo.sum() + out_hi.sum())
            bounds[:, 2 * j] = np.where(out_lo, np.fmin(lo_b, k), lo_b)
            bounds[:, 2 * j + 1] = np.where(out_hi, np.fmax(hi_b, k), hi_b)
    return bounds, missed


def design_bands(shape, mu, contacts, load, bc, n_amplitudes=BAND_AMPLITUDES,
                 n_samples=BAND_SAMPLES, runner=None) -> list:
    """`band.amplitude_bands` of one design on the band grid of its `amplitude_grids` (n_samples
    states plus the vertices at each amplitude, refined sequence by sequence)."""
    from ..band import amplitude_bands

    return amplitude_bands(shape, mu, amplitude_grids(bc, n_amplitudes)[3], contacts, load,
                           n_samples=n_samples, runner=runner)


def stiffness_band_entry(shape, mu, contacts, load, bc, curves=None, n_amplitudes=BAND_AMPLITUDES,
                         n_samples=BAND_SAMPLES, runner=None, bands=None) -> dict:
    """For one design: the exact k_Re, k_Im (N mm/mrad) from both named initial states on the
    `amplitude_grids` grid (`curves`: this design's row of `exact_curves`, computed here if None),
    the paper's interpolation on it, the band over the admissible initial states at every
    CURVE_PER_BAND-th amplitude (`bands`: this design's `design_bands`, computed here if None),
    and the interpolation's largest gap to the band. The band is widened to hold the two named
    states' values (they are admissible states); `named_outside_samples` counts the bounds that
    needed it. Figures and report read this entry."""
    from ..harmonics import complex_stiffness

    if RESULTS.stopped(bc.status):
        return {"status": RESULTS.name_of(bc.status)}
    psi_fs, psi_bc, psi, grid = amplitude_grids(bc, n_amplitudes)
    if curves is None:
        curves = {k: tuple(x[0] for x in v)
                  for k, v in exact_curves([shape], [mu], psi[None], contacts, load,
                                           runner).items()}
    if bands is None:
        bands = design_bands(shape, mu, contacts, load, bc, n_amplitudes, n_samples, runner)
    at_band = slice(None, None, CURVE_PER_BAND)
    k_re_i, k_im_i = (np.asarray(x) for x in complex_stiffness(bc, psi, method="interpolated"))
    bounds, n_valid, status = [], [], []
    for b in bands:
        bounds.append(b.bounds)
        n_valid.append(b.n_valid)
        status.append(RESULTS(b.status).name)
    bounds, missed = widen_band_to_named_states(
        np.array(bounds), [(kr[at_band], ki[at_band]) for kr, ki, _ in
                           (curves[initial] for initial in NAMED_STATES)])
    gap = {name: interpolation_gap(grid, k[at_band], bounds[:, 2 * j], bounds[:, 2 * j + 1])
           for j, (name, k) in enumerate((("k_re", k_re_i), ("k_im", k_im_i)))}
    band_ok = any(s in ("ok", "shakedown") for s in status)
    return {
        "status": "ok" if band_ok else status[0],
        "psi_fs_mrad": psi_fs, "psi_bc_mrad": psi_bc,
        "curve": {"psi_a_mrad": _nums(psi),
                  **{initial: {"k_re": _nums(curves[initial][0]), "k_im": _nums(curves[initial][1]),
                               "status": [RESULTS(int(s)).name for s in curves[initial][2]]}
                     for initial in NAMED_STATES},
                  "interpolated": {"k_re": _nums(k_re_i), "k_im": _nums(k_im_i)}},
        "band": {"psi_a_mrad": _nums(grid), "n_samples": int(n_samples), "refined": True,
                 **{name: _nums(bounds[:, j]) for j, name in
                    enumerate(("k_re_min", "k_re_max", "k_im_min", "k_im_max"))},
                 "n_valid": n_valid, "status": status, "named_outside_samples": missed},
        "gap": gap,
    }


def stiffness_bands(cycles, contacts, load, n_amplitudes=BAND_AMPLITUDES, n_samples=BAND_SAMPLES,
                    progress=None, runner=None) -> dict:
    """`stiffness_band_entry` of every design of the study ({shape: {mu key: entry}}), the exact
    curves of all designs that do not lift off computed in one batch. The curves and the bands
    are independent (the grids come from the Base-Cycles) and mostly XLA compiling on a first
    run: they run side by side (`side_by_side`), the band program compiling while the curves'
    programs do."""
    from ..geometry import family_shape

    live = [(s, m) for s, per in cycles.items() for m, bc in per.items() if not RESULTS.stopped(bc.status)]

    def all_curves():
        if not live:
            return {}
        psi = np.stack([amplitude_grids(cycles[s][m], n_amplitudes)[2] for s, m in live])
        batch = exact_curves([family_shape(s) for s, _ in live], [float(m) for _, m in live], psi,
                             contacts, load, runner)
        return {key: {k: tuple(x[i] for x in v) for k, v in batch.items()}
                for i, key in enumerate(live)}

    def all_bands():
        return {(s, m): design_bands(family_shape(s), float(m), contacts, load, cycles[s][m],
                                     n_amplitudes, n_samples, runner) for s, m in live}

    curves, bands = side_by_side(all_curves, all_bands)
    out = {}
    for s, per in cycles.items():
        for m, bc in per.items():
            out.setdefault(s, {})[m] = stiffness_band_entry(
                family_shape(s), float(m), contacts, load, bc, curves.get((s, m)), n_amplitudes,
                n_samples, runner, bands.get((s, m)))
            if progress is not None:
                progress.update(1)
    return out


# ---------------------------------------------------------------- peak blade response
PEAK_FORCES_N = (5.0, 20.0)  # modal excitation forces of the shape comparison on peak response


def peak_response_entry(shape, mu, contacts, load, status, forces=PEAK_FORCES_N, runner=None) -> dict:
    """Peak tip amplitude A* (mm), its frequency (Hz) and psi_a = r A* (mrad) of the default
    BladeMode with this damper at each force (N), from the exact k(psi_a) (gross-slip history) and,
    for comparison, the paper's interpolation. One compiled kernel per method, shared by all
    designs. status: the design's Base-Cycle status; one that stopped part-way (liftoff, a failed
    solve) has no damper curve: numbers null, that status."""
    import jax.numpy as jnp

    from ..params import prepare_inputs
    from ..response import BladeMode, peak_program

    if RESULTS.stopped(status):
        return {"status": RESULTS.name_of(status), "liftoff": bool(status == RESULTS.liftoff)}
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    mode = BladeMode(*(jnp.asarray(v, float) for v in BladeMode()))
    entry = {"status": "ok", "liftoff": False, "forces_n": [float(f) for f in forces]}
    for method in ("exact", "interpolated"):
        # The forces share one amplitude grid; one compiled program per method for all designs.
        program = peak_program(method)
        args = (shape, mu, contacts, load, mode, jnp.asarray(forces, float))
        p = run_program(program, args, runner)
        st = [RESULTS(int(s)).name for s in np.asarray(p.status)]
        ok = np.array([s == "ok" for s in st])
        entry[method] = {
            "amplitude_mm": [_num(a) if o else None for a, o in zip(np.asarray(p.peak_amplitude_mm), ok)],
            "frequency_hz": [_num(f) if o else None for f, o in zip(np.asarray(p.peak_frequency_hz), ok)],
            "psi_a_mrad": [_num(a) if o else None for a, o in zip(np.asarray(p.psi_a_mrad), ok)],
            "n_roots": [int(n) for n in np.asarray(p.n_roots)],
            "status": st}
        if method == "exact" and not ok.all():
            entry["status"] = next(s for s in st if s != "ok")
    return entry


def blade_mode_dict() -> dict:
    """The default `jaxdamp.response.BladeMode` as a dict of floats (f0 in Hz, k_b in N/mm, ...),
    for the study's JSON."""
    from ..response import BladeMode

    return {k: float(v) for k, v in BladeMode()._asdict().items()}


def check_study_inputs(shapes, mus, kn=None, kt=None):
    """ValueError naming the parameter unless the study's inputs are valid (nothing is computed);
    returns the Contacts (kn, kt default to the reference pair). `run_study` calls it first."""
    from ..params import REFERENCE_KN, REFERENCE_KT, Contacts, validate_contacts, validate_mu

    if not shapes:
        raise ValueError("give at least one shape")
    if not mus:
        raise ValueError("give at least one friction coefficient")
    known = _tables()["shapes"]
    unknown = [s for s in shapes if s not in known]
    if unknown:
        raise ValueError(f"unknown shape(s) {', '.join(unknown)}; choose from {', '.join(known)}")
    for mu in mus:
        validate_mu(float(mu))
    kn = REFERENCE_KN if kn is None else kn
    kt = REFERENCE_KT if kt is None else kt
    return validate_contacts(Contacts(float(kn), float(kt)))


def compute_study(shapes=DEFAULT_SHAPES, mus=DEFAULT_MU, kn=None, kt=None, progress=None,
                  band_amplitudes=BAND_AMPLITUDES, band_samples=BAND_SAMPLES, peak_forces=PEAK_FORCES_N,
                  runner=None, beside=None):
    """Every shape x mu Base-Cycle of the study and its summary dict (the content of study.json,
    without figures), the exact k(psi_a) with its band and the interpolation's gap to it
    (`stiffness_band_entry`), and the peak blade response (`peak_response_entry`). Returns
    (summary, cycles, summaries); progress: None or a tqdm-like bar updated three times per case.
    Inputs are checked before any work (`check_study_inputs`). The bands, the peaks and the claim
    run in three threads: JAX settings made with a context manager (thread-local, such as
    `with jax.enable_x64(True):`) do not reach them; set float64 with
    `jax.config.update("jax_enable_x64", True)`. runner(program, args) -> outputs runs each
    compiled program instead of a plain call (the CLI passes its saved-program cache). beside:
    None or a function (cycles, summaries, load) called once the Base-Cycles are computed, in a
    fourth thread beside the three (the study's figures of the cycles are drawn there)."""
    import jax

    from ..params import LoadCase
    from .scoring import qualitative_findings, score_table

    t0 = time.perf_counter()
    contacts = check_study_inputs(shapes, mus, kn, kt)
    kn, kt = contacts
    tables = _tables()
    ref = tables["reference_case"]
    load = LoadCase(ref["F_D"], ref["q_star"], ref["r_sin_beta"])
    cycles, summaries, statics, transitions = compute_cases(shapes, mus, contacts, load, progress)
    t_cases = time.perf_counter() - t0
    from ..geometry import family_shape

    def all_peaks():
        peaks = {}
        for name, per in cycles.items():
            for m, bc in per.items():
                peaks.setdefault(name, {})[m] = peak_response_entry(
                    family_shape(name), float(m), contacts, load, bc.status, peak_forces, runner)
                if progress is not None:
                    progress.update(1)
        return peaks

    def timed(fn, *args):
        start = time.perf_counter()
        return fn(*args), time.perf_counter() - start

    # The bands, the peaks and the claim (curved-flat against wedge, claim.py) are independent and,
    # on a first run, mostly XLA compiling programs of their own: side by side, XLA compiles them
    # on separate cores. Each part's time below is its own, overlapping. `beside` (the figures of
    # the cycles) is mostly Python drawing: it runs while XLA compiles and runs the others.
    parts = [lambda: timed(stiffness_bands, cycles, contacts, load, band_amplitudes, band_samples,
                           progress, runner),
             lambda: timed(all_peaks),
             lambda: timed(platform_claim, mus, contacts, load, progress, runner)]
    if beside is not None:
        parts.append(lambda: timed(beside, cycles, summaries, load))
    (stiffness_band, t_band), (peaks, t_peaks), (claim, t_claim), *rest = side_by_side(*parts)
    results = {s: {m: result_entry(cs) for m, cs in per.items()} for s, per in summaries.items()}
    energies = {s: {m: cs.energy_Nmm for m, cs in per.items()} for s, per in summaries.items()}
    scores = score_table(results)
    worst = [e["status"] for per in results.values() for e in per.values()
             if e["status"] not in ("ok", "liftoff")]  # liftoff is a finding of the study, not a failure
    summary = {
        "status": worst[0] if worst else "ok",
        "schema_version": SCHEMA_VERSION,
        "jaxdamp_version": _version(),
        "results": results,
        "contacts": {"kn": float(kn), "kt": float(kt)},
        "load": {"F_D": float(load.F_D), "q_star": float(load.q_star), "r_sin_beta": float(load.r_sin_beta)},
        "paper_comparison": paper_comparison(results, tables),
        "scores": scores,
        "findings": qualitative_findings(results, scores),
        "notes": [NOTE_90R] if "90R" in shapes else [],
        "energies": energies,
        "statics": statics,
        "transitions": transitions,
        "paper_transitions": paper_transitions(tables, shapes, [mu_key(m) for m in mus]),
        "stiffness_band": stiffness_band,
        "peak_response": {"mode": blade_mode_dict(), "forces_n": [float(f) for f in peak_forces],
                          "results": peaks},
        "platform_claim": claim,
        "meta": {"shapes": list(shapes), "mus": [mu_key(m) for m in mus], "version": _version(),
                 "jax": jax.__version__, "runtime_s": time.perf_counter() - t0,
                 "runtime_parts_s": {"base_cycles": t_cases, "stiffness_band": t_band,
                                     "peak_response": t_peaks, "platform_claim": t_claim,
                                     **({"beside": rest[0][1]} if rest else {})}},
    }
    return summary, cycles, summaries


def write_study(out: Path, summary: dict) -> None:
    """Write study.json, the CSV tables and the report (Markdown and HTML) into out."""
    from .report import build_report

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    write_tables(out / "tables", summary)
    doc = build_report(summary)
    write_text(out / "report.md", doc.markdown())
    write_text(out / "report.html", doc.html())
    write_text(out / "study.json", json.dumps(summary, indent=1, ensure_ascii=False))


def _version() -> str:
    return __version__  # the one place the version lives (pyproject reads it too)


__all__ = ["SCHEMA_VERSION", "DEFAULT_SHAPES", "DEFAULT_MU", "CONTRACT_KEYS", "PAPER_TABLES",
           "CRITERION_TABLES", "CRITERION_TOL_PCT", "TABLE_B_KEYS", "NOTE_90R", "mu_key",
           "paper_transitions", "paper_comparison", "paper_values", "compute_cases",
           "result_entry", "CSV_NAMES", "write_tables", "BAND_AMPLITUDES", "BAND_SAMPLES",
           "BAND_LO_FS", "BAND_HI_BC", "CURVE_PER_BAND", "NAMED_STATES", "GAP_ROUNDING",
           "interpolation_gap", "amplitude_grids", "exact_curves", "design_bands", "stiffness_band_entry",
           "widen_band_to_named_states",
           "stiffness_bands", "PEAK_FORCES_N", "peak_response_entry", "blade_mode_dict",
           "check_study_inputs", "compute_study", "write_study"]
