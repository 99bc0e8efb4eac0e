"""`jaxdamp optimize --objective peak:worst|peak:q95`: bad flags are one line naming the flag and
its range, exit 2, before any work (the full run is the benchmark's, minutes long)."""

import pytest

from jaxdamp.cli import main
from jaxdamp_optimize.cli import register
from jaxdamp_optimize.robust_cli import robust_text, row_text

from helpers import one_error_line


def run(capsys, *argv):
    code = main(["optimize", *argv], extra_commands=[register])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("argv, needle", [
    (["--objective", "peak:mean"], "--objective must be peak:worst or peak:q95"),
    (["--objective", "peak:worst", "--force-n", "20:2"], "--force-n must be FMIN:FMAX"),
    (["--objective", "peak:worst", "--force-n", "a:b"], "--force-n must be FMIN:FMAX"),
    (["--objective", "peak:q95", "--fd-spread", "1.5"], "--fd-spread must be in [0, 1)"),
    (["--objective", "peak:worst", "--kn-range", "0.5"], "--kn-range must be a factor in [1, 100]"),
    (["--objective", "peak:worst", "--kt-range", "101"], "--kt-range must be a factor in [1, 100]"),
    (["--objective", "peak:worst", "--mu-set", "0.3,-1"], "mu"),
    (["--objective", "peak:worst", "--plot", "/nonexistent/dir/x.png"], "--plot"),
    # the blade row (--modes): its flags, the history and the file, before any work
    (["--objective", "peak:worst", "--h-l", "10"],
     "--engine-order, --h-l, --corners and --references need --modes"),
    (["--objective", "peak:worst", "--references"],
     "--engine-order, --h-l, --corners and --references need --modes"),
    (["--objective", "peak:worst", "--corners", "all"], "need --modes"),
    (["--objective", "peak:q95", "--modes", "example", "--h-l", "10"],
     "--objective must be peak:worst with --modes"),
    (["--objective", "peak:worst", "--modes", "example", "--h-l", "10", "--history", "gross_slip"],
     "--history must be one of assembly, band"),
    (["--objective", "peak:worst", "--modes", "example"], "--h-l must be given with --modes"),
    (["--objective", "peak:worst", "--modes", "example", "--h-l", "10", "--engine-order", "x"],
     "--engine-order must be"),
    (["--objective", "peak:worst", "--modes", "/nonexistent/modes.npz", "--h-l", "10"], "modes"),
    (["--objective", "peak:worst", "--modes", "example", "--h-l", "10", "--plot", "/nonexistent/x.png"],
     "--plot"),
])
def test_bad_flags_are_one_line_errors_before_any_work(capsys, argv, needle):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)


def test_assembly_alone_is_for_the_row_only(capsys):
    code, out, err = run(capsys, "--objective", "peak:worst", "--history", "assembly")
    assert code == 2 and out == ""
    assert "--history must be one of gross_slip, band" in one_error_line(err)


def test_text_names_each_design_and_marks_the_infeasible_one():
    p = {"objective_name": "peak:worst", "objective": 0.9, "mu_set": [0.3, 0.7],
         "spec": {"force_range_n": (2.0, 20.0), "fd_spread": 0.2, "kn_factor": 2.0,
                  "kt_factor": 2.0, "history": "band"},
         "designs": [{"name": "robust optimum", "shape": (35.0, 50.0, 0.3, 0.8), "feasible": True,
                      "worst_dense": 0.9, "worst_mc": 1.0, "q95_mc": 0.8},
                     {"name": "k_Im,BC optimum", "shape": (81.0, 72.0, 0.03, 0.8),
                      "feasible": False, "worst_dense": None, "worst_mc": None, "q95_mc": None,
                      "reason": "not_converged in 3 of 337 scenarios"}]}
    text = robust_text(p)
    assert "0.9000 | 1.0000 | 0.8000" in text
    line = next(ln for ln in text.splitlines() if "k_Im,BC optimum" in ln)
    assert "not certified: not_converged in 3 of 337 scenarios" in line and "liftoff" not in line


def test_row_text_names_the_worst_engine_order_and_the_missing_history():
    p = {"objective": 1.2, "modes": "example", "n_blades": 24, "engine_orders": [0, 1, 12],
         "h_l_mm": 10.0, "mu_set": [0.3, 0.7],
         "spec": {"force_range_n": (2.0, 20.0), "fd_spread": 0.2, "kn_factor": 2.0,
                  "kt_factor": 2.0, "history": "band"},
         "designs": [{"name": "row robust optimum", "shape": (45.0, 55.0, 0.3, 0.85),
                      "feasible": True, "worst": 1.25, "worst_engine_order": 12,
                      "worst_by_history": {"gross_slip": (0.5, 0.9, None),
                                           "assembly": (0.6, 1.0, 1.25)},
                      "worst_scenario": {"mu": 0.3, "kn_factor": 0.5, "kt_factor": 2.0,
                                         "fd_n": 1200.0, "force_n": 2.0,
                                         "history": "assembly"}},
                     {"name": "60sym", "shape": (60.0, 60.0, 0.14, 0.8), "feasible": False,
                      "reason": "not_converged in 2 of 96 scenarios"}]}
    text = row_text(p)
    assert "engine orders 0-12" in text
    assert ("1.2500 | 0.9000 | 1.2500 at engine order 12 (mu 0.3, kn x0.5, kt x2, F_D 1200 N, "
            "2 N, assembly)") in text
    assert "60sym" in text and "not certified: not_converged in 2 of 96 scenarios" in text


@pytest.mark.parametrize("extra, free", [
    ([], ("theta_l", "theta_r", "br_over_hr")),
    (["--modes", "example", "--h-l", "10"], ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl")),
    (["--modes", "example", "--h-l", "10", "--fix", "bl2_over_hl=0.8"],
     ("theta_l", "theta_r", "br_over_hr")),
])
def test_the_row_frees_2b_l_by_default(capsys, monkeypatch, extra, free):
    """On one blade 2b_L/h_L is the paper's fixed 0.8 unless --free-bl2; over a row (--modes) the
    four shape variables are free (issue 61), and --fix fixes it again."""
    import jaxdamp_optimize.robust_cli as robust_cli

    seen = []

    def capture(args, problem):
        seen.append(tuple(problem.space.free))
        raise SystemExit(0)

    monkeypatch.setattr(robust_cli, "robust_payload", capture)
    with pytest.raises(SystemExit):
        run(capsys, "--objective", "peak:worst", *extra)
    assert seen == [free]
