"""`jaxdamp response --modes FILE`: the blade row from modal data; flag combinations and files
checked before any work, and (slow) the JSON contract, table and figure of a run."""

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import assert_tree_allclose, one_error_line, strict_json
from jaxdamp.cli import main
from jaxdamp.modal_file import save_modal_family
from jaxdamp.response import BladeMode
from jaxdamp.response.modes import ModalFamily, family_from_blade_mode

EXAMPLE = Path(__file__).resolve().parents[1] / "jaxdamp" / "data" / "example_disk_modes.npz"


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def modes_file(tmp_path):
    f = family_from_blade_mode(BladeMode(), 100.0, 40.0, 6)
    rep = lambda v: np.repeat(v, 4, axis=0)  # noqa: E731
    fam = ModalFamily(6, np.arange(4), np.array([500.0, 520.0, 530.0, 535.0]), rep(f.loss_factor),
                      rep(f.modal_force), rep(f.response_displacement), rep(f.left_platform),
                      rep(f.right_platform), "six blades")
    return save_modal_family(fam, tmp_path / "modes.json")


@pytest.mark.parametrize("extra, needle", [
    (["--stiffness", "interpolated"], "--stiffness interpolated"),
    (["--f0-hz", "400"], "--f0-hz describes the one-mode blade"),
    (["--engine-order", "x"], "--engine-order must be"),
])
def test_bad_row_arguments_exit_2_in_one_line(capsys, modes_file, extra, needle):
    code, out, err = run(capsys, "response", "--shape", "60sym", "--modes", str(modes_file),
                         "--h-l", "30", *extra)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)


def test_modes_needs_h_l_and_a_readable_file(capsys, tmp_path, modes_file):
    code, _, err = run(capsys, "response", "--shape", "60sym", "--modes", str(modes_file))
    assert code == 2 and "--h-l must be given with --modes" in one_error_line(err)
    code, _, err = run(capsys, "response", "--shape", "60sym", "--modes",
                       str(tmp_path / "none.npz"), "--h-l", "30")
    assert code == 2 and "--modes must be an existing .npz or .json file" in one_error_line(err)
    code, _, err = run(capsys, "response", "--shape", "60sym", "--engine-order", "3")
    assert code == 2 and "--engine-order needs --modes FILE" in one_error_line(err)


def test_engine_order_of_a_missing_nodal_diameter(capsys, tmp_path):
    f = family_from_blade_mode(BladeMode(), 100.0, 40.0, 8)  # 8 blades, only nodal diameter 0
    path = save_modal_family(f, tmp_path / "nd0.npz")
    code, _, err = run(capsys, "response", "--shape", "60sym", "--modes", str(path), "--h-l", "30",
                       "--engine-order", "0,9")
    assert code == 2
    assert "--engine-order 9 excites nodal diameter 1 (n_blades 8), which the modal family lacks" \
        in one_error_line(err)


def test_band_needs_a_loss_factor_at_every_excited_nodal_diameter(capsys, tmp_path, modes_file):
    """Refused in one line before any program runs: the band's table ends at the free peak."""
    fam = json.loads(Path(modes_file).read_text())
    fam["loss_factor"] = [0.0] * len(fam["loss_factor"])
    path = tmp_path / "undamped.json"
    path.write_text(json.dumps(fam))
    code, out, err = run(capsys, "response", "--shape", "60sym", "--modes", str(path), "--h-l",
                         "30", "--engine-order", "1", "--band")
    assert code == 2 and out == ""
    assert "loss_factor must be > 0 at nodal diameter 1 for the band" in one_error_line(err)


def test_plot_dir_checked_before_the_modes_file(capsys, tmp_path):
    afile = tmp_path / "x.png"
    afile.write_text("")
    code, out, err = run(capsys, "response", "--shape", "60sym", "--modes",
                         str(tmp_path / "none.npz"), "--h-l", "30", "--plot", str(afile))
    assert code == 2 and out == "" and "--plot" in one_error_line(err)


@pytest.mark.slow  # the straight and elliptic row programs, about 3 min to build
def test_row_json_table_and_figure(capsys, tmp_path, modes_file):
    plots = tmp_path / "figs"
    argv = ["response", "--shape", "60sym", "--mu", "0.5", "--modes", str(modes_file), "--h-l",
            "30", "--engine-order", "0:4", "--force-n", "5,20"]
    code, out, _ = run(capsys, *argv, "--json", "--plot", str(plots))
    assert code == 0
    d = strict_json(out)
    assert d["status"] == "ok" and d["inputs"]["initial"] == "assembly"
    rows = d["engine_orders"]
    assert [r["engine_order"] for r in rows] == [0, 1, 2, 3, 4]
    # Engine order 4 of six blades is the backward wave of nodal diameter 2.
    assert [r["nodal_diameter"] for r in rows] == [0, 1, 2, 3, 2]
    assert [r["path"] for r in rows] == ["straight", "elliptic", "elliptic", "straight", "elliptic"]
    amps = np.array([[p["peak_amplitude_mm"] for p in r["forces"]] for r in rows])
    free = np.array([[p["free_peak_amplitude_mm"] for p in r["forces"]] for r in rows])
    assert np.all(amps < free)  # the damper lowers every peak
    # No damper: F_tip / (eta k_b) with this family's unit tip force and k_b = 500 N/mm
    # at 500 Hz, scaled with the frequency (the same modal mass).
    f = np.array([r["frequency_hz"] for r in rows])
    assert_tree_allclose(free, np.array([5.0, 20.0])[None] / (1e-3 * 500.0 * (f / 500.0) ** 2)[:, None],
                         rtol=1e-12, atol=0.0)
    w = d["worst"]
    assert [x["force_n"] for x in w] == [5.0, 20.0]
    worst_eo = [int(np.argmax(amps[:, j])) for j in range(2)]
    assert [x["engine_order"] for x in w] == worst_eo
    assert (plots / "row.png").stat().st_size > 0
    code, text, _ = run(capsys, *argv)
    assert code == 0 and "worst at F = 20 N: engine order" in text
    assert json.dumps(d)  # plain JSON


@pytest.mark.slow  # the elliptic row and row band programs: 116 worker-s (2026-11-27)
def test_row_band_json_table_and_figure(capsys, tmp_path):
    """--band with --modes: per engine order and force the band's bounds (as `row_band` gives
    them), which hold the history's peak, the worst engine order over every history, the band's
    table lines and the shaded figure. On the shipped example, with its platforms' residual
    flexibility (each state's peak searched in its own amplitude)."""
    import jaxdamp as jd
    from jaxdamp.modal_file import load_modal_family

    plots = tmp_path / "figs"
    argv = ["response", "--shape", "60sym", "--mu", "0.5", "--modes", "example", "--h-l", "10",
            "--engine-order", "3,5", "--force-n", "2,20", "--band"]
    code, out, _ = run(capsys, *argv, "--json", "--plot", str(plots))
    assert code == 0
    d = strict_json(out)
    assert d["status"] == "ok" and d["inputs"]["band"] is True and d["inputs"]["band_samples"] == 64
    band = jd.row_band(jd.family_shape("60sym"), 0.5, modes=load_modal_family("example"),
                       engine_orders=[3, 5], force_n=[2.0, 20.0], h_l_mm=10.0)
    got = np.array([[[p["band"]["peak_amplitude_min_mm"], p["band"]["peak_amplitude_max_mm"]]
                     for p in r["forces"]] for r in d["engine_orders"]])
    assert_tree_allclose(got, np.stack([band.peak_min_mm, band.peak_max_mm], axis=-1), rtol=1e-12,
                         atol=0.0)
    amps = np.array([[p["peak_amplitude_mm"] for p in r["forces"]] for r in d["engine_orders"]])
    assert np.all(got[..., 0] <= amps) and np.all(amps <= got[..., 1])
    worst = [w["band"]["engine_order"] for w in d["worst"]]
    assert worst == [[3, 5][int(np.argmax(band.peak_max_mm[:, j]))] for j in range(2)]
    assert (plots / "row.png").stat().st_size > 0
    code, text, _ = run(capsys, *argv)
    assert code == 0 and "band over every admissible contact history" in text
    assert "over every history: engine order" in text


@pytest.mark.slow  # the straight row program with the residual, about 1.5 min to build
def test_a_residual_file_gives_the_row_response_of_its_family(capsys, tmp_path):
    """A modal file with platform_residual (the lumped disk's, six blades): the command reads it
    and reports the reduction with the residual, as `row_response` on the same family, and the
    path's residual flexibility per engine order."""
    import jaxdamp as jd
    from jaxdamp.baselines.lumped_disk import LumpedDisk, modal_family

    family = modal_family(LumpedDisk(n_blades=6), 100.0, 20.0, residual=True)
    path = save_modal_family(family, tmp_path / "disk.json")
    code, out, _ = run(capsys, "response", "--shape", "60sym", "--mu", "0.5", "--modes",
                       str(path), "--h-l", "10", "--engine-order", "0,3", "--force-n", "2,20",
                       "--json")
    assert code == 0
    rows = strict_json(out)["engine_orders"]
    row = jd.row_response(jd.family_shape("60sym"), 0.5, modes=family, engine_orders=[0, 3],
                          force_n=[2.0, 20.0], h_l_mm=10.0)
    got = np.array([[p["peak_amplitude_mm"] for p in r["forces"]] for r in rows])
    assert_tree_allclose(got, np.asarray(row.peaks.peak_amplitude_mm), rtol=1e-12, atol=0.0)
    c = [jd.nodal_scene(jd.blocks.validate_family(family), e, 100.0, 10.0).residual_mrad_per_nmm
         for e in (0, 3)]
    assert_tree_allclose(np.array([r["residual_mrad_per_nmm"] for r in rows]), np.array(c),
                         rtol=1e-12, atol=0.0)
    assert min(c) > 0


@pytest.mark.slow  # the straight row program on the diagram's 32 forces, about 1 min to build
def test_row_diagram_json_table_and_figure(capsys, tmp_path):
    """--diagram with --modes: the JSON's two curves are `row_diagram`'s on the command's grids
    (at the median of --force-n), the text has both tables, the figure is written. At 200 N both
    engine orders' peaks turn the platforms beyond the small-rotation model
    (tests/test_status_paths.py::test_large_rotation_through_the_row): the JSON keeps their
    numbers with the status large_rotation, which is the document's, with its reason; the text
    counts them."""
    import jaxdamp as jd
    from jaxdamp.cli.response_row import DIAGRAM_FD_FACTORS, DIAGRAM_FORCES_N
    from jaxdamp.modal_file import load_modal_family

    plots = tmp_path / "figs"
    argv = ["response", "--shape", "60sym", "--mu", "0.5", "--modes", "example", "--h-l", "10",
            "--engine-order", "0,12", "--force-n", "1,20,200", "--diagram"]
    code, out, _ = run(capsys, *argv, "--json", "--plot", str(plots))
    assert code == 0
    doc = strict_json(out)
    assert doc["status"] == "large_rotation" and "small-rotation" in doc["status_reason"]
    beyond = [r["forces"][2] for r in doc["engine_orders"]]
    assert all(p["status"] == "large_rotation" and p["rotation_mrad"] > 50.0
               and p["peak_amplitude_mm"] > 0 for p in beyond)
    d = doc["diagram"]
    dd = jd.row_diagram(jd.family_shape("60sym"), 0.5, modes=load_modal_family("example"),
                        engine_orders=[0, 12], h_l_mm=10.0, force_n=DIAGRAM_FORCES_N,
                        fd_factor=DIAGRAM_FD_FACTORS, force_at_fd_n=20.0)
    assert d["force_at_fd_n"] == 20.0
    for key, worst, orders in (("vs_force", dd.worst_vs_force_mm_per_n, dd.engine_order_vs_force),
                               ("vs_fd_factor", dd.worst_vs_fd_mm_per_n, dd.engine_order_vs_fd)):
        got = np.array([np.nan if p["worst_mm_per_n"] is None else p["worst_mm_per_n"]
                        for p in d[key]])
        want = np.asarray(worst)
        assert np.array_equal(np.isnan(got), np.isnan(want)) and np.isfinite(want).sum() >= 10
        assert_tree_allclose(got[np.isfinite(want)], want[np.isfinite(want)], rtol=1e-12, atol=0.0)
        assert [p["engine_order"] for p in d[key]] == [int(e) if e >= 0 else None for e in orders]
    assert (plots / "row_diagram.png").stat().st_size > 0
    code, text, _ = run(capsys, *argv)
    assert code == 0 and "the row's designer's diagram" in text and "against F_D at F = 20 N" in text
    assert "[status: large_rotation]" in text and "2 of 6 peaks are large_rotation" in text
