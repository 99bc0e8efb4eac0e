"""`jaxdamp design-br`: the centring b_R/h_R; a custom shape needs no --br; mu_max errors name it."""

import pytest

from helpers import one_error_line, run_cli, strict_json


def test_design_br_json(capsys):
    code, out, _ = run_cli(capsys, "design-br", "--shape", "60sym", "--mu-max", "0.7", "--json")
    assert code == 0
    d = strict_json(out)
    assert abs(d["br_over_hr"] - 0.14) <= 0.01  # the paper's 60sym (b_R/h_R = 0.14, §3)
    assert d["status"] == "ok" and d["inputs"]["mu_max"] == 0.7 and d["found"] and d["inside"]
    assert "br_over_hr" not in d["inputs"]["shape"]  # an output here, not an input


def test_custom_shape_needs_no_br(capsys):
    code, out, _ = run_cli(capsys, "design-br", "--theta-l", "60", "--theta-r", "60", "--json")
    assert code == 0
    assert abs(strict_json(out)["br_over_hr"] - 0.14) <= 0.01  # the same triangle as 60sym


def test_45sym_has_no_b_r_avoiding_liftoff(capsys):
    code, out, _ = run_cli(capsys, "design-br", "--theta-l", "45", "--theta-r", "45", "--json")
    assert code == 0
    d = strict_json(out)
    assert d["inside"] is False and d["status"] in ("liftoff", "no_root")


@pytest.mark.parametrize("argv,needle", [
    (["--shape", "60sym", "--mu-max", "7"], "--mu-max"),
    (["--shape", "60sym", "--mu-max", "-1"], "--mu-max"),
    (["--shape", "60sym", "--mu-max", "inf"], "--mu-max"),
    (["--theta-l", "60", "--theta-r", "60", "--br", "0.1"], "--br"),
    (["--theta-l", "60"], "--theta-r"),
])
def test_errors(capsys, argv, needle):
    code, _, err = run_cli(capsys, "design-br", *argv)
    assert code == 2 and needle in one_error_line(err)
