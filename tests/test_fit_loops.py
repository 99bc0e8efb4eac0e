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
from jaxdamp.fit import K_REF, LoopError, analyse_loop, identify, sample_loop

from helpers import assert_tree_allclose, one_error_line, run_cli, strict_json

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


@pytest.mark.slow  # 108 worker-s (run of 2026-11-25)
def test_synthetic_loops_recovered_inside_intervals(noisy_fit):
    _, fit, steps = noisy_fit
    assert jd.RESULTS.name_of(fit.status) == "ok"
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
    assert_tree_allclose(c, c.T, rtol=1e-5, atol=1e-8)
    assert_tree_allclose(np.diag(c), np.ones(len(c)), rtol=1e-5, atol=1e-8)
    assert fit.sigma == pytest.approx(np.mean([0.005 * np.ptp(m) for _, m in _noisy_loops()]), rel=0.3)


@pytest.mark.slow  # 18.5 worker-s (run of 2026-11-28)
def test_standard_errors_are_those_of_a_finite_difference_jacobian():
    """The solver's Jacobian of the residuals (forward mode through the kernel, once per point it
    visits) gives the fit's standard errors; the same formula on central differences of
    `fit_problem`'s residuals at the optimum gives the same numbers."""
    loops = _noisy_loops(seed=3)
    fit = jd.fit_loops(loops, SHAPE, robust=False)
    prob = jd.blocks.fit_problem(loops, SHAPE)
    n_phys = prob.n_phys
    assert all(fit.identifiable) and n_phys == 3
    theta = np.concatenate([np.log(fit.value[:1]), np.log(fit.value[1:3] / K_REF),
                            fit.value[3:] / prob.scale])

    def res(th):
        return np.asarray(prob.residuals(th, 0.0))

    h = 1e-6
    jac = np.stack([(res(theta + h * e) - res(theta - h * e)) / (2 * h) for e in np.eye(theta.size)],
                   axis=1)
    mask = np.asarray(prob.data.mask).reshape(-1) > 0
    r, jac = res(theta)[mask], jac[mask]
    sigma2 = float(np.sum(r ** 2) / (r.size - theta.size))
    ok, _, cov = identify(jac, sigma2, prob.names, n_phys)
    se_t = np.sqrt(np.diag(cov))
    se = np.concatenate([fit.value[:n_phys] * se_t[:n_phys], se_t[n_phys:] * prob.scale])
    assert all(ok)
    assert_tree_allclose(fit.se, se, rtol=1e-4, atol=0.0)


@pytest.mark.slow  # 271 worker-s, fixture included (loaded run, 2026-11-26): a second fit program
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
    assert jd.RESULTS.name_of(res.status) == "ok" and int(res.newton_failures) == 0
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
    assert jd.RESULTS.name_of(fit.status) == "ok" and all(fit.identifiable)
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
    assert_tree_allclose(lp.u[clear], np.where(forward, 0.5 * (1 - x_found), 0.5 * (1 + x_found))[clear],
                         rtol=1e-5, atol=1e-8)
    assert_tree_allclose(lp.u[clear], u[clear], rtol=1e-5, atol=0.03)
    assert np.all((lp.u >= 0) & (lp.u <= 1)) and lp.periods >= 1


def test_synthetic_loops_refuse_times_that_are_not_numbers():
    """sample_loop's and sample_contact_loop's t: one line naming t (numpy's conversion error
    before; a NaN time gave NaN samples)."""
    from jaxdamp.fit import sample_contact_loop

    for t in ("a", [0.0, np.nan]):
        with pytest.raises(ValueError, match=r"^t must be a finite number in \(-inf, inf\) periods"):
            sample_loop(SHAPE, TRUE["mu"], 1.2, CONTACTS, t=t)
        with pytest.raises(ValueError, match=r"^t must be a finite number in \(-inf, inf\) periods"):
            sample_contact_loop(SHAPE, TRUE["mu"], 1.2, CONTACTS, contact=0, component="normal", t=t)


def test_a_loop_that_is_not_a_pair_of_number_arrays_is_one_line_naming_it():
    """A lone array, text or a triple failed in `analyse_loop`'s call with Python's argument
    errors; text columns with numpy's conversion error."""
    for loop, says in ((np.ones(5), "got ndarray of length 5"), ("a", "got str"),
                       ((np.ones(5), np.ones(5), 1.0), "got tuple of length 3")):
        with pytest.raises(ValueError, match=r"^loops: loop 1 must be a \(psi_mrad, moment_nmm\) "
                                             r"pair of 1-D arrays, a MomentLoop or a ContactLoop; " + says):
            jd.fit_loops([loop], SHAPE)
    with pytest.raises(LoopError, match=r"^loop 1: moment_nmm must be numbers; got \['x'"):
        jd.fit_loops([(np.ones(5), ["x"] * 5)], SHAPE)
    with pytest.raises(ValueError, match=r"^loops must be a list of loops; got float$"):
        jd.fit_loops(1.0, SHAPE)


def test_fit_options_are_refused_in_one_line_before_any_work():
    """An unknown start key and names of another length were ignored, robust="no" taken as True,
    a callback that is not a function failed after the first solver step."""
    loop = sample_loop(SHAPE, TRUE["mu"], 1.2, CONTACTS, t=np.linspace(0.0, 2.0, 201))
    for kwargs, says in (({"start": {"mux": 0.5}}, r"^start may give mu, kn, kt; got mux$"),
                         ({"names": ["a", "b"]}, r"^names must be a list of one name per loop \(1\); got \['a', 'b'\]$"),
                         ({"robust": "no"}, r"^robust must be True or False; got 'no'$"),
                         ({"callback": 5}, r"^callback must be a function \(stage, step, loss\) or None"),
                         ({"max_steps": 0}, r"^max_steps must be an integer in \[1, inf\); got 0$"),
                         ({"start": 5}, r"^start must be a dict of mu, kn, kt or None; got int$"),
                         ({"names": "a"}, r"^names must be a list of one name per loop \(1\)")):
        with pytest.raises(ValueError, match=says):
            jd.fit_loops([loop], SHAPE, **kwargs)


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
    # the start's stiffness inside the validated range: at most 1e6 F_D per mm (1e9 N/mm here)
    code, _, err = run_cli(capsys, "fit-loops", f, "--shape", "60sym", "--start-kn", "2e9")
    assert code == 2 and "--start-kn must be in (0, 1e+09] N/mm; got 2e+09" in one_error_line(err)
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


@pytest.mark.slow  # 96 worker-s (run of 2026-11-25)
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


# ---------------------------------------------------------------- per-contact loops (disp_mm, force_n)
# Tangential loops of the three contacts, one per amplitude (the same three-loop program as above).
CONTACT_CASES = ((0.8, 0, 20.0), (1.5, 1, -30.0), (3.0, 2, 10.0))  # psi_a mrad, contact, force offset N
DISP_OFFSET = 0.01  # mm


def _contact_loops(seed=2, n=500, noise=0.005, component="tangential", cases=CONTACT_CASES):
    from jaxdamp.fit import sample_contact_loop

    rng = np.random.default_rng(seed)
    out = []
    for a, c, off in cases:
        t = np.sort(rng.uniform(0.0, 2.5, n))
        d, f = sample_contact_loop(SHAPE, TRUE["mu"], a, CONTACTS, contact=c, component=component, t=t)
        out.append((d + DISP_OFFSET, f + off + rng.normal(0.0, noise * np.ptp(f), n)))
    return out


def test_contact_loops_recovered_inside_intervals():
    """Tangential force against the contact's own displacement, one loop per contact: mu, kn, kt and
    the force offsets come back inside their intervals."""
    from jaxdamp.fit import analyse_contact_loop

    loops = [analyse_contact_loop(d, f, c, "tangential", a, name=f"c{c}")
             for (d, f), (a, c, _) in zip(_contact_loops(), CONTACT_CASES)]
    fit = jd.fit_loops(loops, SHAPE)
    assert jd.RESULTS.name_of(fit.status) == "ok" and all(fit.monotone)
    assert fit.names == ["mu", "kn", "kt", "offset_0", "offset_1", "offset_2"] and all(fit.identifiable)
    for i, key in enumerate(("mu", "kn", "kt")):
        assert fit.lo[i] <= TRUE[key] <= fit.hi[i], (key, fit.lo[i], fit.value[i], fit.hi[i])
    for j, (_, _, off) in enumerate(CONTACT_CASES):
        assert abs(fit.value[3 + j] - off) <= 3.0 * fit.se[3 + j]
    for lp, (a, c, _) in zip(fit.loops, CONTACT_CASES):
        assert lp.psi_a == a and lp.contact == c and lp.periods == 2
    # residual sd near the noise put in (N)
    noise = np.mean([0.005 * np.ptp(f) for _, f in _contact_loops()])
    assert fit.sigma == pytest.approx(noise, rel=0.3)


@pytest.mark.slow  # 12 worker-s (run of 2026-11-25)
def test_contact_model_force_is_exact_at_the_truth():
    """The fit's displacement-inverted model force equals the travel-sampled one (no noise): the
    residual at the true parameters is rounding only."""
    from jaxdamp.fit import analyse_contact_loop, fit_problem

    from jaxdamp.fit import sample_contact_loop

    rng = np.random.default_rng(12)
    loops = []
    for a, c, _ in CONTACT_CASES:  # random times that include the reversals (exact centre found)
        t = np.sort(np.concatenate([rng.uniform(0.1, 2.4, 300), [0.5, 1.0, 1.5, 2.0]]))
        d, f = sample_contact_loop(SHAPE, TRUE["mu"], a, CONTACTS, contact=c, component="tangential", t=t)
        loops.append(analyse_contact_loop(d + DISP_OFFSET, f, c, "tangential", a))
    prob = fit_problem(loops, SHAPE)
    theta = np.concatenate([[np.log(TRUE["mu"]), np.log(TRUE["kn"] / 1e4), np.log(TRUE["kt"] / 1e4)],
                            np.zeros(3)])
    r = np.asarray(prob.residuals(theta, 0.0))
    assert np.max(np.abs(r)) < 1e-9  # units of the force scale (~ 250 N)


def _march_contact_loop(a, contact, n_steps=120, pairs=4):
    """Two periods of one contact's (d_t = T / kt - slip in mm, T in N) from the time marcher's
    steady cycle (fine uniform steps; no direct method in it)."""
    import jax

    from jaxdamp.baselines.timemarch import initial_state, march_half, march_model
    from jaxdamp.conventions import travel_mm
    from jaxdamp.params import LoadCase, prepare_inputs

    shape, mu, contacts, load = prepare_inputs(SHAPE, TRUE["mu"], CONTACTS, LoadCase())

    @jax.jit
    def run(a):
        m, _ = march_model(shape, mu, contacts, load)
        h = 2.0 * travel_mm(a, m.q_star) / n_steps

        def pair(s, _):
            s1, f = march_half(m, s, -1.0, h, n_steps)
            s2, b = march_half(m, s1, 1.0, h, n_steps)
            return s2, (f.samples, b.samples)

        _, (f, b) = jax.lax.scan(pair, initial_state(m), None, length=pairs)
        return m.kt, m.F_D, f, b

    kt, F_D, f, b = run(a)
    kt = float(kt[contact])
    d = lambda s: np.asarray(s.T[-1, :, contact]) / kt - np.asarray(s.p[-1, :, contact])  # noqa: E731
    T = lambda s: np.asarray(s.T[-1, :, contact]) * float(F_D)  # noqa: E731
    assert np.all(np.asarray(f.newton_ok)) and np.all(np.asarray(b.newton_ok))
    return (np.concatenate([d(f), d(b)[1:], d(f)[1:], d(b)[1:]]),
            np.concatenate([T(f), T(b)[1:], T(f)[1:], T(b)[1:]]))


@pytest.mark.slow  # 18 worker-s (run of 2026-11-25)
def test_contact_loops_from_the_time_marcher():
    from jaxdamp.fit import analyse_contact_loop

    rng = np.random.default_rng(5)
    loops = []
    for a, c, _ in CONTACT_CASES:
        d, f = _march_contact_loop(a, c)
        loops.append(analyse_contact_loop(d, f + rng.normal(0.0, 0.002 * np.ptp(f), f.size), c,
                                          "tangential", a))
    fit = jd.fit_loops(loops, SHAPE, start={"mu": 0.6, "kn": 5e3, "kt": 2e3})
    assert jd.RESULTS.name_of(fit.status) == "ok" and all(fit.identifiable)
    for i, key in enumerate(("mu", "kn", "kt")):
        assert fit.value[i] == pytest.approx(TRUE[key], rel=0.03), key
        assert fit.lo[i] <= TRUE[key] <= fit.hi[i] or abs(fit.value[i] / TRUE[key] - 1) < 0.01


def test_cli_normal_contact_loops_identify_kn_only(capsys, tmp_path):
    """Normal force against the approach is the line N = kn d (no hysteresis in the normal spring):
    kn comes back inside its interval; mu, kt (and the offsets) are stated not identifiable, with no
    number."""
    cases = ((0.8, 0, 5.0), (0.8, 1, -5.0), (0.8, 2, 0.0))
    files = [_write_csv(tmp_path / f"n{i}.csv", d, f, header="disp_mm,force_n")
             for i, (d, f) in enumerate(_contact_loops(component="normal", cases=cases))]
    d2, f2 = _contact_loops(component="normal", cases=cases)[2]  # one as NPZ
    np.savez(tmp_path / "n2.npz", disp_mm=d2, force_n=f2)
    files[2] = tmp_path / "n2.npz"
    code, text, _ = run_cli(capsys, "fit-loops", *files, "--shape", "60sym", "--contact", "R1,L1,L2",
                            "--component", "normal", "--psi-a", "0.8", "--json", "--no-progress",
                            "--plot", tmp_path / "plots")
    assert code == 0
    d = strict_json(text)
    p = d["parameters"]
    # the force offsets go with them: a free offset cannot be told from the mean normal force,
    # the only place where mu and kt enter a normal loop
    assert set(d["not_identifiable"]) == {"mu", "kt", "offset_0", "offset_1", "offset_2"}
    for name in ("mu", "kt"):
        assert p[name]["value"] is None and "not identifiable" in p[name]["why"]
    assert p["kn"]["identifiable"] and p["kn"]["lo"] <= TRUE["kn"] <= p["kn"]["hi"]
    rows = d["loops"]
    assert [r["contact"] for r in rows] == ["R1", "L1", "L2"] and rows[0]["component"] == "normal"
    assert d["sigma_unit"] == "N" and d["sigma_nmm"] is None
    assert len(list((tmp_path / "plots").glob("loop_*.png"))) == 3


@pytest.mark.parametrize("content, flags, says", [
    ("disp_mm,force\n1,2\n", (), "no column force_n"),
    ("disp_mm,force_n\n1,2\n0,3\n", (), "give --contact"),
    ("disp_mm,force_n\n1,2\n0,3\n", ("--contact", "R1"), "give --component"),
    ("disp_mm,force_n\n1,2\n0,3\n", ("--contact", "R1", "--component", "tangential"), "give --psi-a"),
    ("disp_mm,force_n\n1,2\n0,3\n", ("--contact", "R3", "--component", "normal", "--psi-a", "1"),
     "--contact takes R1, L1 or L2"),
    ("disp_mm,force_n\n1,2\n0,3\n", ("--contact", "R1", "--component", "shear", "--psi-a", "1"),
     "--component takes tangential or normal"),
    ("disp_mm,force_n\n1,2\n0,3\n", ("--contact", "R1", "--component", "normal", "--psi-a", "-1"),
     "--psi-a must be in"),
    ("disp_mm,force_n\n1,2\n0,3\n", ("--contact", "R1,L1", "--component", "normal", "--psi-a", "1"),
     "one per per-contact file (1); got 2"),
    ("disp_mm,force_n\n1,2\n", ("--contact", "R1", "--component", "normal", "--psi-a", "1"), "1 sample"),
    ("disp_mm,force_n\n1,2\n0,nan\n-1,3\n", ("--contact", "R1", "--component", "normal", "--psi-a", "1"),
     "force_n is not a finite number at sample 2"),
    ("disp_mm,force_n\n1,2\n0,abc\n", ("--contact", "R1", "--component", "normal", "--psi-a", "1"),
     "line 3: force_n"),
    ("disp_mm,force_n\n" + "".join(f"{float(np.cos(x))!r},1\n" for x in np.linspace(0, 3, 40)),
     ("--contact", "L2", "--component", "tangential", "--psi-a", "1"), "no closed period: disp_mm"),
    ("disp_mm,force_n\n" + "".join(f"{float(500 * np.cos(x))!r},1\n" for x in np.linspace(0, 13, 90)),
     ("--contact", "L2", "--component", "tangential", "--psi-a", "1"), "out of range"),
    ("psi_mrad,moment_nmm,disp_mm,force_n\n1,2,3,4\n", (), "both a moment loop"),
    ("psi_mrad,moment_nmm\n1,2\n0,3\n", ("--psi-a", "1"), "none of the files is one"),
])
def test_cli_bad_contact_files_one_line_exit_2(capsys, tmp_path, content, flags, says):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    code, _, err = run_cli(capsys, "fit-loops", f, "--shape", "60sym", *flags)
    assert code == 2 and says in one_error_line(err), one_error_line(err)


def test_moment_and_contact_loops_fitted_together():
    """Two moment loops and one tangential contact loop in one fit: units kept apart (offsets in
    N mm and N, no common residual sd), parameters inside their intervals."""
    from jaxdamp.fit import analyse_contact_loop

    moment = _noisy_loops()[:2]
    (d, f), = _contact_loops(cases=CONTACT_CASES[2:])
    a, c, off = CONTACT_CASES[2]
    fit = jd.fit_loops(moment + [analyse_contact_loop(d, f, c, "tangential", a)], SHAPE)
    assert jd.RESULTS.name_of(fit.status) == "ok" and all(fit.identifiable) and np.isnan(fit.sigma)
    for i, key in enumerate(("mu", "kn", "kt")):
        assert fit.lo[i] <= TRUE[key] <= fit.hi[i], (key, fit.lo[i], fit.value[i], fit.hi[i])
    for j, o in enumerate(OFFSETS[:2] + (off,)):
        assert abs(fit.value[3 + j] - o) <= 3.0 * fit.se[3 + j]


@settings(max_examples=15, deadline=None)
@given(a=st.floats(1e-3, 50.0), c=st.floats(-1.0, 1.0), periods=st.floats(1.6, 4.0),
       per_period=st.integers(60, 300), seed=st.integers(0, 2 ** 16), contact=st.sampled_from(["R1", "L1", "L2", 0, 2]),
       component=st.sampled_from(["tangential", "normal"]), psi_a=st.floats(1e-3, 1e4))
def test_random_valid_contact_loops_analysed(a, c, periods, per_period, seed, contact, component, psi_a):
    """A contact loop's displacement is analysed as psi is (amplitude, centre, halves: forward =
    displacement decreasing); the contact, component and the given psi_a are kept."""
    from jaxdamp.fit import analyse_contact_loop

    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0.0, periods, int(per_period * periods)))
    d = c + a * np.cos(2 * np.pi * t)
    lp = analyse_contact_loop(d, np.sin(t), contact, component, psi_a)
    ref = analyse_loop(d, np.sin(t))
    assert lp.disp_a == ref.psi_a and lp.disp_c == ref.psi_c and lp.periods == ref.periods
    assert np.array_equal(lp.forward, ref.forward) and lp.disp_a == pytest.approx(a, rel=2e-2)
    assert lp.contact == (contact if isinstance(contact, int) else ["R1", "L1", "L2"].index(contact))
    assert lp.component == component and lp.psi_a == psi_a


def test_contact_loop_api_errors_one_line():
    from jaxdamp.fit import analyse_contact_loop

    d = np.cos(np.linspace(0, 4 * np.pi, 80))
    for args, says in (((d, d, "R4", "normal", 1.0), "contact must be one of R1, L1, L2"),
                       ((d, d, 3, "normal", 1.0), "contact must be 0, 1, 2"),
                       ((d, d, 0, "shear", 1.0), "tangential or normal"),
                       ((d, d, 0, "normal", 0.0), "out of range"),
                       ((d, d, 0, "normal", "x"), "must be a number"),
                       ((d * 1e3, d, 0, "normal", 1.0), "mm is out of range: must be in (0, 100] mm")):
        with pytest.raises(LoopError) as e:
            analyse_contact_loop(*args)
        assert says in str(e.value) and "\n" not in str(e.value), (says, str(e.value))


# ---------------------------------------------------------------- the loop's direction
def test_loop_work_is_the_energy_of_the_first_harmonic():
    """The loop M = psi_a (k_Re cos tau - k_Im sin tau) at psi = psi_a cos tau encloses
    pi psi_a^2 k_Im per cycle (the closed form of the harmonic's energy, README's convention:
    k_Im > 0 and the integral of M dpsi is the energy dissipated); offsets in either channel, the
    start phase and the sampling do not change it; the mirrored loops enclose minus that."""
    from jaxdamp.fit import loop_work

    psi_a, k_re, k_im = 1.3, 800.0, 150.0
    rng = np.random.default_rng(5)
    tau = 0.7 + np.sort(rng.uniform(0.0, 3 * 2 * np.pi, 3000))
    tau = np.concatenate([[0.7], tau, [0.7 + 6 * np.pi]])  # whole periods: three
    psi = 0.4 + psi_a * np.cos(tau)
    m = -25.0 + psi_a * (k_re * np.cos(tau) - k_im * np.sin(tau))
    energy = np.pi * psi_a ** 2 * k_im  # N mm mrad per cycle
    assert loop_work(psi, m) == pytest.approx(energy, rel=1e-4)
    assert loop_work(psi, -m) == pytest.approx(-energy, rel=1e-4)
    assert loop_work(-psi, m) == pytest.approx(-energy, rel=1e-4)
    # part of a period more: the sign and the size stay
    cut = tau < 0.7 + 2.4 * 2 * np.pi
    assert 0.7 * energy < loop_work(psi[cut], m[cut]) < 1.3 * energy
    assert loop_work(psi, np.full_like(psi, 3.0)) == pytest.approx(0.0, abs=1e-9 * energy)


@pytest.mark.parametrize("mirror", ["moment", "psi"])
def test_cli_refuses_a_loop_that_runs_the_wrong_way(capsys, tmp_path, monkeypatch, mirror):
    """A moment loop enclosing negative energy (the model's loop with M or psi negated) stops the
    command before any fitting: one line saying so and naming --flip-moment, exit code 2."""
    import jaxdamp.fit

    def no_fit(*a, **k):
        raise AssertionError("the fit started")

    monkeypatch.setattr(jaxdamp.fit, "fit_loops", no_fit)
    monkeypatch.setattr(jaxdamp.fit, "fit_problem", no_fit)
    good = _noisy_loops(n=300)
    psi, m = good[1]
    files = [_write_csv(tmp_path / "good.csv", *good[0]),
             _write_csv(tmp_path / "mirrored.csv", *((psi, -m) if mirror == "moment" else (-psi, m)))]
    code, _, err = run_cli(capsys, "fit-loops", *files, "--shape", "60sym")
    line = one_error_line(err)
    assert code == 2 and "mirrored.csv" in line and "good.csv" not in line
    assert "encloses negative energy under the convention" in line and "rerun with --flip-moment" in line


def test_cli_flip_moment_fits_the_negated_loop(capsys, tmp_path, monkeypatch):
    """--flip-moment negates the moment column: loops recorded with the opposite moment sign go to
    the fit as the convention has them (stopped at the fit's entry: the loops it receives are
    checked, no fit is run); on loops that were right, the flag makes them wrong and says so."""
    import jaxdamp.fit

    class Reached(Exception):
        pass

    seen = {}

    def capture(loops, shape, **kw):
        seen["loops"] = loops
        raise Reached

    monkeypatch.setattr(jaxdamp.fit, "fit_loops", capture)
    good = _noisy_loops(n=300)
    files = [_write_csv(tmp_path / f"{i}.csv", psi, -m) for i, (psi, m) in enumerate(good)]
    with pytest.raises(Reached):
        run_cli(capsys, "fit-loops", *files, "--shape", "60sym", "--flip-moment")
    assert len(seen["loops"]) == 3
    for lp, (psi, m) in zip(seen["loops"], good):
        assert np.array_equal(lp.psi, psi) and np.array_equal(lp.moment, m)
        assert jaxdamp.fit.loop_work(lp.psi, lp.moment) > 0
    files = [_write_csv(tmp_path / f"g{i}.csv", psi, m) for i, (psi, m) in enumerate(good)]
    code, _, err = run_cli(capsys, "fit-loops", *files, "--shape", "60sym", "--flip-moment")
    assert code == 2 and "--flip-moment was given: drop it" in one_error_line(err)


def test_cli_tangential_loops_checked_normal_loops_not(capsys, tmp_path, monkeypatch):
    """A tangential contact loop encloses the friction energy dissipated at its contact (positive):
    negated, it is refused in one line naming --flip-force, and --flip-force fixes it. A normal
    loop is elastic (no enclosed energy, its sign is noise): not checked."""
    import jaxdamp.fit

    class Reached(Exception):
        pass

    def stop(*a, **k):
        raise Reached

    monkeypatch.setattr(jaxdamp.fit, "fit_loops", stop)
    (d, f), = _contact_loops(n=300, cases=CONTACT_CASES[1:2])
    a, c, _ = CONTACT_CASES[1]
    flags = ("--shape", "60sym", "--contact", "L1", "--psi-a", str(a))
    neg = _write_csv(tmp_path / "t.csv", d, -f, header="disp_mm,force_n")
    code, _, err = run_cli(capsys, "fit-loops", neg, *flags, "--component", "tangential")
    line = one_error_line(err)
    assert code == 2 and "encloses negative energy" in line and "rerun with --flip-force" in line
    with pytest.raises(Reached):
        run_cli(capsys, "fit-loops", neg, *flags, "--component", "tangential", "--flip-force")
    (dn, fn), = _contact_loops(n=300, component="normal", cases=CONTACT_CASES[1:2])
    for sign in (1.0, -1.0):
        nf = _write_csv(tmp_path / "n.csv", dn, sign * fn, header="disp_mm,force_n")
        with pytest.raises(Reached):
            run_cli(capsys, "fit-loops", nf, *flags, "--component", "normal")
