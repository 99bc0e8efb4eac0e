"""`jaxdamp statics`: JSON contract (status, inputs, forces), liftoff as a result, errors."""

import pytest

from helpers import one_error_line, run_cli, strict_json


def test_statics_json_contract(capsys):
    code, out, _ = run_cli(capsys, "statics", "--shape", "60sym", "--mu", "0.7", "--json")
    assert code == 0
    d = strict_json(out)
    assert {"start", "mid", "liftoff", "min_normal_over_fd", "status", "schema_version",
            "jaxdamp_version", "status_reason", "inputs"} == set(d)
    assert d["status"] == "ok" and d["schema_version"] == 3 and d["inputs"]["mu"] == 0.7
    assert d["inputs"]["shape"] == {"theta_l_deg": 60.0, "theta_r_deg": 60.0, "br_over_hr": 0.14, "bl2_over_hl": 0.8}
    for end in ("start", "mid"):
        assert set(d[end]) == {"N", "T", "resultant_pos_pct"}
        assert set(d[end]["N"]) == {"R1", "L1", "L2"} == set(d[end]["T"])
    # Table 1 of the paper: 60sym at mu = 0.7, 6.6 % from L1 at cycle start, 6.5 % from L2 mid-cycle
    assert abs(d["start"]["resultant_pos_pct"] - 6.6) <= 0.1
    assert abs(100 - d["mid"]["resultant_pos_pct"] - 6.5) <= 0.1
    assert d["liftoff"] is False


def test_statics_liftoff_is_a_result_not_an_error(capsys):
    code, out, _ = run_cli(capsys, "statics", "--theta-l", "45", "--theta-r", "45", "--br", "-0.2",
                           "--mu", "0.7", "--json")
    assert code == 0
    d = strict_json(out)
    assert d["liftoff"] is True and d["status"] == "liftoff"
    assert abs(d["start"]["resultant_pos_pct"] - 2.94) < 0.01


def test_statics_table_shows_status_first(capsys):
    code, out, _ = run_cli(capsys, "statics", "--shape", "74R", "--mu", "0.5")
    assert code == 0 and "cycle start" in out and "liftoff" in out
    assert "[status: ok]" in out.splitlines()[0]


@pytest.mark.parametrize("argv,needle", [
    (["--theta-l", "95", "--theta-r", "60", "--br", "0.1", "--mu", "0.5"], "--theta-l"),
    (["--shape", "60sym", "--mu", "0"], "--mu"),
    (["--shape", "60sym", "--mu", "nan"], "--mu"),
    (["--shape", "60sym", "--mu", "inf"], "--mu"),
    (["--theta-l", "60", "--theta-r", "60", "--br", "0.1", "--bl2", "1.5", "--mu", "0.5"], "--bl2"),
    (["--theta-l", "60", "--mu", "0.5"], "--theta-r"),
    (["--shape", "61sym", "--mu", "0.5"], "shape"),
    # a paper shape fixes 2b_L/h_L: --bl2 with --shape is rejected, not silently combined
    (["--shape", "60sym", "--bl2", "0.5", "--mu", "0.5"], "--bl2"),
    (["--shape", "60sym", "--theta-l", "60", "--mu", "0.5"], "--shape"),
])
def test_bad_input_exits_2_with_one_line(capsys, argv, needle):
    code, out, err = run_cli(capsys, "statics", *argv)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)
