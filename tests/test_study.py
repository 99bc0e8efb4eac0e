"""`jaxdamp study`: study.json contract, paper tables, Table 11 scores, figures, report, CLI."""

import json
import struct

import pytest

from jaxdamp.params import REFERENCE_KN, REFERENCE_KT
from jaxdamp.paper.scoring import qualitative_findings, rank_indicator, score_table
from jaxdamp.paper.study import CONTRACT_KEYS, DEFAULT_SHAPES
from jaxdamp.plotting.study import run_study

MU_KEYS = ["0.7", "0.5", "0.3"]
TABLE_B_KEYS = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc")


@pytest.fixture(scope="module")
def full(tmp_path_factory):
    """The default study (whole family, three mu), numbers and report only."""
    out = tmp_path_factory.mktemp("study_full")
    run_study(out, progress=False, figures=False)
    return out, json.loads((out / "study.json").read_text())


@pytest.fixture(scope="module")
def with_figures(tmp_path_factory):
    """A reduced study with figures: 60sym and 74L (which lifts off at mu = 0.7), drawn in two worker
    processes (the CLI's way)."""
    out = tmp_path_factory.mktemp("study_figs")
    run_study(out, shapes=("60sym", "74L"), mus=(0.7, 0.3), progress=False, figure_processes=2)
    return out, json.loads((out / "study.json").read_text())


# ---------------------------------------------------------------- study.json contract
@pytest.mark.slow  # 131 worker-s (run of 2026-11-25)
def test_study_json_contract(full):
    _, s = full
    assert list(s["results"]) == list(DEFAULT_SHAPES)
    assert s["contacts"] == {"kn": REFERENCE_KN, "kt": REFERENCE_KT}
    for shape, per_mu in s["results"].items():
        assert list(per_mu) == MU_KEYS, shape
        for mu, e in per_mu.items():
            assert set(CONTRACT_KEYS) | {"liftoff", "converged"} <= set(e), (shape, mu)
            assert isinstance(e["liftoff"], bool) and isinstance(e["converged"], bool)
            # the file's booleans are read from the status, the one truth
            assert e["liftoff"] == (e["status"] == "liftoff") and e["converged"] == (e["status"] == "ok")
            for k in CONTRACT_KEYS:
                assert (e[k] is None) == e["liftoff"], (shape, mu, k)
                if not e["liftoff"]:
                    assert isinstance(e[k], float)


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_74L_lifts_off_at_mu_07_and_is_shown_as_such(full):
    out, s = full
    e = s["results"]["74L"]["0.7"]
    assert e["liftoff"] and not e["converged"]
    assert all(e[k] is None for k in CONTRACT_KEYS)
    others = [(sh, m) for sh, per in s["results"].items() for m, x in per.items() if x["liftoff"]]
    assert others == [("74L", "0.7")]
    report = (out / "report.md").read_text()
    assert "**LIFTOFF**" in report and "74L at μ = 0.7" in report
    assert "| 74L | 0.7 | LIFTOFF |" in report


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_every_valid_case_converges(full):
    _, s = full
    assert all(e["converged"] for per in s["results"].values() for e in per.values() if not e["liftoff"])


# ---------------------------------------------------------------- the paper's tables
@pytest.mark.parametrize("shape", ["60sym", "74R"])
@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_tables_B3_B4_within_2_percent_and_in_report(full, paper, shape):
    """Tables B3.1 (60sym) and B4.1 (74R), every number, within 2 % of the paper."""
    out, s = full
    report = (out / "report.md").read_text()
    worst = 0.0
    for row in paper["table_B"][shape]:
        mu = f"{row[0]:g}"
        ours = s["results"][shape][mu]
        for key, ref in zip(TABLE_B_KEYS, row[1:]):
            dev = 100.0 * (ours[key] - ref) / ref
            worst = max(worst, abs(dev))
            assert f"{dev:+.2f} %" in report, (shape, mu, key)
    assert worst <= 2.0, f"{shape}: largest deviation from the paper {worst:.2f} %"


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_states_the_2_percent_criterion_truthfully(full, paper):
    out, s = full
    worst = max(abs(100.0 * (s["results"][sh][f"{row[0]:g}"][k] - ref) / ref)
                for sh in ("60sym", "74R") for row in paper["table_B"][sh]
                for k, ref in zip(TABLE_B_KEYS, row[1:]))
    crit = s["paper_comparison"]["criterion"]
    assert crit["max_abs_dev_pct"] == pytest.approx(worst, rel=1e-12)
    assert crit["holds"] == (worst <= 2.0)
    verdict = "**met**" if worst <= 2.0 else "**not met**"
    assert f"largest |deviation| {worst:.2f} %: {verdict}" in (out / "report.md").read_text()


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_table_1_resultant_distances(full, paper):
    """60sym's left-resultant distances (Table 1) from the study's statics."""
    _, s = full
    for row in paper["table_1_60sym_resultant_distance"]["rows"]:
        d = s["statics"]["60sym"][f"{row['mu']:g}"]
        assert d["dist_L1"] == pytest.approx(row["dist_L1"], abs=0.06)
        assert d["dist_L2"] == pytest.approx(row["dist_L2"], abs=0.06)


@pytest.mark.slow  # 136 worker-s (run of 2026-11-25)
def test_paper_qualitative_findings_hold(full):
    """§10.1: 90L most best scores, 74L most worst, 90R lowest w_M, 60sym's 50 % R1 share."""
    out, s = full
    sc = s["scores"]
    assert max(sc["best_count"], key=sc["best_count"].get) == "90L"
    assert sorted(sc["best_count"].values())[-1] > sorted(sc["best_count"].values())[-2]
    assert max(sc["worst_count"], key=sc["worst_count"].get) == "74L"
    assert sorted(sc["worst_count"].values())[-1] > sorted(sc["worst_count"].values())[-2]
    for mu in MU_KEYS:
        valid = {k: per[mu]["w_M"] for k, per in s["results"].items() if not per[mu]["liftoff"]}
        assert min(valid, key=valid.get) == "90R", mu
        e = s["results"]["60sym"][mu]
        assert e["w_R1"] / e["w_M"] == pytest.approx(0.5, abs=1e-3)
        assert e["w_L1"] / (e["w_L1"] + e["w_L2"]) == pytest.approx(2 / 3, abs=0.03)
    assert all(f["holds"] for f in s["findings"]), [f["claim"] for f in s["findings"] if not f["holds"]]
    assert (out / "report.md").read_text().count("**holds**") == len(s["findings"])


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_tables_written(full):
    out, s = full
    for name in ("five_numbers.csv", "work_shape_factors.csv", "scores.csv", "transitions.csv",
                 "paper_comparison.csv"):
        lines = (out / "tables" / name).read_text().splitlines()
        assert len(lines) > 5, name
    header = (out / "tables" / "five_numbers.csv").read_text().splitlines()[0].split(",")
    assert header[2:7] == ["psi_fs_mrad", "k_re_fs_Nmm_per_mrad", "psi_bc_mrad", "k_re_bc_Nmm_per_mrad",
                           "k_im_bc_Nmm_per_mrad"]  # every k_* column says its unit
    quantities = {ln.split(",")[3] for ln in (out / "tables" / "paper_comparison.csv").read_text().splitlines()[1:]}
    assert quantities == {"psi_fs_mrad", "k_re_fs_Nmm_per_mrad", "psi_bc_mrad", "k_re_bc_Nmm_per_mrad",
                          "k_im_bc_Nmm_per_mrad"}
    trans = s["transitions"]["60sym"]["0.7"]
    assert [t["tract"] for t in trans][:3] == ["0-A", "A-B", "B-C"]
    # Table 2: 0-A all stick, A-B L2 slips, B-C L1 and L2 slip.
    assert [t["slip"] for t in trans][:3] == ["—", "L2", "L1 L2"]


# ---------------------------------------------------------------- Table 11 scoring logic
def _entry(**kw):
    e = {"k_re_fs": 1.0, "psi_bc_mrad": 1.0, "k_re_bc": 1.0, "w_M": 1.0, "liftoff": False}
    e.update(kw)
    return e


def test_score_table_hand_made_example():
    """Four shapes, one mu; known marks including a tie and a liftoff."""
    results = {
        "A": {"0.5": _entry(k_re_fs=30.0, psi_bc_mrad=2.0, k_re_bc=20.0, w_M=3.0)},
        "B": {"0.5": _entry(k_re_fs=20.0, psi_bc_mrad=1.0, k_re_bc=25.0, w_M=2.0)},
        "C": {"0.5": _entry(k_re_fs=10.0, psi_bc_mrad=3.0, k_re_bc=10.0, w_M=2.0)},
        "D": {"0.5": _entry(k_re_fs=99.0, psi_bc_mrad=0.1, k_re_bc=99.0, w_M=9.0, liftoff=True)},
    }
    sc = score_table(results, mus=("0.5",))
    m = sc["marks"]["0.5"]
    assert m["k_re_fs"] == {"A": "best", "B": "second", "C": "worst"}
    assert m["psi_bc_mrad"] == {"A": "second", "B": "best", "C": "worst"}
    assert m["k_re_bc"] == {"A": "second", "B": "best", "C": "worst"}
    assert m["w_M"] == {"A": "best", "B": "worst", "C": "worst"}  # B and C tie: two levels only
    assert sc["best_count"] == {"A": 2, "B": 2, "C": 0, "D": 0}
    assert sc["worst_count"] == {"A": 0, "B": 1, "C": 4, "D": 0}
    assert sc["excluded"] == [["D", "0.5", "liftoff"]]
    assert "D" not in sc["values"]["0.5"]["w_M"]


def test_rank_indicator_directions_and_ties():
    assert rank_indicator({"a": 1.0, "b": 2.0, "c": 3.0, "d": 4.0}, "min") == {
        "a": "best", "b": "second", "c": "", "d": "worst"}
    assert rank_indicator({"a": 1.0, "b": 1.0 + 1e-9, "c": 0.5}, "max") == {
        "a": "best", "b": "best", "c": "worst"}
    assert rank_indicator({"a": 1.0}, "max") == {"a": "best"}
    with pytest.raises(ValueError, match="better"):
        rank_indicator({"a": 1.0}, "highest")


def test_findings_report_a_finding_that_does_not_hold():
    """With 74R made the clear worst, '74L most worst' must be reported as not holding."""
    results = {s: {"0.5": _entry(k_re_fs=10.0 + i, psi_bc_mrad=5.0 - i, k_re_bc=10.0 + i, w_M=1.0 + i)}
               for i, s in enumerate(["74R", "74L", "60sym", "90R", "90L"])}
    results["90R"]["0.5"]["w_M"] = 0.1
    for e in (results["60sym"]["0.5"],):
        e.update(w_R1=0.5 * e["w_M"], w_L1=e["w_M"] / 3, w_L2=e["w_M"] / 6)
    sc = score_table(results, mus=("0.5",))
    found = {f["claim"].split(" (")[0].split(":")[0]: f["holds"] for f in qualitative_findings(results, sc)}
    assert found["74L collects the most worst scores"] is False
    assert found["90L collects the most best scores"] is True
    assert found["90R has the lowest w_M of the family"] is True


# ---------------------------------------------------------------- figures and report
def _png_size(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    width, height = struct.unpack(">II", data[16:24])
    return len(data), width, height


@pytest.mark.slow  # 43 worker-s (run of 2026-11-25)
def test_figures_exist_and_are_real_pngs(with_figures):
    out, s = with_figures
    files = [f["file"] for f in s["figures"]]
    for kind in ("section", "tracks", "moment", "stretched", "stiffness", "amplitude_stiffness"):
        for shape in ("60sym", "74L"):
            assert f"figures/{kind}_{shape}.png" in files
    assert {"figures/energy.png", "figures/family.png", "figures/key_figure.png"} <= set(files)
    # The cycles' figures are drawn while the bands compute (in worker processes), the rest after:
    # the report's order is still each shape's five cycle figures, then the others.
    kinds = ("section", "tracks", "moment", "stretched", "stiffness")
    assert files[:10] == [f"figures/{k}_{shape}.png" for shape in ("60sym", "74L") for k in kinds]
    assert len(files) == len(set(files))
    for f in files:
        nbytes, w, h = _png_size(out / f)
        assert nbytes > 30_000 and w >= 700 and h >= 450, (f, nbytes, w, h)


@pytest.mark.slow  # the reduced study with figures (fixture `with_figures`): 223 worker-s
def test_report_html_and_markdown_reference_every_figure(with_figures):
    out, s = with_figures
    md = (out / "report.md").read_text()
    html = (out / "report.html").read_text()
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>")
    assert html.count("<table>") == sum(line.startswith("|---") for line in md.splitlines()) > 5
    for f in s["figures"]:
        assert f"]({f['file']})" in md
        assert f'src="{f["file"]}"' in html
    assert "60sym" in md and "Table B3.1" in md


SHAPE_NAMES = ("90L", "74L", "60sym", "74R", "90R")


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_has_a_contents_list_and_shape_names_in_every_heading(full):
    out, _ = full
    md = (out / "report.md").read_text()
    heads = [line.lstrip("#").strip() for line in md.splitlines() if line.startswith("## ")
             or line.startswith("### ")]
    assert len(heads) > 10
    for h in heads:
        assert any(s in h for s in SHAPE_NAMES), h
        assert f"[{h}](#" in md, f"heading {h!r} missing from the contents"
    html = (out / "report.html").read_text()
    assert "<nav><b>Contents</b>" in html
    # Every contents link points at an existing heading id.
    for anchor in __import__("re").findall(r'<a href="#([^"]+)">', html):
        assert f'id="{anchor}"' in html, anchor


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_states_the_90R_caveat_once(full):
    from jaxdamp.paper.study import NOTE_90R

    out, _ = full
    md = (out / "report.md").read_text()
    assert md.count(NOTE_90R) == 1
    assert md.count("the paper's 79 / 33 / 168") + md.count("The paper's 79 / 33 / 168") == 1
    assert "90R: see the note under Table B5.1." in md


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_text_cells_are_left_aligned(full):
    out, _ = full
    html = (out / "report.html").read_text()
    assert "td,th{border:1px solid #bbb;padding:3px 8px;text-align:left}td.num{text-align:right}" in html
    assert '<td class="txt">0-A: —' in html  # the transitions charts
    assert '<td class="num">0.7</td>' in html


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_explains_W_R1_zero_beside_w_R1_50_percent(full):
    """60sym: R1 sticks through the Base-Cycle (W_R1 = 0) yet carries half of w_M; the report says why,
    and the reason holds: energy beyond psi_BC grows as F_D * 2 (psi_a - psi_BC) * q*/2 * w_i."""
    import jaxdamp as jd
    from jaxdamp.harmonics import base_cycle_amplitude

    out, s = full
    e, en = s["results"]["60sym"]["0.7"], s["energies"]["60sym"]["0.7"]
    assert abs(en["R1"]) < 1e-9 and e["w_R1"] / e["w_M"] == pytest.approx(0.5, abs=1e-3)
    md = (out / "report.md").read_text()
    assert "Why W and w can disagree (e.g. W_R1 = 0 beside w_R1 = 50 %)" in md
    assert "R1 of 60sym at μ = 0.7" in md
    bc = jd.base_cycle(jd.family_shape("60sym"), 0.7)
    psi_bc = float(base_cycle_amplitude(bc))
    extra = 1.5  # mrad beyond the Base-Cycle
    gain = (jd.contact_energies(bc, psi_bc + extra).contacts - jd.contact_energies(bc).contacts)
    ref = [s["load"]["F_D"] * 2 * extra * 1e-3 * s["load"]["q_star"] / 2 * e[f"w_{c}"] for c in ("R1", "L1", "L2")]
    assert [float(g) for g in gain] == pytest.approx(ref, rel=1e-9)


@pytest.mark.slow  # the reduced study with figures (fixture `with_figures`): 223 worker-s
def test_key_figure_has_its_own_heading(with_figures):
    out, _ = with_figures
    md = (out / "report.md").read_text()
    head = md.index("## Key figure: 60sym at μ = 0.7")
    assert md.index("](figures/key_figure.png)") > head
    assert md.index("](figures/key_figure.png)") < md.index("\n## ", head + 5)
    assert md.count("](figures/key_figure.png)") == 1


# ---------------------------------------------------------------- k(psi_a) band and peak response
def _arr(v):
    import numpy as np

    return np.array([np.nan if x is None else x for x in v], float)


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_stiffness_band_entries_have_status_gaps_and_finite_or_null_numbers(full):
    import math

    _, s = full
    bands = s["stiffness_band"]
    assert list(bands) == list(DEFAULT_SHAPES)
    for shape, per in bands.items():
        assert list(per) == MU_KEYS, shape
        for mu, e in per.items():
            if s["results"][shape][mu]["liftoff"]:
                assert e == {"status": "liftoff"}, (shape, mu)
                continue
            assert e["status"] == "ok", (shape, mu)
            grid = e["band"]["psi_a_mrad"]
            assert len(grid) >= 2 and all(isinstance(x, float) for x in grid)
            assert grid[0] < e["psi_fs_mrad"] and grid[-1] > e["psi_bc_mrad"]
            for key in ("k_re_min", "k_re_max", "k_im_min", "k_im_max", "n_valid", "status"):
                assert len(e["band"][key]) == len(grid), (shape, mu, key)
            for k in ("k_re", "k_im"):
                g = e["gap"][k]
                assert g["side"] in ("inside", "above", "below")
                assert isinstance(g["gap"], float) and math.isfinite(g["gap"]) and g["gap"] >= 0.0
                assert g["pct"] is None or (math.isfinite(g["pct"]) and g["pct"] >= 0.0)
                assert g["psi_a_mrad"] in grid
                assert (g["gap"] == 0.0) == (g["side"] == "inside")


# Two routes to one stiffness agree to ~10^2 units of round-off (cycles of a few tracts, each a
# 3x3 solve, and a first-harmonic sum; 38 units seen): 1e-12 of the stiffness scale is ~4500
# units, still a million times tighter than the 1e-6 at which a band that missed a history's
# state would show.
BOUND_ROUNDOFF = 1e-12


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_band_holds_both_named_states_and_the_exact_base_cycle_beyond_psi_bc(full):
    """Every amplitude of the band: both named states' exact k lie in [min, max]; beyond psi_BC
    the paper's curve is the Base-Cycle's own (stretched-cycle) first harmonic, an admissible
    history computed by another route (jaxdamp.harmonics), so it lies in the band too."""
    import numpy as np

    _, s = full
    for shape, per in s["stiffness_band"].items():
        for mu, e in per.items():
            if "band" not in e:
                continue
            b, c = e["band"], e["curve"]
            grid = np.array(b["psi_a_mrad"])
            at = [int(np.argmin(np.abs(np.array(c["psi_a_mrad"]) - p))) for p in grid]
            for j, k in enumerate(("k_re", "k_im")):
                lo, hi = _arr(b[f"{k}_min"]), _arr(b[f"{k}_max"])
                # Where the damper is stuck under every history the band is one point, which the
                # named states reach by other floating-point routes: they equal its bounds to
                # round-off, not bit for bit (90L at mu 0.5: 41270.15991929 both, 8.5e-15 apart).
                # Round-off of a stiffness is relative to the problem's stiffness scale, the
                # stuck damper's k_Re,fs (no history's k exceeds it): BOUND_ROUNDOFF of it.
                roundoff = BOUND_ROUNDOFF * abs(s["results"][shape][mu]["k_re_fs"])
                for initial in ("gross_slip", "assembly"):
                    v = _arr(c[initial][k])[at]
                    have = np.isfinite(v)
                    assert np.all((lo[have] - roundoff <= v[have]) & (v[have] <= hi[have] + roundoff)), \
                        (shape, mu, initial, k, np.max(np.maximum(lo - v, v - hi)[have]))
                v = _arr(c["interpolated"][k])[at]
                beyond = grid >= e["psi_bc_mrad"] * (1 + 1e-9)
                tol = 1e-9 * np.nanmax(np.abs(hi))
                assert np.all((lo[beyond] - tol <= v[beyond]) & (v[beyond] <= hi[beyond] + tol)), (shape, mu, k)


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_peak_response_entries_are_physical_and_mark_liftoff(full):
    """A* lies in (0, F/(eta k_b)] (k_Im >= 0); its frequency between the free f0 and the stuck
    damper's f0 sqrt(1 + 1e-3 r^2 k_Re,fs / k_b) (0 <= k_Re <= the stick stiffness)."""
    _, s = full
    pr = s["peak_response"]
    md, forces = pr["mode"], pr["forces_n"]
    assert forces and list(pr["results"]) == list(DEFAULT_SHAPES)
    for shape, per in pr["results"].items():
        for mu, e in per.items():
            if s["results"][shape][mu]["liftoff"]:
                assert e["liftoff"] and e["status"] == "liftoff" and "exact" not in e
                continue
            assert e["status"] == "ok" and not e["liftoff"]
            f_stuck = md["f0_hz"] * (1 + 1e-3 * md["r"] ** 2 * s["results"][shape][mu]["k_re_fs"] / md["k_b"]) ** 0.5
            for method in ("exact", "interpolated"):
                r = e[method]
                for i, f in enumerate(forces):
                    a, hz = r["amplitude_mm"][i], r["frequency_hz"][i]
                    assert r["status"][i] == "ok" and r["n_roots"][i] >= 1, (shape, mu, method, f)
                    assert 0.0 < a <= f / (md["eta"] * md["k_b"]) * (1 + 1e-9), (shape, mu, method, f)
                    assert md["f0_hz"] <= hz <= f_stuck * (1 + 1e-12), (shape, mu, method, f)
                    assert abs(r["psi_a_mrad"][i] - md["r"] * a) <= 1e-12 * a


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_gap_and_band_lines_say_what_they_mean(full):
    """The gap cells name the bound they pass and the units; the count of band bounds widened to a
    named state says of how many (was "982 (518.2 %, above)" and "Band bounds that the samples
    missed and a named state set: 27.")."""
    out, s = full
    md = (out / "report.md").read_text()
    assert "samples missed and a named state set" not in md and "%, above)" not in md
    gaps = [e["gap"]["k_re"] for per in s["stiffness_band"].values() for e in per.values() if "gap" in e]
    g = next(g for g in gaps if g["gap"])
    bound = "maximum" if g["side"] == "above" else "minimum"
    assert f"{g['side']} the band's {bound} (" in md and f"% of that {bound}) at ψ_a = " in md
    drawn = [e["band"] for per in s["stiffness_band"].values() for e in per.values() if "band" in e]
    missed = sum(b["named_outside_samples"] for b in drawn)
    assert f"Of the {sum(4 * len(b['psi_a_mrad']) for b in drawn)} band bounds" in md
    if missed:
        assert f"), {missed} lay outside every sampled initial state" in md
    else:  # the study's case since the count ignores rounding: no widening to claim
        assert "), none lay outside the sampled initial states: the samples held both" in md
        assert "the band was widened" not in md


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_report_shows_the_gaps_and_the_peak_response(full):
    out, s = full
    report = (out / "report.md").read_text()
    assert "The paper's interpolation against the band of exact cycles" in report
    assert "The shapes compared on peak blade response" in report
    g = s["stiffness_band"]["60sym"]["0.5"]["gap"]["k_re"]
    if g["gap"] > 0:
        bound = "maximum" if g["side"] == "above" else "minimum"
        assert (f"{g['side']} the band's {bound} ({g['pct']:.1f} % of that {bound}) at ψ_a = "
                f"{g['psi_a_mrad']:.3f} mrad") in report
    a = s["peak_response"]["results"]["60sym"]["0.5"]["exact"]["amplitude_mm"][0]
    assert f"| 60sym | 0.5 | {a:.3f} |" in report
    assert "| 74L | 0.7 | LIFTOFF |" in report


@pytest.mark.slow  # the whole-family study (fixture `full`): 243 worker-s
def test_the_platform_claim_is_computed_and_reported(full):
    from jaxdamp.paper.claim import CLAIM_AMPLITUDES_MRAD, CLAIM_PHIS_DEG

    out, summary = full
    claim = summary["platform_claim"]
    assert {c["damper"] for c in claim["curves"]} == {"60sym", "wedge"}
    assert len(claim["curves"]) == 2 * len(summary["meta"]["mus"]) * len(CLAIM_AMPLITUDES_MRAD)
    for c in claim["curves"]:
        assert [r["ibpa_deg"] for r in c["rows"]] == list(CLAIM_PHIS_DEG)
        assert len(c["pads"]) == (4 if c["damper"] == "wedge" else 3)
        first = c["rows"][0]
        assert first["status"] == "ok" and first["k_im_over_in_phase"] == 1.0
    report = (out / "report.md").read_text()
    assert "# 60sym (curved-flat) against its wedge on every platform motion" in report


def test_the_claim_section_counts_what_its_table_shows():
    from jaxdamp.paper.claim import claim_section
    from jaxdamp.paper.report import Doc, fmt

    def curve(damper, pads, opened, status):
        return {"damper": damper, "pads": pads, "mu": 0.5, "amplitude_mrad": 10.0,
                "rows": [{"ibpa_deg": p, "status": s, "k_im_over_in_phase": 1.0 - p / 360,
                          "open_fraction": o} for p, o, s in zip((0.0, 90.0, 180.0), opened, status)]}

    claim = {"h_c_mm": 20.0, "h_l_mm": 10.0, "wedge_br2_over_hr": 0.8, "curves": [
        curve("60sym", ["R1", "L1", "L2"], [[0.0] * 3] * 3, ["ok", "ok", "shakedown"]),
        curve("wedge", ["R1", "R2", "L1", "L2"], [[0.0] * 4, [0.25, 0.0, 0.1, 0.0], [0.5] * 4],
              ["ok", "ok", "unseated"])]}
    doc = Doc("t")
    claim_section(doc, claim, [], fmt)
    text = doc.markdown()
    assert "| 60sym | 0.5 | 10 | 1.00 / 0.00 | 0.75 / 0.00 | 0.50 / 0.00 |" in text
    assert "| wedge | 0.5 | 10 | 1.00 / 0.00 | 0.75 / 0.25 | unseated |" in text
    assert "- 60sym: no pad opens at any phase angle, amplitude or μ." in text
    assert ("- wedge: a pad opens in 1 of 2 valid cycles, for up to 25.00 % of the period "
            "(μ = 0.5, a = 10 mrad, φ = 90°); 1 without a valid cycle.") in text


def test_cycle_figures_are_drawn_beside_only_off_screen(monkeypatch):
    """run_study draws the cycles' figures in a thread of their own only with a backend that draws
    off screen (the CLI's Agg): a GUI backend's windows belong to the main thread, so there they
    are drawn after the computing, on the calling thread."""
    import matplotlib

    from jaxdamp.plotting.study import draws_off_screen

    for backend, off in (("agg", True), ("Agg", True), ("svg", True), ("TkAgg", False),
                         ("QtAgg", False), ("module://matplotlib_inline.backend_inline", False)):
        monkeypatch.setattr(matplotlib, "get_backend", lambda b=backend: b)
        assert draws_off_screen() is off, backend


def test_named_states_widen_the_band_only_beyond_its_rounding():
    """A named state's k outside the sampled band widens it and is counted; one that equals a bound
    to the band's rounding (a k_Im of 0 +- 1e-10 against a bound of 0 +- 1e-10) is the same number
    and is not; a bound with no valid sample (NaN) takes the named value."""
    import numpy as np

    from jaxdamp.band import CONFIRM_TOL
    from jaxdamp.paper.study import widen_band_to_named_states

    nan = float("nan")
    # two amplitudes: k_re_min, k_re_max, k_im_min, k_im_max (N mm/mrad); scale 10000
    bounds = np.array([[9000.0, 10000.0, -1e-10, 1e-10],
                       [8000.0, 9500.0, nan, nan]])
    near_zero = 1e-10 + 0.5 * CONFIRM_TOL * 1e4  # beyond the bound by half the tolerance
    named = [(np.array([9500.0, 7990.0]), np.array([near_zero, 300.0]))]
    widened, missed = widen_band_to_named_states(bounds, named)
    expected = np.array([[9000.0, 10000.0, -1e-10, 1e-10],
                         [7990.0, 9500.0, 300.0, 300.0]])
    np.testing.assert_array_equal(widened, expected)
    assert missed == 3  # k_re below the second minimum, and k_im against both NaN bounds
    # beyond the tolerance it counts and widens
    far = 1e-10 + 2.0 * CONFIRM_TOL * 1e4
    widened, missed = widen_band_to_named_states(bounds[:1], [(np.array([9500.0]), np.array([far]))])
    assert missed == 1 and widened[0, 3] == far


@pytest.mark.parametrize("bad", [-1, True, 1.5])
def test_run_study_checks_figure_processes_before_any_work(tmp_path, bad):
    with pytest.raises(ValueError, match=r"figure_processes must be an integer in \[0, inf\)"):
        run_study(tmp_path / "o", progress=False, figure_processes=bad)
    assert not (tmp_path / "o").exists()
