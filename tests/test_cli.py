import json

import pytest

from jaxdamp.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_statics_json_contract(capsys):
    code, out, _ = run(capsys, "statics", "--shape", "60sym", "--mu", "0.7", "--json")
    assert code == 0
    d = json.loads(out)
    assert set(d) == {"start", "mid", "liftoff", "min_normal_over_fd"}
    for end in ("start", "mid"):
        assert set(d[end]) == {"N", "T", "resultant_pos_pct"}
        assert set(d[end]["N"]) == {"R1", "L1", "L2"} == set(d[end]["T"])
    assert abs(d["start"]["resultant_pos_pct"] - 6.6) <= 0.1
    assert abs(100 - d["mid"]["resultant_pos_pct"] - 6.5) <= 0.1
    assert d["liftoff"] is False


def test_statics_liftoff_is_a_result_not_an_error(capsys):
    code, out, _ = run(capsys, "statics", "--theta-l", "45", "--theta-r", "45", "--br", "-0.2",
                       "--mu", "0.7", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["liftoff"] is True and abs(d["start"]["resultant_pos_pct"] - 2.94) < 0.01


def test_statics_table(capsys):
    code, out, _ = run(capsys, "statics", "--shape", "74R", "--mu", "0.5")
    assert code == 0 and "cycle start" in out and "liftoff" in out


@pytest.mark.parametrize("argv,needle", [
    (["statics", "--theta-l", "95", "--theta-r", "60", "--br", "0.1", "--mu", "0.5"], "theta_l"),
    (["statics", "--shape", "60sym", "--mu", "0"], "mu"),
    (["statics", "--shape", "60sym", "--mu", "nan"], "mu"),
    (["statics", "--shape", "60sym", "--bl2", "1.5", "--mu", "0.5"], "bl2_over_hl"),
    (["statics", "--theta-l", "60", "--mu", "0.5"], "--theta-r"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "-1"], "kn"),
])
def test_bad_input_exits_2_with_one_line(capsys, argv, needle):
    code, _, err = run(capsys, *argv)
    assert code == 2
    lines = [ln for ln in err.strip().splitlines() if ln]
    assert len(lines) == 1 and needle in lines[0]


def test_design_br_json(capsys):
    code, out, _ = run(capsys, "design-br", "--shape", "60sym", "--mu-max", "0.7", "--json")
    assert code == 0
    assert abs(json.loads(out)["br_over_hr"] - 0.14) <= 0.01


def test_help_explains_units(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert "N/mm" in out and "mrad" in out and "degrees" in out


def test_cycle_json_contract(capsys):
    code, out, _ = run(capsys, "cycle", "--shape", "74R", "--mu", "0.7", "--kn", "17900", "--kt", "3600",
                       "--json")
    assert code == 0
    d = json.loads(out)
    for key in ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc", "converged", "liftoff",
                "half_cycles"):
        assert key in d
    assert set(d["spans_mm"]) == {"forward", "backward"}
    assert set(d["energy_Nmm"]) == {"R1", "L1", "L2", "moment"}
    assert set(d["work_shape_factors"]) == {"w_R1", "w_L1", "w_L2", "w_M"}
    states = {"stick", "slip", "backslide", "open"}
    for half in ("forward", "backward"):
        for t in d["tracts"][half]:
            assert {t["R1"], t["L1"], t["L2"]} <= states and t["dv_mm"] >= 0
    # 74R, mu = 0.7: L1 back-slides in 0-A (Table 8) and the forward half needs the C-C2 stretch.
    assert d["tracts"]["forward"][0]["L1"] == "backslide"
    assert d["tracts"]["forward"][-1].get("stretch") is True
    assert d["spans_mm"]["forward"] < d["spans_mm"]["backward"]
    assert abs(sum(d["energy_Nmm"][c] for c in ("R1", "L1", "L2")) - d["energy_Nmm"]["moment"]) < 1e-9 * d["energy_Nmm"]["moment"]
    # psi_BC within 2 % of Table B4.1 (3.270 mrad)
    assert abs(d["psi_bc_mrad"] / 3.270 - 1) < 0.02


def test_cycle_liftoff_reported(capsys):
    code, out, _ = run(capsys, "cycle", "--shape", "74L", "--mu", "0.7", "--json")
    assert code == 0 and json.loads(out)["liftoff"] is True
