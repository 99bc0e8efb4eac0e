"""`jaxdamp cycle`: the JSON contract, null numbers at liftoff, echoed inputs, errors."""

import pytest

import jaxdamp as jd

from helpers import one_error_line, run_cli, strict_json


def test_cycle_json_contract(capsys):
    code, out, _ = run_cli(capsys, "cycle", "--shape", "74R", "--mu", "0.7", "--kn", "17900", "--kt", "3600",
                           "--json")
    assert code == 0
    d = strict_json(out)
    for key in ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc",
                "half_cycles", "status", "schema_version", "jaxdamp_version"):
        assert key in d
    assert d["status"] == "ok" and not {"converged", "liftoff", "failed"} & set(d)
    assert d["inputs"]["contacts"] == {"kn_n_per_mm": 17900.0, "kt_n_per_mm": 3600.0}
    assert d["inputs"]["load"] == {"F_D_n": 1000.0, "q_star_mm": 100.0, "r_sin_beta_mm": 0.0}
    assert d["inputs"]["mu"] == 0.7 and d["inputs"]["shape"]["theta_r_deg"] == jd.family_shape("74R").theta_r
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
    # energy identity: the contacts dissipate what the moment does
    assert abs(sum(d["energy_Nmm"][c] for c in ("R1", "L1", "L2")) - d["energy_Nmm"]["moment"]) < 1e-9 * d["energy_Nmm"]["moment"]
    # psi_BC within 2 % of Table B4.1 (3.270 mrad)
    assert abs(d["psi_bc_mrad"] / 3.270 - 1) < 0.02


def test_cycle_liftoff_numbers_are_null(capsys):
    code, out, _ = run_cli(capsys, "cycle", "--shape", "74L", "--mu", "0.7", "--json")
    assert code == 0
    d = strict_json(out)
    assert d["status"] == "liftoff" and "liftoff" not in d  # the status is the one truth
    for key in ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc"):
        assert d[key] is None
    assert d["tracts"] is None and set(d["energy_Nmm"].values()) == {None}
    code, out, _ = run_cli(capsys, "cycle", "--shape", "74L", "--mu", "0.7")
    assert code == 0 and "[status: liftoff]" in out.splitlines()[0] and "liftoff" in out


@pytest.mark.parametrize("argv,says", [
    # kt/kn = 1 / 20246.3 (the reference kn) = 4.94e-5 < 1e-4
    (["--kt", "1"], "kt/kn = 4.94e-05 below the validated range [1e-4, 1e4]"),
    # kn/F_D = 1e12 N/mm / 1000 N = 1e9 per mm > 1e6
    (["--kn", "1e12"], "kn/F_D = 1e+09 per mm above the validated range (at most 1e6 per mm)"),
])
def test_ill_conditioned_names_its_cause(capsys, argv, says):
    """Outside the validated stiffness range the cycle is ill_conditioned, and the text's status
    line, the JSON's status_reason and its warnings name the limit, the value and the range."""
    code, out, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", *argv)
    first = out.splitlines()[0]
    assert code == 0 and "[status: ill_conditioned] " in first and says in first
    assert "above the validated range (docs/model.md) or" not in out  # not the generic message
    code, out, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", *argv, "--json")
    d = strict_json(out)
    assert d["status"] == "ill_conditioned" and says in d["status_reason"]
    assert d["warnings"][-1] == d["status_reason"] and d["psi_bc_mrad"] is None


def test_ok_has_no_cause(capsys):
    code, out, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--json")
    d = strict_json(out)
    assert code == 0 and d["status"] == "ok" and d["status_reason"] is None
    assert all("validated range" not in w for w in d["warnings"])


@pytest.mark.parametrize("argv,needle", [
    (["--kn", "-1"], "--kn"),
    (["--kt", "inf"], "--kt"),
    (["--fd", "0"], "--fd"),
    (["--q", "nan"], "--q"),
    (["--r-sin-beta", "1e12"], "--r-sin-beta"),
])
def test_errors(capsys, argv, needle):
    code, _, err = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", *argv)
    assert code == 2
    line = one_error_line(err)
    assert needle in line and "inf]" not in line


def test_interblade_phase_angle_zero_is_the_in_phase_base_cycle(capsys):
    """--ibpa 0 is the in-phase scene exactly (MODEL.md): the same Base-Cycle as without it."""
    argv = ("cycle", "--shape", "60sym", "--mu", "0.5", "--json")
    code, out, _ = run_cli(capsys, *argv)
    code0, out0, _ = run_cli(capsys, *argv, "--ibpa", "0", "--h-c", "20")
    assert code == code0 == 0
    plain, zero = strict_json(out), strict_json(out0)
    for key in ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc"):
        assert zero[key] == plain[key] and plain[key] is not None


@pytest.mark.parametrize("argv,needle", [
    (["--ibpa", "90", "--h-c", "20", "--h-l", "10"], "ellipse, which has no Base-Cycle"),
    (["--ibpa", "90", "--h-c", "20", "--h-l", "10"], "jaxdamp amplitude --ibpa 90 --h-c MM"),
    (["--motion", "0.02,0.1+0.05j,1", "--h-l", "10"], "jaxdamp amplitude --motion"),
    (["--ibpa", "90"], "--h-c"),  # the flags' own checks come first
    (["--ibpa", "400", "--h-c", "20"], "--ibpa"),
])
def test_an_elliptic_path_is_refused_with_where_to_go(capsys, argv, needle):
    code, _, err = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", *argv)
    assert code == 2
    assert needle in one_error_line(err)


def test_a_wedge_base_cycle_json(capsys):
    """A wedge in-phase (`--ibpa 0` is that path): the Base-Cycle on the tract engine, its numbers
    under the in-phase keys, per-pad fields keyed R1, R2, L1, L2, the energy balance; out of phase
    it has none (a status and its reason, numbers null)."""
    argv = ("cycle", "--shape", "60sym", "--mu", "0.5", "--damper", "wedge", "--ibpa", "0",
            "--h-c", "20", "--h-l", "10", "--json")
    code, out, _ = run_cli(capsys, *argv)
    assert code == 0
    d = strict_json(out)
    assert d["status"] == "ok" and d["inputs"]["damper"] == "wedge"
    assert d["inputs"]["pads"] == ["R1", "R2", "L1", "L2"]
    assert d["inputs"]["shape"]["br2_over_hr"] == 0.8 and d["inputs"]["shape"]["br_over_hr"] is None
    assert d["inputs"]["motion"]["ibpa_deg"] == 0.0
    for key in ("energy_nmm", "slip_fraction", "open_fraction"):
        assert set(d[key]) == {"R1", "R2", "L1", "L2"}
    assert 0.0 < d["psi_fs_mrad"] <= d["psi_bc_mrad"] and d["k_re_bc"] > 0.0
    # the work of the modal force over the cycle is what the pads dissipate
    work = 3.141592653589793 * d["psi_bc_mrad"] ** 2 * d["k_im_bc"] / 1e3
    assert abs(sum(d["energy_nmm"].values()) - d["dissipated_energy_nmm"]) <= 1e-12
    assert abs(d["dissipated_energy_nmm"] - work) <= 1e-9 * d["k_re_bc"]
    assert all(set(t) >= {"tau_start_deg", "tau_end_deg", "R1", "R2", "L1", "L2"}
               for t in d["tracts"])
    code, out, _ = run_cli(capsys, *argv[:-7], "--ibpa", "180", "--h-c", "20", "--h-l", "10",
                           "--json")
    d = strict_json(out)
    assert code == 0 and d["status"] == "unreachable" and "never brings every pad to slip" in \
        d["status_reason"]
    assert d["psi_bc_mrad"] is None and d["energy_nmm"]["R2"] is None
