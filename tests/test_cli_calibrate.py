"""`jaxdamp calibrate`: the JSON contract; bad start and unusable --markdown fail before work."""

import pytest

import jaxdamp as jd
from jaxdamp.paper import calibration as cal

from helpers import one_error_line, run_cli, strict_json

KN0, KT0 = jd.REFERENCE_KN, jd.REFERENCE_KT
FITTED = {"60sym": "B3.1", "74R": "B4.1"}


@pytest.mark.slow  # 28 worker-s (run of 2026-11-25)
def test_cli_json_contract(capsys, paper, tmp_path):
    md = tmp_path / "cmp.md"
    code, out, _ = run_cli(capsys, "calibrate", "--json", "--start-kn", 3 * KN0, "--start-kt", KT0 / 3,
                           "--markdown", md)
    assert code == 0
    d = strict_json(out)
    assert {"kn", "kt", "residuals_pct", "iterations", "residuals_90R_pct", "status", "inputs"} <= set(d)
    assert d["status"] in ("ok", "not_converged") and d["inputs"]["start"]["kn_n_per_mm"] == 3 * KN0
    assert isinstance(d["kn"], float) and isinstance(d["kt"], float) and d["kn"] > 0 and d["kt"] > 0
    assert isinstance(d["iterations"], int) and d["iterations"] >= 1
    keys = {f"{s}/{row[0]:g}/{n}" for s in FITTED for row in paper["table_B"][s] for n in cal.NUMBERS}
    assert set(d["residuals_pct"]) == keys
    assert max(abs(v) for v in d["residuals_pct"].values()) <= 2.0
    assert all(k.startswith("90R/") and not k.endswith("k_im_bc") for k in d["residuals_90R_pct"])
    assert len(d["residuals_90R_pct"]) == 12
    assert "Table B3.1 (60sym)" in md.read_text()
    # The convergence is shown: iterate 0 is the start, the last row is the result.
    hist = d["history"]
    assert len(hist) == d["iterations"] + 1 and hist[0]["iterate"] == 0
    assert hist[0]["kn"] == pytest.approx(3 * KN0) and hist[-1]["kn"] == pytest.approx(d["kn"])
    assert hist[-1]["loss"] == pytest.approx(d["loss"])


def test_cli_rejects_bad_start(capsys):
    code, _, err = run_cli(capsys, "calibrate", "--start-kn", "-5")
    assert code == 2 and "start" in one_error_line(err)
    code, _, err = run_cli(capsys, "calibrate", "--start-kt", "inf")
    assert code == 2 and "(0, inf)" in one_error_line(err)


def test_cli_rejects_missing_markdown_dir_before_work(capsys, tmp_path):
    code, out, err = run_cli(capsys, "calibrate", "--markdown", tmp_path / "nowhere" / "cmp.md")
    assert code == 2 and out == "" and "--markdown" in one_error_line(err)
