"""`jaxdamp sweep`: files and summary (printed = sweep.json), input errors, path and size checks
before any computing."""

import numpy as np
import pytest

from helpers import one_error_line, run_cli, strict_json


def test_cli_sweep_writes_heatmaps_and_data(tmp_path, capsys):
    out = tmp_path / "sw"
    code, stdout, err = run_cli(capsys, "sweep", "--theta-l", "40,60,90", "--theta-r", "45:75:3",
                                "--mu", "0.5,0.7", "--out", out, "--json")
    assert code == 0
    printed = strict_json(stdout)
    assert printed["points"] == 18 and printed["status"] in ("ok", "not_converged")
    assert "18 designs" in err and "GB" in err  # the size estimate, before the work
    data = np.load(out / "sweep.npz")
    assert data["psi_bc"].shape == (2, 3, 3) and data["status"].shape == (2, 3, 3)
    np.testing.assert_array_equal(data["theta_r"], [45.0, 60.0, 75.0])
    meta = strict_json((out / "sweep.json").read_text())
    # the printed summary and sweep.json agree: one dict
    assert meta["summary"] == {k: printed[k] for k in meta["summary"]}
    assert meta["summary"]["valid"] == int(data["valid"].sum())
    assert meta["summary"]["liftoff"] == int((data["status"] == 1).sum())
    assert meta["counts"]["valid"] == printed["valid"]
    assert meta["inputs"]["theta_l_deg"] == [40.0, 60.0, 90.0] and meta["inputs"]["br_over_hr"] == "centred"
    # numbers of valid points as computed; of the others (liftoff...) null, never 0.0
    valid = data["valid"]
    k_im = np.array(meta["data"]["k_im_bc"], dtype=object)
    assert all(v is None for v in k_im[~valid])
    np.testing.assert_array_equal(k_im[valid].astype(float), data["k_im_bc"][valid])
    assert (out / "sweep.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("argv,needle", [
    (["--theta-l", "40:90"], "--theta-l"),
    (["--br", "middle"], "--br"),
    (["--br", "5"], "--br"),  # was accepted (and clipped)
    (["--mu", "0.5,-1"], "mu"),
    (["--mu-max", "inf"], "--mu-max"),
    (["--theta-r", "60,95"], "--theta-r"),
    (["--kn", "inf"], "kn"),
    (["--bl2", "0"], "--bl2"),
])
def test_cli_sweep_errors(tmp_path, capsys, argv, needle):
    code, _, err = run_cli(capsys, "sweep", "--out", tmp_path / "o", "--theta-l", "60", "--theta-r", "60", *argv)
    assert code == 2 and needle in one_error_line(err)
    assert not (tmp_path / "o").exists()


def test_unusable_out_is_refused_before_work(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code, _, err = run_cli(capsys, "sweep", "--out", blocker / "sub", "--theta-l", "60", "--theta-r", "60")
    assert code == 2 and "--out" in one_error_line(err)


def test_huge_sweep_is_refused_without_force(tmp_path, capsys):
    code, _, err = run_cli(capsys, "sweep", "--out", tmp_path / "o", "--theta-l", "40:90:2000",
                           "--theta-r", "40:90:2000", "--mu", "0.5")
    line = one_error_line(err)
    assert code == 2 and "--force" in line and "4000000 designs" in line and "GB" in line
    assert not (tmp_path / "o").exists()


def test_estimate_scales_with_the_grid():
    from jaxdamp.cli.sweep import estimate

    small, big = estimate(1000, 1, 1024), estimate(4_000_000, 1, 1024)
    assert big["memory_bytes"] > 2 * 1024**3 > small["memory_bytes"]
    assert big["time_s"] > 60 and estimate(4_000_000, 2, 1024)["time_s"] < big["time_s"]
