"""jaxdamp.fit and `jaxdamp fit-loops`: contact parameters from measured moment loops.

Truth values are chosen inputs (mu = 0.4, kn = 25000, kt = 4000 N/mm: neither the library's
reference pair nor the fit's generic start), never numbers the fit produced. Every fit here uses
three loops of at most 512 samples, shared parameters and the gross-slip history, so that they all
run one compiled program (the persistent cache keeps it between runs).
"""

import json

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import jaxdamp as jd
from jaxdamp.baselines.timemarch import march_amplitude
from jaxdamp.fit import LoopError, analyse_loop, identify, sample_loop

from helpers import one_error_line, run_cli, strict_json

SHAPE = jd.family_shape("60sym")
TRUE = {"mu": 0.4, "kn": 25000.0, "kt": 4000.0}
CONTACTS = jd.Contacts(TRUE["kn"], TRUE["kt"])
AMPS = (0.8, 1.5, 3.0)  # mrad: two microslip loops (psi_BC ~ 1.6) and one with gross slip
OFFSETS = (30.0, -50.0, 10.0)  # N mm
PSI_OFFSET = 0.2  # mrad


def _noisy_loops(seed=1, n=500, noise=0.005):
    rng = np.random.default_rng(seed)
    loops = []
    for a, off in zip(AMPS, OFFSETS):
        t = np.sort(rng.uniform(0.0, 2.5, n))  # 2.5 periods, irregular sampling
        psi, m = sample_loop(SHAPE, TRUE["mu"], a, CONTACTS, t=t)
        loops.append((psi + PSI_OFFSET, m + off + rng.normal(0.0, noise * np.ptp(m), n)))
    return loops


@pytest.fixture(scope="module")
def noisy_fit():
    loops = _noisy_loops()
    steps = []
    fit = jd.fit_loops(loops, SHAPE, callback=lambda s, k, loss: steps.append((s, k, loss)))
    return loops, fit, steps


def test_synthetic_loops_recovered_inside_intervals(noisy_fit):
    _, fit, steps = noisy_fit
    assert fit.converged and jd.RESULTS.name_of(fit.status) == "ok"
    assert fit.names[:3] == ["mu", "kn", "kt"] and all(fit.identifiable)
    for i, key in enumerate(("mu", "kn", "kt")):
        assert fit.lo[i] <= TRUE[key] <= fit.hi[i], (key, fit.lo[i], fit.value[i], fit.hi[i])
        assert fit.lo[i] < fit.value[i] < fit.hi[i]
    for j, off in enumerate(OFFSETS):  # per-loop moment offsets within 3 standard errors
        assert abs(fit.value[3 + j] - off) <= 3.0 * fit.se[3 + j]
    # the amplitude and centre found from the data
    for lp, a in zip(fit.loops, AMPS):
        assert lp.psi_a == pytest.approx(a, rel=2e-3) and lp.psi_c == pytest.approx(PSI_OFFSET, abs=2e-3)
        assert lp.periods == 2
    # convergence shown: both stages reported, the loss falls from the generic start
    assert {s for s, _, _ in steps} == {0, 1} and fit.history == steps
    first = [v for s, k, v in steps if s == 0]
    assert steps[0][:2] == (0, 0) and first[-1] < 0.01 * first[0]
    c = fit.correlation
    assert np.allclose(c, c.T) and np.allclose(np.diag(c), 1.0)
    assert fit.sigma == pytest.approx(np.mean([0.005 * np.ptp(m) for _, m in _noisy_loops()]), rel=0.3)


def test_robust_loss_resists_outliers(noisy_fit):
    loops, clean, _ = noisy_fit
    rng = np.random.default_rng(7)
    spoiled = []
    for psi, m in loops:
        m = m.copy()
        k = rng.choice(m.size, 10, replace=False)  # 2 % of the samples, 30 x the noise
        m[k] += rng.choice([-1.0, 1.0], 10) * 30 * 0.005 * np.ptp(m)
        spoiled.append((psi, m))
    robust = jd.fit_loops(spoiled, SHAPE)
    plain = jd.fit_loops(spoiled, SHAPE, robust=False)
    err = lambda f: abs(np.log(f.value[:3] / np.array([0.4, 25000.0, 4000.0])))  # noqa: E731
    assert np.all(err(robust) < 0.02)
    assert np.sum(err(robust)) < np.sum(err(plain))


def _march_loop(a, n_steps=120):
    """Two periods of the time marcher's steady loop: psi uniform in travel, forward half first."""
    res = march_amplitude(SHAPE, TRUE["mu"], a, CONTACTS, n_steps=n_steps, max_pairs=4)
    assert not bool(res.liftoff) and int(res.newton_failures) == 0
    x = np.linspace(1.0, -1.0, n_steps + 1)
    fwd, bwd = np.asarray(res.M_forward), np.asarray(res.M_backward)
    psi = np.concatenate([a * x, -a * x[1:], a * x[1:], -a * x[1:]])
    m = np.concatenate([fwd, bwd[1:], fwd[1:], bwd[1:]])
    return psi, m


def test_loops_from_the_time_marcher():
    """Loops of the independent fine-step time marcher (no direct method in them) give back the
    parameters they were marched with."""
    rng = np.random.default_rng(3)
    loops = []
    for a in AMPS:
        psi, m = _march_loop(a)
        loops.append((psi, m + rng.normal(0.0, 0.002 * np.ptp(m), m.size)))
    fit = jd.fit_loops(loops, SHAPE, start={"mu": 0.6, "kn": 5e3, "kt": 2e3})
    assert fit.converged and all(fit.identifiable)
    for i, key in enumerate(("mu", "kn", "kt")):
        assert fit.value[i] == pytest.approx(TRUE[key], rel=0.03), key
        assert fit.lo[i] <= TRUE[key] <= fit.hi[i] or abs(fit.value[i] / TRUE[key] - 1) < 0.01


def test_identify_states_a_null_direction_instead_of_a_number():
    rng = np.random.default_rng(0)
    a = rng.normal(size=(200, 1))
    # columns 1 and 2 enter only through their sum (kn R1 and kn L that one loop cannot separate)
    jac = np.hstack([rng.normal(size=(200, 1)), a, a, rng.normal(size=(200, 1))])
    ok, why, cov = identify(jac, 1e-4, ["mu", "kn_R1", "kn_L", "offset_0"], 3)
    assert list(ok) == [True, False, False, True]
    assert "not identifiable" in why[1] and "kn_L" in why[1] and why[0] == ""
    assert np.isnan(cov[1, 1]) and np.isfinite(cov[0, 0]) and np.isfinite(cov[0, 3])
    # a parameter the data barely see: a huge interval is reported as not identifiable
    jac2 = np.hstack([rng.normal(size=(200, 1)), 1e-3 * rng.normal(size=(200, 1))])
    ok2, why2, _ = identify(jac2, 1e-2, ["mu", "kt"], 2)
    assert list(ok2) == [True, False] and "factor" in why2[1]


# ---------------------------------------------------------------- loop analysis (no fitting)
@settings(max_examples=25, deadline=None)
@given(a=st.floats(0.05, 50.0), c=st.floats(-5.0, 5.0), periods=st.floats(1.6, 4.0),
       per_period=st.integers(60, 300), t0=st.floats(0.0, 1.0), seed=st.integers(0, 2 ** 16))
def test_random_valid_loops_analysed(a, c, periods, per_period, t0, seed):
    """Any random sampling (60-300 samples a period), start phase, centre and length: amplitude, centre and every sample's half and
    travel fraction come back (psi = c + a cos 2 pi t; forward = psi decreasing)."""
    rng = np.random.default_rng(seed)
    t = np.sort(t0 + rng.uniform(0.0, periods, int(per_period * periods)))
    psi = c + a * np.cos(2 * np.pi * t)
    lp = analyse_loop(psi, np.sin(t))
    assert lp.psi_a == pytest.approx(a, rel=2e-2) and lp.psi_c == pytest.approx(c, abs=2e-2 * a)
    phase = np.mod(t, 1.0)
    forward = phase < 0.5
    # every sample but the sampled turning points (a sampled extreme starts the next half, whichever
    # side of the true reversal it lies: the model's halves meet there)
    pad = np.concatenate([[np.inf], psi, [np.inf]])
    low = (psi <= pad[:-2]) & (psi <= pad[2:])
    pad = np.concatenate([[-np.inf], psi, [-np.inf]])
    high = (psi >= pad[:-2]) & (psi >= pad[2:])
    clear = ~low & ~high
    assert np.array_equal(lp.forward[clear], forward[clear])
    x = np.cos(2 * np.pi * t)
    u = np.where(forward, 0.5 * (1 - x), 0.5 * (1 + x))
    x_found = np.clip((psi - lp.psi_c) / lp.psi_a, -1.0, 1.0)
    assert np.allclose(lp.u[clear], np.where(forward, 0.5 * (1 - x_found), 0.5 * (1 + x_found))[clear])
    assert np.allclose(lp.u[clear], u[clear], atol=0.03)
    assert np.all((lp.u >= 0) & (lp.u <= 1)) and lp.periods >= 1


def test_model_residual_is_zero_at_the_truth_on_random_sampling():
    """The travel-phase residual of exact model samples vanishes at the true parameters (random
    sampling that includes the reversals, so that the amplitude found is exact)."""
    rng = np.random.default_rng(11)
    t = np.sort(np.concatenate([rng.uniform(0.1, 2.4, 300), [0.5, 1.0, 1.5, 2.0]]))
    psi, m = sample_loop(SHAPE, TRUE["mu"], 1.2, CONTACTS, t=t)
    lp = analyse_loop(psi, m)
    ac = jd.amplitude_cycle(SHAPE, TRUE["mu"], lp.psi_a, CONTACTS)
    from jaxdamp.fit import loop_model_moment

    back = np.asarray(loop_model_moment(ac, lp.forward, lp.u))
    assert lp.psi_a == pytest.approx(1.2, rel=1e-12)
    assert np.max(np.abs(back - m)) <= 1e-9 * np.ptp(m)


@pytest.mark.parametrize("psi, m, says", [
    ([1.0], [2.0], "1 sample"),
    ([0.0, 1.0, np.nan, 0.0], [1.0, 2.0, 3.0, 4.0], "not a finite number at sample 3"),
    (np.cos(np.linspace(0, np.pi, 50)), np.zeros(50), "no closed period"),
    (np.ones(20), np.zeros(20), "constant"),
    (2e4 * np.cos(np.linspace(0, 4 * np.pi, 80)), np.zeros(80), "out of range"),
])
def test_unusable_loops_raise_one_line(psi, m, says):
    with pytest.raises(LoopError, match=says) as exc:
        analyse_loop(psi, m, name="x.csv")
    assert "\n" not in str(exc.value) and "x.csv" in str(exc.value)


# ---------------------------------------------------------------- the command
def _write_csv(path, psi, m, header="psi_mrad,moment_nmm"):
    rows = [header] + [f"{float(p)!r},{float(v)!r}" for p, v in zip(psi, m)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_cli_fit_json_feeds_contacts_from(capsys, tmp_path):
    files = []
    for i, (psi, m) in enumerate(_noisy_loops()):
        if i == 2:  # one loop as NPZ
            np.savez(tmp_path / "c.npz", psi_mrad=psi, moment_nmm=m)
            files.append(tmp_path / "c.npz")
        else:
            files.append(_write_csv(tmp_path / f"{'ab'[i]}.csv", psi, m))
    out = tmp_path / "fit.json"
    code, text, err = run_cli(capsys, "fit-loops", *files, "--shape", "60sym", "--json", "--out", out,
                              "--plot", tmp_path / "plots")
    assert code == 0
    d = strict_json(text)
    assert d["status"] == "ok" and d["inputs"]["history"] == "gross_slip"
    assert json.loads(out.read_text())["contacts"] == d["contacts"]
    p = d["parameters"]
    for key in ("mu", "kn", "kt"):
        assert p[key]["identifiable"] and p[key]["lo"] <= TRUE[key] <= p[key]["hi"]
    assert d["not_identifiable"] == [] and len(d["loops"]) == 3
    assert "stage 1 (least squares) step" in err and "stage 2" in err  # convergence on stderr
    assert len(list((tmp_path / "plots").glob("loop_*.png"))) == 3
    assert (tmp_path / "plots" / "parameters.csv").read_text().startswith("parameter,value")
    # the fitted contacts run the other commands directly
    code, text, _ = run_cli(capsys, "amplitude", "--shape", "60sym", "--psi-a", "1.5",
                            "--contacts-from", out, "--json")
    a = strict_json(text)
    assert code == 0 and a["status"] == "ok"
    assert a["inputs"]["mu"] == pytest.approx(p["mu"]["value"])


@pytest.mark.parametrize("content, says", [
    ("psi_mrad,force\n1,2\n", "no column moment_nmm"),
    ("disp_mm,force_n\n1,2\n", "per-contact loops"),
    ("psi_mrad,moment_nmm\n1,2\n", "1 sample"),
    ("psi_mrad,moment_nmm\n1,2\n0,nan\n-1,3\n", "not a finite number at sample 2"),
    ("psi_mrad,moment_nmm\n1,2\n0,abc\n", "line 3"),
    ("psi_mrad,moment_nmm\n" + "".join(f"{float(np.cos(x))!r},1\n" for x in np.linspace(0, 3, 40)),
     "no closed period"),
    ("psi_mrad,moment_nmm\n" + "".join(f"{float(2e4 * np.cos(x))!r},1\n" for x in np.linspace(0, 13, 90)),
     "out of range"),
    ("", "empty"),
])
def test_cli_bad_files_one_line_exit_2(capsys, tmp_path, content, says):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    code, _, err = run_cli(capsys, "fit-loops", f, "--shape", "60sym")
    assert code == 2 and says in one_error_line(err)


def test_cli_bad_arguments(capsys, tmp_path):
    code, _, err = run_cli(capsys, "fit-loops", tmp_path / "none.csv", "--shape", "60sym")
    assert code == 2 and "does not exist" in one_error_line(err)
    f = _write_csv(tmp_path / "a.csv", *_noisy_loops(n=100)[0])
    code, _, err = run_cli(capsys, "fit-loops", f, "--shape", "60sym", "--per-contact", "mu,q")
    assert code == 2 and "--per-contact" in one_error_line(err)
    code, _, err = run_cli(capsys, "fit-loops", f, "--shape", "60sym", "--start-mu", "-1")
    assert code == 2 and "--start-mu" in one_error_line(err)
    (tmp_path / "file").write_text("")
    code, _, err = run_cli(capsys, "fit-loops", f, "--shape", "60sym", "--plot", tmp_path / "file")
    assert code == 2 and "--plot" in one_error_line(err)
    np.savez(tmp_path / "n.npz", psi=np.ones(3))
    code, _, err = run_cli(capsys, "fit-loops", tmp_path / "n.npz", "--shape", "60sym")
    assert code == 2 and "no column psi_mrad, moment_nmm" in one_error_line(err)


def test_fit_refuses_float32():
    import jax

    jax.config.update("jax_enable_x64", False)
    try:
        with pytest.raises(jd.Float64Required):
            jd.fit_loops([(np.cos(np.linspace(0, 9, 50)), np.zeros(50))], SHAPE)
    finally:
        jax.config.update("jax_enable_x64", True)


def test_unidentifiable_parameters_are_reported_not_numbered(capsys, tmp_path):
    """kn per contact from moment loops: the command names what the loops do not determine, gives
    no number for it, and keeps intervals for the rest (one compiled program more: ~1 min cold)."""
    files = [_write_csv(tmp_path / f"{i}.csv", psi, m) for i, (psi, m) in enumerate(_noisy_loops()[::2])]
    code, text, _ = run_cli(capsys, "fit-loops", *files, "--shape", "60sym", "--per-contact", "kn",
                            "--per-side", "kt", "--json", "--no-progress")
    d = strict_json(text)
    assert code == 0 and d["inputs"]["groups"] == {"mu": "shared", "kn": "contact", "kt": "side"}
    p = d["parameters"]
    for name in ("kn_R1", "kn_L1", "kn_L2"):
        assert name in d["not_identifiable"] and p[name]["value"] is None and p[name]["se"] is None
        assert "not identifiable" in p[name]["why"]
    assert p["mu"]["identifiable"] and p["mu"]["lo"] <= TRUE["mu"] <= p["mu"]["hi"]
    assert p["kt_L"]["identifiable"] and p["kt_L"]["lo"] <= TRUE["kt"] <= p["kt_L"]["hi"]
    assert any("not identifiable from these loops" in n for n in d["notes"])
    assert len(d["contacts"]["kn_n_per_mm"]) == 3  # the model still runs with them
