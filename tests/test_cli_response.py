"""`jaxdamp response`: JSON contract, inputs echoed, nulls not NaN, bad input before any work."""

import json
import math

import pytest

from helpers import strict_json
from jaxdamp.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def _no_nan(x):
    if isinstance(x, float):
        return math.isfinite(x)
    if isinstance(x, dict):
        return all(_no_nan(v) for v in x.values())
    if isinstance(x, list):
        return all(_no_nan(v) for v in x)
    return True


@pytest.mark.slow  # 218 worker-s (run of 2026-11-25)
def test_response_json_contract_and_figures(capsys, tmp_path):
    plots = tmp_path / "figs"
    code, out, _ = run(capsys, "response", "--shape", "60sym", "--mu", "0.5", "--force-n", "0.2,20",
                       "--initial", "assembly", "--diagram", "--plot", str(plots), "--json")
    assert code == 0
    d = json.loads(out)
    assert _no_nan(d)
    assert {"inputs", "peaks", "frf", "designer_diagram", "status"} <= set(d)
    assert d["status"] == "ok"
    inp = d["inputs"]
    assert inp["initial"] == "assembly" and inp["stiffness_method"] == "exact"
    assert d["schema_version"] == 3 and "jaxdamp_version" in d
    assert inp["force_n"] == [0.2, 20.0] and inp["f0_hz"] == 500.0 and inp["mu"] == 0.5
    low, high = d["peaks"]
    for p in d["peaks"]:
        assert {"force_n", "peak_amplitude_mm", "peak_frequency_hz", "psi_a_mrad", "status",
                "roots"} <= set(p)
        assert p["status"] == "ok" and len(p["roots"]) >= 1
        assert p["roots"][0]["amplitude_mm"] == p["peak_amplitude_mm"]
    # 0.2 N keeps the damper stuck: the linear resonance F / (eta k_b) at the stuck frequency.
    assert low["peak_amplitude_mm"] == pytest.approx(0.2 / (1e-3 * 500.0), rel=1e-9)
    assert high["psi_a_mrad"] == pytest.approx(high["peak_amplitude_mm"] * 1.0, rel=1e-12)
    # Both branches exist below the peak; the free curve exists at every force.
    f0 = d["frf"]["forces"][0]
    assert len(f0["damper"]["low"]["frequency_hz"]) > 0
    assert all(v > 0 for v in f0["damper"]["low"]["frequency_hz"])
    assert len(f0["free"]["high"]["frequency_hz"]) == len(f0["free"]["high"]["amplitude_mm"]) > 0
    dd = d["designer_diagram"]
    assert dd["mu"] == [0.3, 0.4, 0.5, 0.6, 0.7] and len(dd["peak_vs_force_mm"]) == 5
    assert dd["force_at_fd_n"] == pytest.approx(10.1)
    assert (plots / "frf.png").stat().st_size > 0 and (plots / "designer_diagram.png").exists()


@pytest.mark.parametrize("argv,needle", [
    (["--force-n", "5,-1"], "--force-n"),
    (["--force-n", "abc"], "--force-n"),
    (["--loss-factor", "2"], "--loss-factor"),
    (["--f0-hz", "0"], "--f0-hz"),
    (["--psi-per-mm", "-1"], "--psi-per-mm"),
    (["--modal-stiffness-n-per-mm", "nan"], "--modal-stiffness-n-per-mm"),
    (["--mu", "0"], "--mu"),
])
def test_bad_input_exits_2_with_one_line(capsys, argv, needle):
    code, out, err = run(capsys, "response", "--shape", "60sym", *argv)
    assert code == 2 and out == ""
    lines = [ln for ln in err.strip().splitlines() if ln]
    assert len(lines) == 1 and needle in lines[0]


def test_plot_dir_checked_before_work(capsys, tmp_path):
    afile = tmp_path / "x.png"
    afile.write_text("")
    code, out, err = run(capsys, "response", "--shape", "60sym", "--plot", str(afile))
    assert code == 2 and out == "" and "plot" in err


@pytest.mark.slow  # 85 worker-s (run of 2026-11-25)
def test_liftoff_is_a_result(capsys):
    code, out, _ = run(capsys, "response", "--shape", "74L", "--mu", "0.7", "--force-n", "5",
                       "--json")
    assert code == 0
    d = json.loads(out)
    assert d["status"] == "liftoff" and d["peaks"][0]["peak_amplitude_mm"] is None
    assert d["designer_diagram"] is None and _no_nan(d)
    # An invalid damper's FRF has no points, the free one is still there.
    entry = d["frf"]["forces"][0]
    assert entry["damper"]["high"]["frequency_hz"] == [] and entry["peak_reduction"] is None
    assert len(entry["free"]["high"]["frequency_hz"]) > 0


def _no_null(x, path="doc"):
    if isinstance(x, dict):
        for k, v in x.items():
            _no_null(v, f"{path}.{k}")
    elif isinstance(x, list):
        for i, v in enumerate(x):
            _no_null(v, f"{path}[{i}]")
    else:
        assert x is not None, path


@pytest.mark.slow  # 71 worker-s (run of 2026-11-25)
def test_ill_conditioned_damper_status_survives(capsys):
    """#23: the Base-Cycle's own status reaches the response (it was rebuilt from flags)."""
    code, out, _ = run(capsys, "response", "--shape", "60sym", "--mu", "0.5", "--kt", "1e12",
                       "--force-n", "5", "--json")
    assert code == 0
    d = json.loads(out)
    code, cyc, _ = run(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--kt", "1e12", "--json")
    assert json.loads(cyc)["status"] == "ill_conditioned"
    assert d["status"] == d["damper_status"] == d["peaks"][0]["status"] == "ill_conditioned"


@pytest.mark.slow  # 60 worker-s (run of 2026-11-25)
def test_frf_json_strict_and_free_peaks_shown(capsys):
    """#27: the free and stuck curves reach their own peaks F / (eta k_b) (a linear oscillator's
    resonance), the peak reduction is A*_free / A*, and no null stands where a number exists."""
    code, out, _ = run(capsys, "response", "--shape", "60sym", "--mu", "0.5", "--force-n",
                       "2,5,20", "--json")
    assert code == 0
    d = strict_json(out)
    entries = d["frf"]["forces"]
    for p, e in zip(d["peaks"], entries):
        _no_null(e, "frf")
        top = p["force_n"] / (1e-3 * 500.0)
        for limit in ("free", "stuck"):
            amps = e[limit]["low"]["amplitude_mm"] + e[limit]["high"]["amplitude_mm"]
            assert max(amps) == pytest.approx(top, rel=1e-6)
        assert e["peak_reduction"] == pytest.approx(e["free_peak_amplitude_mm"]
                                                    / p["peak_amplitude_mm"], rel=1e-12)
        assert e["peak_reduction"] > 1.0
    assert max(entries[2]["free"]["high"]["amplitude_mm"]) == pytest.approx(40.0, rel=1e-6)


@pytest.mark.slow  # 88 worker-s (run of 2026-11-25)
def test_band_is_reported_in_json_and_text(capsys):
    """`--band`: the peak's bounds over every admissible history, in JSON and in the text table;
    the history run (gross slip) lies inside them."""
    code, out, _ = run(capsys, "response", "--shape", "74L", "--mu", "0.3", "--force-n", "5,20",
                       "--band", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["inputs"]["band"] is True
    for p in d["peaks"]:
        b = p["band"]
        assert b["peak_amplitude_min_mm"] <= p["peak_amplitude_mm"] * (1 + 1e-9)
        assert p["peak_amplitude_mm"] <= b["peak_amplitude_max_mm"] * (1 + 1e-9)
    code, text, _ = run(capsys, "response", "--shape", "74L", "--mu", "0.3", "--force-n", "5,20",
                        "--band")
    assert code == 0 and "band over every admissible contact history" in text
    assert f"{d['peaks'][0]['band']['peak_amplitude_min_mm']:.5g}" in text


@pytest.mark.slow  # 146 worker-s (run of 2026-11-26)
def test_band_and_diagram_check_every_input_once(capsys):
    """On the path of `response --band --diagram` each input is checked once: the CLI builds one
    Scene (`prepare_scene`) and the band and the diagram take it as it is (counted by
    jaxdamp.params.RANGE_CHECKS, which every range check of params.RANGES goes through)."""
    from jaxdamp._validate import MOTION_RANGES
    from jaxdamp.params import RANGE_CHECKS, RANGES

    RANGE_CHECKS.clear()
    code, out, _ = run(capsys, "response", "--shape", "60sym", "--mu", "0.5", "--force-n", "20",
                       "--stiffness", "interpolated", "--band", "--diagram", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["designer_diagram"] is not None and "band" in d["peaks"][0]
    # no --x-d given: the shape has none to check (nor a wedge's pads); the response takes no
    # platform path
    inputs = set(RANGES) - {"x_d", "br2_over_hr"} - MOTION_RANGES
    assert dict(RANGE_CHECKS) == {name: 1 for name in inputs}
