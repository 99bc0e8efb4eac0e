"""Errors name the flag the user typed, with a correct example; options mean the same in every
command; output paths are created before any work; every JSON document has "inputs"."""

import pytest

import jaxdamp as jd
from helpers import count_compiles, one_error_line, run_cli, strict_json


@pytest.mark.parametrize("argv, flag, forbidden", [
    (["response", "--shape", "60sym", "--loss-factor", "2"], "--loss-factor must be in [0, 1]", "eta"),
    (["amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "-1"], "--psi-a must be in (0, 10000] mrad",
     "psi_a_mrad"),
    (["amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "x"], "e.g. --psi-a 0.5,1.2,3", "0.7,0.5,0.3"),
    (["grad", "--shape", "60sym", "--mu", "0.5", "--psi-a", "-3"], "--psi-a must be in [0, 1e+09] mrad",
     "psi_a_mrad"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--fd", "-1"], "--fd must be in (0, inf) N", "F_D"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--q", "0"], "--q must be in (0, inf) mm", "q_star"),
    (["cycle", "--shape", "60sym", "--mu", "9"], "--mu must be in (0, 5]", "error: mu"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "-1"], "--kn must be in (0, inf) N/mm", "error: kn"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--kt", "1,2"], "--kt takes one value (all contacts) or "
     "three (R1,L1,L2), e.g. --kt 2e4,2e4,1.8e4", "0.7,0.5"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--x-d", "1e7"], "--x-d must be in [-1e+06, 1e+06]", "x_d "),
    (["cycle", "--theta-l", "100", "--theta-r", "60", "--br", "0", "--mu", "0.5"], "--theta-l must be in (0, 90] deg",
     "theta_l"),
    (["cycle", "--theta-l", "60", "--theta-r", "60", "--br", "0.9", "--mu", "0.5"], "--br must be in [-0.5, 0.5]",
     "br_over_hr"),
    (["cycle", "--theta-l", "60", "--theta-r", "60", "--br", "middle", "--mu", "0.5"],
     "--br must be a number in [-0.5, 0.5] or 'centred', e.g. --br 0.1", "float"),
    (["design-br", "--shape", "60sym", "--mu-max", "0"], "--mu-max must be in (0, 5]", "mu_max"),
    (["cycle", "--shape", "61sym", "--mu", "0.5"], "--shape must name shapes among", "shape must be"),
])
def test_errors_name_the_flag(capsys, argv, flag, forbidden):
    code, out, err = run_cli(capsys, *argv)
    line = one_error_line(err)
    assert code == 2 and out == "" and flag in line and forbidden not in line, line


def test_shape_names_are_case_insensitive(capsys):
    code, out, _ = run_cli(capsys, "statics", "--shape", "60SYM", "--mu", "0.7", "--json")
    ref = jd.family_shape("60sym")
    assert code == 0 and strict_json(out)["inputs"]["shape"]["br_over_hr"] == ref.br_over_hr


def test_br_centred_means_the_design_rule_in_every_command(capsys):
    """`--br centred` with --mu m is the b_R/h_R that design-br gives at --mu-max m (the sweep's rule
    with one mu)."""
    _, out, _ = run_cli(capsys, "design-br", "--theta-l", "66", "--theta-r", "58", "--mu-max", "0.6", "--json")
    br = strict_json(out)["br_over_hr"]
    for cmd in ("statics", "cycle"):
        code, out, _ = run_cli(capsys, cmd, "--theta-l", "66", "--theta-r", "58", "--br", "Centred", "--mu", "0.6",
                               "--json")
        assert code == 0 and strict_json(out)["inputs"]["shape"]["br_over_hr"] == br, cmd


def test_output_dir_is_created_before_any_work(capsys):
    with count_compiles() as compiled:
        code, _, err = run_cli(capsys, "study", "--out", "/proc/nonexistent/study")
    line = one_error_line(err)
    assert code == 2 and "--out '/proc/nonexistent/study' cannot be created" in line
    assert compiled == []  # nothing was computed: the check came before any program ran


def test_section_out_under_a_regular_file(tmp_path, capsys):
    (tmp_path / "FILE").write_text("x")
    code, _, err = run_cli(capsys, "section", "--shape", "74R", "--mu", "0.7", "--out", tmp_path / "FILE" / "x.png")
    line = one_error_line(err)
    assert code == 2 and "is a file, not a directory" in line and "does not exist" not in line


@pytest.mark.parametrize("argv", [
    ["statics", "--shape", "60sym", "--mu", "0.7"],
    ["design-br", "--shape", "60sym"],
    ["cycle", "--shape", "60sym", "--mu", "0.5"],
    ["grad", "--shape", "60sym", "--mu", "0.5"],
    ["amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "3"],
])
@pytest.mark.slow  # 12 worker-s (run of 2026-11-25)
def test_every_document_has_inputs(capsys, argv):
    code, out, _ = run_cli(capsys, *argv, "--json")
    d = strict_json(out)
    assert code == 0 and isinstance(d["inputs"], dict) and d["inputs"]
    assert "shape" not in d and "mu" not in d  # not echoed at the top level any more
