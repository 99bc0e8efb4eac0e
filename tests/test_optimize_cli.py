"""`jaxdamp optimize`: the --json contract, infeasible reporting, errors."""

import json

import pytest

import jaxdamp as jd
from jaxdamp.cli import main
from jaxdamp_optimize.cli import register

from helpers import one_error_line

CONTRACT = {"theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "objective_name", "objective",
            "baseline", "feasible", "min_margin_pct", "mu_set", "kn", "kt", "evaluations",
            "history"}


def run(capsys, *argv):
    # optimize is an entry point of jaxdamp.commands; passing its register function makes the test
    # independent of whether the installed metadata already lists it (added once either way)
    code = main(["optimize", *argv], extra_commands=[register])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.slow  # 86 worker-s (run of 2026-11-25)
def test_json_contract_default_objective(capsys):
    code, out, _ = run(capsys, "--json", "--kn", "20000", "--kt", "4000")
    assert code == 0
    d = json.loads(out)
    assert CONTRACT <= set(d)
    assert d["objective_name"] == "k_im_bc:worst" and d["status"] == "ok"
    assert d["inputs"]["contacts"] == {"kn_n_per_mm": 20000.0, "kt_n_per_mm": 4000.0}
    assert d["baseline"]["shape"] == "60sym" and isinstance(d["baseline"]["objective"], float)
    assert d["feasible"] is True and d["reason"] is None
    assert d["mu_set"] == [0.3, 0.5, 0.7] and d["kn"] == 20000.0 and d["kt"] == 4000.0
    assert isinstance(d["evaluations"], int) and d["evaluations"] > 0
    assert d["min_margin_pct"] >= 5.0
    assert d["objective"] > d["baseline"]["objective"]
    assert 35 <= d["theta_l"] <= 90 and 35 <= d["theta_r"] <= 90 and -0.3 <= d["br_over_hr"] <= 0.4
    assert d["bl2_over_hl"] == 0.8
    h = d["history"]
    assert isinstance(h, list) and len(h) >= 2 and {"theta_l", "objective", "feasible"} <= set(h[0])
    # the reported objective is the worst-case k_Im,BC of the returned shape with these contacts
    shape = jd.DamperShape(d["theta_l"], d["theta_r"], d["br_over_hr"], d["bl2_over_hl"])
    worst = min(float(jd.five_numbers(jd.base_cycle(shape, mu, jd.Contacts(20000.0, 4000.0)))
                      .k_im_bc) for mu in d["mu_set"])
    assert worst == pytest.approx(d["objective"], rel=1e-9)


@pytest.mark.slow  # 81 worker-s (run of 2026-11-25); test_optimize_solver holds the same in Python
def test_45sym_at_mu_07_is_infeasible_not_an_optimum(capsys):
    code, out, _ = run(capsys, "--fix", "theta_l=45,theta_r=45", "--mu-set", "0.7", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["feasible"] is False and d["free"] == ["br_over_hr"] and d["status"] == "liftoff"
    assert "no feasible design" in d["reason"] and "mid-cycle" in d["reason"]
    assert d["theta_l"] == 45.0 and d["active_constraints"] == []
    code, text, _ = run(capsys, "--fix", "theta_l=45,theta_r=45", "--mu-set", "0.7")
    assert code == 0 and text.startswith("INFEASIBLE") and "reason:" in text


@pytest.mark.slow  # 72 worker-s (2026-11-26); test_optimize_solver holds the optimiser in Python
def test_text_output(capsys):
    code, out, _ = run(capsys, "--objective", "k_im_bc:mean")
    assert code == 0
    assert out.startswith("OPTIMUM: k_im_bc:mean") and "evaluations:" in out
    assert "baseline 60sym" in out and "active constraints" in out


@pytest.mark.parametrize("argv, needle", [
    (("--mu-set", "0.3,abc"), "--mu-set"),
    (("--mu-set", "0.3,-0.5"), "mu_set"),
    (("--margin", "60"), "margin"),
    (("--objective", "k_re_bc"), "objective NAME"),
    (("--objective", "k_im_bc:mu=0.4"), "mu set"),
    (("--fix", "theta_q=3"), "--fix"),
    (("--fix", "theta_l"), "NAME=VALUE"),
    (("--kn", "-1"), "kn"),
    (("--min-vertex-angle", "200"), "min_vertex_deg"),
    (("--weights", "psi_bc=1"), "combined"),
    (("--kt", "inf"), "kt"),
    (("--plot", "/nonexistent-dir/paths.png"), "--plot"),
    (("--plot", "paths.txt"), "--plot"),
])
def test_bad_input_is_an_error_naming_the_parameter(capsys, argv, needle):
    code, _, err = run(capsys, *argv)
    assert code == 2 and needle in one_error_line(err)
