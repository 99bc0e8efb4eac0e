"""`jaxdamp study` and `jaxdamp section`: outputs, status in study.json, errors before work."""

import struct

import pytest

from helpers import one_error_line, run_cli, strict_json


def _png_size(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    width, height = struct.unpack(">II", data[16:24])
    return len(data), width, height


@pytest.mark.slow  # 189 worker-s (run of 2026-11-25)
def test_cli_study_subset(tmp_path, capsys):
    code, out, _ = run_cli(capsys, "study", "--out", tmp_path, "--shapes", "60sym", "--mu", "0.5",
                           "--no-progress", "--no-figures")
    assert code == 0
    s = strict_json((tmp_path / "study.json").read_text())
    assert list(s["results"]) == ["60sym"] and list(s["results"]["60sym"]) == ["0.5"]
    assert s["status"] == "ok" and s["schema_version"] == 2 and s["results"]["60sym"]["0.5"]["status"] == "ok"
    assert (tmp_path / "report.html").exists()
    assert "study.json" in out and "[status: ok]" in out.splitlines()[0]


def test_cli_study_json_and_liftoff_case(tmp_path, capsys):
    code, out, _ = run_cli(capsys, "study", "--out", tmp_path, "--shapes", "74L", "--mu", "0.7",
                           "--no-figures", "--json")
    assert code == 0
    d = strict_json(out)
    entry = d["results"]["74L"]["0.7"]
    assert entry["status"] == "liftoff" and entry["psi_bc_mrad"] is None
    assert d["status"] == "ok" and d["inputs"]["shapes"] == ["74L"] and d["inputs"]["mu"] == [0.7]
    assert d["inputs"]["load"] == {"F_D_n": 1000.0, "q_star_mm": 100.0, "r_sin_beta_mm": 0.0}


@pytest.mark.parametrize("argv, message", [
    (["--shapes", "61sym"], "--shapes must name shapes among"),
    (["--mu", "0.5,abc"], "--mu must be"),
    (["--mu", "-0.5"], "mu must be in"),
    (["--kn", "inf"], "kn must be"),
    (["--figure-processes", "-1"], "--figure-processes must be an integer in [0, inf)"),
    (["--figure-processes", "two"], "--figure-processes"),
])
def test_cli_study_errors(tmp_path, capsys, argv, message):
    code, _, err = run_cli(capsys, "study", "--out", tmp_path / "o", "--no-progress", "--no-figures", *argv)
    assert code == 2 and message in one_error_line(err)
    assert not (tmp_path / "o").exists()


def test_cli_study_unusable_out(tmp_path, capsys):
    blocker = tmp_path / "f"
    blocker.write_text("x")
    code, _, err = run_cli(capsys, "study", "--out", blocker, "--no-figures")
    assert code == 2 and "not a directory" in one_error_line(err)


def test_cli_section(tmp_path, capsys):
    out = tmp_path / "s.png"
    code, text, _ = run_cli(capsys, "section", "--shape", "74R", "--mu", "0.7", "--out", out)
    assert code == 0 and "wrote" in text
    nbytes, w, h = _png_size(out)
    assert nbytes > 20_000 and w > h
    code, _, err = run_cli(capsys, "section", "--shape", "74R", "--mu", "0.7", "--out", tmp_path / "s.txt")
    assert code == 2 and "--out must end" in one_error_line(err)
    (tmp_path / "FILE").write_text("x")
    code, _, err = run_cli(capsys, "section", "--shape", "74R", "--mu", "0.7", "--out", tmp_path / "FILE" / "x.png")
    line = one_error_line(err)
    assert code == 2 and "--out" in line and "is a file, not a directory" in line
