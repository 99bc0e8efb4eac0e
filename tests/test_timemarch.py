"""The independent time-marching solver (incremental return mapping) against the direct method.

The two solvers share only the geometry and the full-slip statics of state 0; the direct method's
state choice and closed-form events are not used by the time marcher. Agreement of all five numbers
is therefore an independent check of both.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.cycle import base_cycle_kernel
from jaxdamp.harmonics import five_numbers
from jaxdamp.statics import START_FRICTION_SIGNS
from jaxdamp.baselines.timemarch import time_march_kernel, time_march

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(jnp.asarray(jd.REFERENCE_KN), jnp.asarray(jd.REFERENCE_KT))
LOAD = jd.LoadCase(*(jnp.asarray(v) for v in (1000.0, 100.0, 0.0)))
FAMILY_CASES = [(name, mu) for name in jd.FAMILY for mu in (0.7, 0.5, 0.3)]
N_FINE = 24000  # steps per (longer) half-cycle at the finest step
NAMES = ("psi_fs", "k_re_fs", "psi_bc", "k_re_bc", "k_im_bc")


def _stack(shapes):
    return jd.DamperShape(*(jnp.asarray([getattr(s, f) for s in shapes], float)
                            for f in ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl")))


def _random_shapes(n=6, seed=20240607):
    rng = np.random.default_rng(seed)
    return ([jd.DamperShape(float(a), float(b), float(c)) for a, b, c in
             zip(rng.uniform(45, 85, n), rng.uniform(45, 85, n), rng.uniform(0.0, 0.22, n))],
            list(rng.uniform(0.2, 0.75, n)))


def _direct(shapes, mus):
    bc = jax.vmap(lambda s, m: base_cycle_kernel(s, m, CONTACTS, LOAD))(_stack(shapes), jnp.asarray(mus))
    nums = np.array(jax.vmap(five_numbers)(bc).numbers()).T
    span = np.maximum(np.asarray(bc.forward.span), np.asarray(bc.backward.span))
    return bc, nums, span


def _march(shapes, mus, h, n_steps):
    fn = jax.vmap(lambda s, m, hh: time_march_kernel(s, m, CONTACTS, LOAD, hh, n_steps=n_steps))
    return fn(_stack(shapes), jnp.asarray(mus), jnp.asarray(h))


@pytest.fixture(scope="module")
def fine():
    """Family x mu plus seeded random shapes, both solvers, time marcher at its finest step."""
    rshapes, rmus = _random_shapes()
    shapes = [jd.family_shape(n) for n, _ in FAMILY_CASES] + rshapes
    mus = [m for _, m in FAMILY_CASES] + rmus
    labels = [f"{n}@{m}" for n, m in FAMILY_CASES] + [f"random{i}" for i in range(len(rshapes))]
    bc, direct, span = _direct(shapes, mus)
    lift = np.asarray(bc.status) == jd.RESULTS.liftoff
    span = np.where(lift | ~(span > 0), 1.0, span)
    # A step incommensurate with the span, so the gross-slip step is not hit exactly by chance.
    h = span / (N_FINE + 0.37)
    tm = _march(shapes, mus, h, n_steps=int(N_FINE * 1.02) + 4)
    return dict(labels=labels, bc=bc, direct=direct, tm=tm, shapes=shapes, mus=mus)


@pytest.mark.slow  # 32 worker-s (run of 2026-11-25)
def test_liftoff_flags_agree(fine):
    lift_d = np.asarray(fine["bc"].status) == jd.RESULTS.liftoff
    lift_t = np.asarray(fine["tm"].status) == jd.RESULTS.liftoff
    assert lift_d[fine["labels"].index("74L@0.7")]  # the paper's real liftoff case
    np.testing.assert_array_equal(lift_t, lift_d, err_msg=str(fine["labels"]))


def test_five_numbers_agree_within_0p2_percent(fine):
    tm, bc = fine["tm"], fine["bc"]
    got = np.array(tm[:5]).T
    want = fine["direct"]
    checked = 0
    for i, label in enumerate(fine["labels"]):
        if int(bc.status[i]) == jd.RESULTS.liftoff:
            continue
        assert int(bc.status[i]) == int(tm.status[i]) == jd.RESULTS.ok, label
        assert int(tm.newton_failures[i]) == 0, label
        for j, name in enumerate(NAMES):
            if name == "k_im_bc" and label.startswith("90R"):
                # 90R's converged cycle is elastic (k_Im = 0): compare on the scale of k_Re.
                assert abs(got[i, j] - want[i, j]) <= 2e-3 * abs(want[i, 3]), (label, name)
            else:
                assert abs(got[i, j] / want[i, j] - 1.0) <= 2e-3, (label, name, got[i, j], want[i, j])
        checked += 1
    assert checked >= 14 + 4  # 14 non-liftoff family cases, most random shapes


def test_energy_identity_of_the_marched_loop(fine):
    """sum_i oint T_i d(slip_i) equals oint M dpsi of the sampled loop (cycle energy balance)."""
    tm = fine["tm"]
    ok = np.asarray(tm.status) != jd.RESULTS.liftoff
    w_c = np.sum(np.asarray(tm.work_contacts), axis=1)[ok]
    w_m = np.asarray(tm.work_moment)[ok]
    scale = np.abs(np.asarray(tm.k_re_bc)[ok]) * np.asarray(tm.psi_bc)[ok] ** 2 * 1e-3
    assert np.all(np.abs(w_c - w_m) <= 1e-8 * scale)
    assert_tree_allclose(np.asarray(tm.k_im_energy)[ok], np.asarray(tm.k_im_bc)[ok],
                         rtol=0, atol=1e-6 * float(np.max(np.abs(np.asarray(tm.k_re_bc)[ok]))))


@pytest.fixture(scope="module")
def coarse(fine):
    """The same designs marched at coarser steps (one compiled program, n_steps = 1100)."""
    bc = fine["bc"]
    span = np.maximum(np.asarray(bc.forward.span), np.asarray(bc.backward.span))
    span = np.where((np.asarray(bc.status) == jd.RESULTS.liftoff) | ~(span > 0), 1.0, span)
    offsets = np.random.default_rng(7).uniform(0.1, 0.9, span.shape[0])
    return {n: _march(fine["shapes"], fine["mus"], span / (n + offsets), n_steps=1100)
            for n in (250, 500, 1000, 2000)}


@pytest.mark.slow  # 12 worker-s (run of 2026-11-25)
def test_error_falls_linearly_with_step(fine, coarse):
    labels = fine["labels"]
    lift = np.asarray(fine["bc"].status) == jd.RESULTS.liftoff
    use = np.array([not lab.startswith("random") for lab in labels]) & ~lift
    is90r = np.array([lab.startswith("90R") for lab in labels])[use]
    direct = fine["direct"][use]
    steps = (250, 500, 1000)
    errs = []
    for n in steps:
        got = np.array(coarse[n][:5]).T[use]
        # Relative errors; k_Im of 90R is ~0, so measure it on the scale of k_Re.
        scale = np.abs(direct)
        scale[is90r, 4] = np.abs(direct[is90r, 3])
        rel = np.abs(got - direct) / scale
        errs.append(rel.mean(axis=0))
    errs = np.array(errs)  # (steps, five numbers), mean over the 14 non-liftoff family cases
    log_h = np.log(1.0 / np.array(steps, float))
    for j in (2, 3, 4):  # psi_BC, k_Re,BC, k_Im,BC
        slope = np.polyfit(log_h, np.log(errs[:, j]), 1)[0]
        assert 0.7 <= slope <= 1.5, (NAMES[j], slope, errs[:, j])
    # k_Re,fs is the slope of the first step: exact once h is below the first tract.
    assert np.all(errs[:, 1] < 1e-10)


@pytest.mark.slow  # 15 worker-s (2026-11-26): the coarse marcher program
def test_too_few_steps_is_flagged_not_wrong(fine, coarse):
    """1100 steps of span/2000 cannot reach gross slip: every non-liftoff design is flagged failed."""
    tm = coarse[2000]
    lift = np.asarray(fine["bc"].status) == jd.RESULTS.liftoff
    status = np.asarray(tm.status)
    assert np.all(status[~lift] == jd.RESULTS.singular) and np.all(status[lift] == jd.RESULTS.liftoff)


@pytest.mark.slow  # 22 worker-s (run of 2026-11-25)
def test_gross_slip_end_is_the_full_slip_statics(fine):
    """60sym and 74R end both halves in full slip: the marched forces at C and F equal the statics."""
    tm = fine["tm"]
    for label in ("60sym@0.5", "74R@0.3", "60sym@0.7"):
        i = fine["labels"].index(label)
        shape, mu = fine["shapes"][i], fine["mus"][i]
        start = jd.blocks.full_slip_state(shape, mu, START_FRICTION_SIGNS)
        mid = jd.blocks.full_slip_state(shape, mu, -START_FRICTION_SIGNS)
        for got, want in ((tm.N_C[i], mid.N), (tm.T_C[i], mid.T), (tm.N_F[i], start.N),
                          (tm.T_F[i], start.T)):
            assert_tree_allclose(got, want, rtol=0, atol=1e-10)


@pytest.mark.parametrize("kwargs, name", [(dict(h=0.0, n_steps=10), "h"), (dict(h=-1.0, n_steps=10), "h"),
                                          (dict(h=1e-3, n_steps=1), "n_steps"),
                                          (dict(h=1e-3, n_steps=10, max_pairs=0), "max_pairs")])
def test_bad_input_raises(kwargs, name):
    with pytest.raises(ValueError, match=name):
        time_march(jd.family_shape("60sym"), 0.5, **kwargs)


def test_bad_mu_raises():
    with pytest.raises(ValueError, match="mu"):
        time_march(jd.family_shape("60sym"), -0.1, h=1e-3, n_steps=10)
