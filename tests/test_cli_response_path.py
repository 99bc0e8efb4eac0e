"""`jaxdamp response --ibpa / --motion`: the one-mode blade with the damper on a platform path.
Flag combinations are checked before any work; (slow) a run's peaks satisfy the peak equation
with the steady cycle that `jaxdamp.elliptic_cycle` computes on its own at the peak amplitude."""

import pytest

import jaxdamp as jd
from helpers import one_error_line, strict_json
from jaxdamp.cli import main

BASE = ("response", "--shape", "60sym", "--mu", "0.5")


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("extra, needle", [
    (["--ibpa", "90", "--h-l", "10"], "--h-c (depth of the blades' rotation centre below D, mm"),
    (["--ibpa", "90", "--h-c", "20"], "--h-l"),
    (["--h-c", "20"], "--h-c places the blades' rotation centre for --ibpa"),
    (["--h-l", "10"], "--h-l is the damper's size on a path that turns the platforms"),
    (["--ibpa", "90", "--motion", "0,1,0"], "--ibpa and --motion are two ways"),
    (["--motion", "0,1"], "--motion must be three numbers"),
    (["--ibpa", "90", "--h-c", "20", "--h-l", "10", "--band"], "--band is computed for the paper's "
                                                                 "in-phase motion and curved-flat"),
    (["--ibpa", "90", "--h-c", "20", "--h-l", "10", "--diagram"], "--diagram is computed"),
    (["--ibpa", "90", "--h-c", "20", "--h-l", "10", "--stiffness", "interpolated"],
     "--stiffness interpolated is computed"),
    (["--damper", "wedge", "--band"], "--band is computed for the paper's in-phase motion and "
                                      "curved-flat damper only"),
    (["--damper", "wedge", "--modes", "example", "--h-l", "10"],
     "--damper must be curved-flat with --modes"),
    (["--br2", "0.5"], "--br2 places a wedge's right pads"),
    (["--ibpa", "90", "--h-c", "20", "--modes", "example", "--h-l", "10"],
     "--ibpa gives one platform path; with --modes"),
    (["--ibpa", "720", "--h-c", "20", "--h-l", "10"], "ibpa"),
])
def test_bad_path_arguments_exit_2_in_one_line(capsys, extra, needle):
    code, out, err = run(capsys, *BASE, *extra)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)


WEDGE = jd.DamperShape(60.0, 60.0, 0.0, 0.8, br2_over_hr=0.8)


# 86 worker-s each (2026-11-26): the path response program of each pad set
@pytest.mark.slow
@pytest.mark.parametrize("damper, shape, phi", [
    ([], jd.family_shape("60sym"), 60.0),
    (["--damper", "wedge", "--theta-l", "60", "--theta-r", "60"], WEDGE, 90.0),
])
def test_path_peaks_satisfy_the_peak_equation(capsys, damper, shape, phi):
    """At each reported peak A* (mm), A* (eta k_b + 1e-3 r^2 k_Im(r A*)) = F and
    f* = f0 sqrt(1 + 1e-3 r^2 k_Re(r A*) / k_b), with k from `elliptic_cycle` at psi = r A*
    from assembly (the response's default history on a path), and at FRF points |D| A = F:
    the peak solver, the path and the units, checked against the cycle computed on its own,
    for the curved-flat damper and a wedge."""
    r, f0, kb, eta = 1.5, 480.0, 600.0, 0.002
    base = BASE if not damper else ("response", "--mu", "0.5", *damper)
    code, out, _ = run(capsys, *base, "--force-n", "5,20", "--ibpa", str(phi), "--h-c", "25",
                       "--h-l", "10", "--psi-per-mm", str(r), "--f0-hz", str(f0),
                       "--modal-stiffness-n-per-mm", str(kb), "--loss-factor", str(eta), "--json")
    assert code == 0
    d = strict_json(out)
    assert d["inputs"]["initial"] == "assembly"
    assert d["inputs"]["motion"]["ibpa_deg"] == phi and d["inputs"]["motion"]["quadrature"]
    motion = jd.interblade_motion(phi, 25.0, 100.0, 10.0)
    for p in d["peaks"]:
        assert p["status"] == "ok"
        a = p["peak_amplitude_mm"]
        assert p["psi_a_mrad"] == pytest.approx(r * a, rel=1e-12)
        c = jd.elliptic_cycle(shape, 0.5, r * a, motion, initial="assembly")
        assert jd.RESULTS.name_of(c.status) == "ok"
        force = a * (eta * kb + 1e-3 * r ** 2 * float(c.k_im))
        assert force == pytest.approx(p["force_n"], rel=1e-6)
        f_peak = f0 * (1.0 + 1e-3 * r ** 2 * float(c.k_re) / kb) ** 0.5
        assert p["peak_frequency_hz"] == pytest.approx(f_peak, rel=1e-9)
    # FRF points: |D(omega, A)| A = F with D = k_b (1 - (f/f0)^2 + i eta) + 1e-3 r^2 k(r A).
    for entry in d["frf"]["forces"]:
        assert entry["damper"]["low"]["amplitude_mm"] and entry["damper"]["high"]["amplitude_mm"]
        for branch in ("low", "high"):
            pts = entry["damper"][branch]
            for i in (0, len(pts["amplitude_mm"]) // 2):
                a, f = pts["amplitude_mm"][i], pts["frequency_hz"][i]
                c = jd.elliptic_cycle(shape, 0.5, r * a, motion, initial="assembly")
                re = kb * (1.0 - (f / f0) ** 2) + 1e-3 * r ** 2 * float(c.k_re)
                im = eta * kb + 1e-3 * r ** 2 * float(c.k_im)
                assert abs(complex(re, im)) * a == pytest.approx(entry["force_n"], rel=1e-7)
