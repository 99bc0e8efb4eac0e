"""`jaxdamp amplitude`: JSON contract, nulls, status names, bad input."""

import json

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_cycle
from jaxdamp.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_json_contract(capsys):
    code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--kn", "17900",
                       "--kt", "3580", "--psi-a", "0.3,1.2", "--initial", "assembly", "--json")
    assert code == 0
    d = json.loads(out)
    assert set(d) == {"inputs", "status", "amplitudes", "warnings", "schema_version",
                      "jaxdamp_version", "status_reason"}
    assert d["status"] == "ok" and d["warnings"] == []
    assert d["inputs"]["psi_a_mrad"] == [0.3, 1.2] and d["inputs"]["initial"] == "assembly"
    assert d["inputs"]["mu"] == 0.5 and d["inputs"]["kn"] == 17900 and d["inputs"]["shape"] == "60sym"
    rows = d["amplitudes"]
    assert [set(r) for r in rows] == [{"psi_a_mrad", "k_re", "k_im", "status", "cycles"}] * 2
    assert rows[0]["status"] == "shakedown" and rows[1]["status"] == "ok"
    ref = amplitude_cycle(jd.family_shape("60sym"), 0.5, 1.2, jd.Contacts(17900.0, 3580.0),
                          initial="assembly")
    assert rows[1]["k_im"] == pytest.approx(float(ref.k_im), rel=1e-12)
    assert rows[1]["k_im"] == pytest.approx(1793, abs=1)  # the brute-force value


def test_an_amplitude_above_the_small_rotation_limit_warns(capsys):
    """10 rad is a number of the linearised model, not of a damper: the output says so."""
    code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a",
                       f"1,{2 * jd.blocks.SMALL_ROTATION_MRAD:g}", "--json")
    assert code == 0
    d = json.loads(out)
    assert len(d["warnings"]) == 1 and "small-rotation limit" in d["warnings"][0]
    assert "psi_a = 100 mrad" in d["warnings"][0]
    with pytest.warns(jd.SmallRotationWarning, match="psi_a"):
        amplitude_cycle(jd.family_shape("60sym"), 0.5, 2 * jd.blocks.SMALL_ROTATION_MRAD)


def test_liftoff_gives_nulls(capsys):
    code, out, _ = run(capsys, "amplitude", "--shape", "74L", "--mu", "0.7", "--psi-a", "1",
                       "--json")
    assert code == 0
    d = json.loads(out)
    row = d["amplitudes"][0]
    assert row["status"] == "liftoff" and row["k_re"] is None and row["k_im"] is None
    assert d["status"] == "liftoff"
    assert "NaN" not in out and "Infinity" not in out


@pytest.mark.slow  # 36 worker-s (run of 2026-11-25)
def test_band_in_json_and_table(capsys):
    code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "4",
                       "--band", "--json")
    assert code == 0
    band = json.loads(out)["amplitudes"][0]["band"]
    assert set(band) == {"k_re_min", "k_re_max", "k_im_min", "k_im_max"}
    # Above psi_BC the band closes on the cycle itself.
    row = json.loads(out)["amplitudes"][0]
    assert band["k_im_min"] == pytest.approx(row["k_im"], rel=1e-9)
    assert band["k_im_max"] == pytest.approx(row["k_im"], rel=1e-9)
    code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "4")
    assert code == 0 and "k_Im" in out


@pytest.mark.parametrize("argv,needle", [
    (["--psi-a", "0,1"], "--psi-a"), (["--psi-a", "abc"], "--psi-a"), (["--psi-a", "nan"], "--psi-a"),
    (["--psi-a", "1", "--initial", "rest"], "--initial"), (["--psi-a", "1", "--kn", "-1"], "kn"),
])
def test_bad_input_exits_2_with_one_line(capsys, argv, needle):
    code, _, err = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", *argv)
    assert code == 2
    lines = [ln for ln in err.strip().splitlines() if ln]
    assert len(lines) == 1 and needle in lines[0]


def test_out_of_phase_path_json(capsys):
    """--ibpa 180: the out-of-phase path, its motion in the JSON, the library's numbers; the
    modal force's loop work is the energy at the pads (the library's identity, through the CLI)."""
    code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--kn", "17900",
                       "--kt", "3580", "--psi-a", "10,20", "--initial", "assembly", "--ibpa", "180",
                       "--h-c", "20", "--h-l", "10", "--json")
    assert code == 0
    d = json.loads(out)
    m = d["inputs"]["motion"]
    assert m["ibpa_deg"] == 180 and m["h_c_mm"] == 20 and m["h_l_mm"] == 10
    assert m["direction"] == [-0.04, 0.0, 2.0]  # (h_C (-2), 0, 2) / 1e3 mm and mrad per mrad
    motion = jd.interblade_motion(180, 20.0, 100.0, 10.0)
    for row, psi in zip(d["amplitudes"], (10.0, 20.0)):
        ref = amplitude_cycle(jd.family_shape("60sym"), 0.5, psi, jd.Contacts(17900.0, 3580.0),
                              initial="assembly", motion=motion)
        assert row["status"] == "ok"
        assert row["k_im"] == pytest.approx(float(ref.k_im), rel=1e-12)
        assert row["k_re"] == pytest.approx(float(ref.k_re), rel=1e-12)
        # every path carries the per-pad fields (issue 62): on a straight path the curved-flat
        # damper's pads never open in a valid cycle, and its chart covers each half's travel
        assert row["open_fraction"] == {"R1": 0.0, "L1": 0.0, "L2": 0.0}
        assert list(row["slip_fraction"]) == ["R1", "L1", "L2"]
        for half in ("forward", "backward"):
            travel = sum(t["dv_mm"] for t in row["tracts"] if t["half"] == half)
            assert travel == pytest.approx(2.0 * psi * 100.0 / 1e3, rel=1e-9)


@pytest.mark.parametrize("extra, message", [
    (["--ibpa", "400", "--h-c", "20", "--h-l", "10"], "--ibpa must be a finite angle in [-360, 360] deg"),
    (["--ibpa", "90", "--h-c", "20", "--h-l", "10", "--initial", "steady"],
     "--initial must be one of gross_slip, assembly; got 'steady'"),
    (["--ibpa", "180", "--h-c", "20", "--h-l", "0"], "--h-l must be in (0, 10000] mm; got 0"),
    (["--ibpa", "180", "--h-l", "10"], "--h-c (depth of the blades' rotation centre"),
    (["--ibpa", "180", "--h-c", "20"], "--h-l must be given for a motion that turns the platforms"),
    (["--motion", "0.03,0.05", "--h-l", "12"], "--motion must be three numbers"),
    (["--motion", "0,1,0", "--ibpa", "0", "--h-c", "1"], "--ibpa and --motion are two ways"),
    (["--h-l", "5"], "--h-l is the damper's size on a path that turns the platforms"),
    (["--ibpa", "180", "--h-c", "20", "--h-l", "10", "--band"], "--band is computed for the paper's"),
    (["--damper", "wedge", "--band"], "--band is computed for the curved-flat damper only"),
    (["--br2", "0.8"], "--br2 places a wedge's right pads: give --damper wedge"),
    (["--damper", "wedge", "--br2", "1.5"], "br2_over_hr must be in (0, 1]"),
    (["--damper", "cone"], "invalid choice: 'cone'"),
])
def test_bad_paths_are_one_line_and_exit_2(capsys, extra, message):
    code, out, err = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "5",
                         *extra)
    assert code == 2 and out == ""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and message in lines[0], err


def test_elliptic_path_json(capsys):
    """--ibpa 90: an elliptic path, run from assembly (its default there), the library's numbers,
    per-pad energy and slip fractions, and the work identity pi a^2 k_Im / 1e3 = energy."""
    code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--kn", "17900",
                       "--kt", "3580", "--psi-a", "10", "--ibpa", "90", "--h-c", "20", "--h-l", "10",
                       "--json")
    assert code == 0
    d = json.loads(out)
    assert d["inputs"]["initial"] == "assembly" and d["inputs"]["motion"]["quadrature"] is not None
    row = d["amplitudes"][0]
    ref = jd.elliptic_cycle(jd.family_shape("60sym"), 0.5, 10.0,
                            jd.interblade_motion(90, 20.0, 100.0, 10.0), jd.Contacts(17900.0, 3580.0))
    assert row["status"] == "ok"
    assert row["k_im"] == pytest.approx(float(ref.k_im), rel=1e-12)
    assert set(row["energy_nmm"]) == set(row["slip_fraction"]) == {"R1", "L1", "L2"}
    assert sum(row["energy_nmm"].values()) == pytest.approx(row["dissipated_energy_nmm"], rel=1e-12)
    assert row["dissipated_energy_nmm"] == pytest.approx(3.141592653589793 * 100 * row["k_im"] / 1e3,
                                                         rel=1e-9)
    assert all(0.0 <= f <= 1.0 for f in row["slip_fraction"].values())


def test_a_complex_motion_is_an_elliptic_path(capsys):
    """--motion with complex entries that are not real up to one phase runs the elliptic solver:
    --motion of the phi = 90 deg direction gives the --ibpa 90 cycle."""
    x = np.asarray(jd.interblade_motion(90, 20.0, 100.0, 10.0).direction) + 1j * np.asarray(
        jd.interblade_motion(90, 20.0, 100.0, 10.0).quadrature)
    text = ",".join(f"{float(v.real)!r}{float(v.imag):+.17g}j" for v in x)
    rows = []
    # "--motion=..." : the first entry is negative, which argparse would take for an option.
    for path in ([f"--motion={text}"], ["--ibpa", "90", "--h-c", "20"]):
        code, out, _ = run(capsys, "amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "10",
                           *path, "--h-l", "10", "--json")
        assert code == 0
        d = json.loads(out)
        assert d["inputs"]["initial"] == "assembly" and d["inputs"]["motion"]["quadrature"] is not None
        rows.append(d["amplitudes"][0])
    assert rows[0]["status"] == rows[1]["status"] == "ok"
    assert rows[0]["k_im"] == pytest.approx(rows[1]["k_im"], rel=1e-12)
    assert rows[0]["k_re"] == pytest.approx(rows[1]["k_re"], rel=1e-12)


def test_a_wedge_runs_on_the_engine_with_its_pads_in_the_json(capsys):
    """--damper wedge: the library's wedge cycle (elliptic_cycle), four pads named in the JSON with
    their energies, slip and open fractions; --br is refused for a wedge."""
    code, out, _ = run(capsys, "amplitude", "--theta-l", "70", "--theta-r", "50", "--bl2", "0.6",
                       "--damper", "wedge", "--mu", "0.5", "--kn", "17900", "--kt", "3580",
                       "--psi-a", "20", "--ibpa", "120", "--h-c", "20", "--h-l", "10", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["inputs"]["damper"] == "wedge" and d["inputs"]["pads"] == ["R1", "R2", "L1", "L2"]
    assert d["inputs"]["br2_over_hr"] == 0.8 and d["inputs"]["br_over_hr"] is None
    row = d["amplitudes"][0]
    ref = jd.elliptic_cycle(jd.DamperShape(70.0, 50.0, 0.0, 0.6, None, 0.8), 0.5, 20.0,
                            jd.interblade_motion(120, 20.0, 100.0, 10.0), jd.Contacts(17900.0, 3580.0))
    assert row["status"] == "ok"
    assert row["k_im"] == pytest.approx(float(ref.k_im), rel=1e-12)
    assert list(row["open_fraction"]) == ["R1", "R2", "L1", "L2"]
    assert list(row["open_fraction"].values()) == pytest.approx(np.asarray(ref.open_fraction).tolist(),
                                                                abs=1e-12)
    assert max(row["open_fraction"].values()) > 0.1
    # The contact-state chart covers the period, and its open intervals are the open fractions.
    tracts = row["tracts"]
    assert tracts[0]["tau_start_deg"] == 0.0 and tracts[-1]["tau_end_deg"] == pytest.approx(360.0)
    for pad, fraction in row["open_fraction"].items():
        spans = sum(t["tau_end_deg"] - t["tau_start_deg"] for t in tracts if t[pad] == "open")
        assert spans / 360.0 == pytest.approx(fraction, abs=1e-12)
    code, out, err = run(capsys, "amplitude", "--theta-l", "70", "--theta-r", "50", "--br", "0.1",
                         "--damper", "wedge", "--mu", "0.5", "--psi-a", "5")
    assert code == 2 and out == "" and "--br places the curved-flat damper's pad R1" in err
