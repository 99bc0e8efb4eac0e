"""AD sensitivities (jaxdamp.gradients) against float64 central differences, identities, and NaN scans.

References are independent of AD: central differences of the forward solver (away from transition-
sequence switches), one-sided differences at a switch, and the scaling law psi ~ F_D/k (Euler's
theorem for homogeneous functions). Every AD program is compiled once (module-level jit) and reused.
"""

from functools import lru_cache

import jax
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose, fd_jvp
from jaxdamp import gradients as G

FIVE = jd.FiveNumbers._fields[:5]
OUTPUTS = FIVE + ("k_im_at",)
P = G.PARAMETERS
REF_K = (jd.REFERENCE_KN, jd.REFERENCE_KT)


def design(x):
    return jd.DamperShape(*x[:4]), x[4], jd.Contacts(x[5], x[6])


def vector(name, mu, kn=REF_K[0], kt=REF_K[1]):
    s = jd.family_shape(name)
    return np.array([s.theta_l, s.theta_r, s.br_over_hr, s.bl2_over_hl, mu, kn, kt], float)


def signature(x):
    """The transition sequence: states of the active tracts, which half is longer (ties count as
    equal), the number of half-cycles and the status. Equal signatures at x +- h mean no switch."""
    bc = jd.base_cycle(*design(x))
    sig = [np.where(np.asarray(h.active)[:, None], np.asarray(h.state), -1)
           for h in (bc.forward, bc.backward)]
    f, b = float(bc.forward.span), float(bc.backward.span)
    longer = 0 if abs(f - b) <= 1e-9 * max(f, b) else int(np.sign(f - b))
    sig.append(np.array([longer, int(bc.half_cycles), int(bc.status)]))
    return sig


def same_sequence(a, b):
    return all(np.array_equal(u, v) for u, v in zip(a, b))


def values(x, psi_a):
    out, _ = G.evaluate(*design(x), psi_a_mrad=psi_a)
    return np.array(out, float)


def ad_matrix(x, psi_a, mode):
    """(6 outputs, 7 variables) from the public API."""
    jac = G.five_numbers_jacobian(*design(x), mode=mode)
    k = G.k_im_gradient_at(psi_a, *design(x), mode=mode)
    rows = [getattr(jac.d, o) for o in FIVE] + [k.d]
    m = np.array([[float(G.by_name(r)[p]) for p in P] for r in rows])
    assert jd.RESULTS.name_of(jac.status) == "ok"
    return m


def scales(x):
    """Variable magnitudes: steps are 1e-6 of these (b_R/h_R may be 0, so at least 0.1)."""
    s = np.abs(np.asarray(x, float)).copy()
    s[2] = max(s[2], 0.1)
    return s


@lru_cache(maxsize=None)
def central_differences(key):
    """Central differences of the six outputs and, per variable, whether x +- h keep the sequence."""
    x, psi_a = np.array(key[0]), key[1]
    sc = scales(x)
    fd = np.zeros((len(OUTPUTS), len(P)))
    smooth = np.zeros(len(P), bool)
    s0 = signature(x)
    for j in range(len(P)):
        unit = np.eye(len(P))[j]
        h = 1e-6 * sc[j]
        fd[:, j] = fd_jvp(lambda z: values(z, psi_a), x, unit, h=h)
        smooth[j] = (same_sequence(signature(x + h * unit), s0)
                     and same_sequence(signature(x - h * unit), s0))
    return fd, smooth


@lru_cache(maxsize=None)
def _random_points(count, seed=20240611):
    """Random designs that work as dampers (no liftoff, converged) and sit away from every switch."""
    rng = np.random.default_rng(seed)
    pts = []
    while len(pts) < count:
        x = np.array([rng.uniform(40, 85), rng.uniform(40, 85), rng.uniform(-0.2, 0.3),
                      rng.uniform(0.6, 0.9), rng.uniform(0.2, 0.8), rng.uniform(1e4, 3e4),
                      rng.uniform(2e3, 8e3)])
        bc = jd.base_cycle(*design(x))
        if jd.RESULTS.name_of(bc.status) != "ok":
            continue
        pts.append(x)
    return pts


def _amplitude(x, k):
    """Amplitude for k_Im(psi_a): above psi_BC (exact harmonic) or inside the microslip range."""
    v = values(x, 0.0)
    psi_fs, psi_bc = v[0], v[2]
    return float(1.4 * psi_bc) if k % 2 == 0 else float(0.5 * (psi_fs + psi_bc))


PAPER_POINTS = {f"{name}-mu{mu}": (name, mu) for name in ("60sym", "74R") for mu in (0.7, 0.5, 0.3)}
N_RANDOM = 4
POINT_IDS = list(PAPER_POINTS) + [f"random{k}" for k in range(N_RANDOM)]


@lru_cache(maxsize=None)
def point(pid):
    """Design vector of a test point (generated lazily: nothing is computed at collection)."""
    if pid in PAPER_POINTS:
        return vector(*PAPER_POINTS[pid])
    return _random_points(N_RANDOM)[int(pid[len("random"):])]


@pytest.mark.parametrize("mode", G.MODES)
@pytest.mark.parametrize("pid", POINT_IDS)
def test_ad_matches_central_differences(pid, mode):
    x = point(pid)
    psi_a = _amplitude(x, POINT_IDS.index(pid))
    fd, smooth = central_differences((tuple(x), psi_a))
    # Steps that cross a switch do not measure a derivative; these points are chosen away from them.
    assert smooth.sum() >= 6, dict(zip(P, smooth))
    ad = ad_matrix(x, psi_a, mode)
    assert np.all(np.isfinite(ad))
    sc = scales(x)
    a, b = (ad * sc)[:, smooth], (fd * sc)[:, smooth]  # change per relative change of each variable
    row = np.abs(b).max(axis=1, keepdims=True)
    assert np.all(row > 0)
    # 1e-5 relative, elementwise, with the row's largest sensitivity as the floor for entries that
    # vanish (e.g. d k_Re,fs / d mu = 0 where the first tract is all stick).
    err = np.abs(a - b) / (np.abs(b) + row)
    assert err.max() <= 1e-5, (pid, mode, err.max())


@pytest.mark.parametrize("mode", G.MODES)
def test_forward_and_reverse_mode_agree(mode):
    x = point("74R-mu0.5")
    other = "rev" if mode == "fwd" else "fwd"
    assert_tree_allclose(ad_matrix(x, 3.0, mode), ad_matrix(x, 3.0, other), rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize("name,mu", [("60sym", 0.5), ("74R", 0.7), ("90L", 0.3)])
def test_stiffness_scaling_law(name, mu):
    """psi scales with F_D/k at fixed kt/kn and k_Re, k_Im with k: Euler's theorem gives
    kn d/dkn + kt d/dkt = -psi for angles and +k for stiffnesses."""
    jac = G.five_numbers_jacobian(jd.family_shape(name), mu, jd.Contacts(*REF_K))
    for field, degree in (("psi_fs", -1), ("psi_bc", -1), ("k_re_fs", 1), ("k_re_bc", 1),
                          ("k_im_bc", 1)):
        d = getattr(jac.d, field)
        euler = REF_K[0] * float(d.contacts.kn) + REF_K[1] * float(d.contacts.kt)
        value = float(getattr(jac.values, field))
        assert euler == pytest.approx(degree * value, rel=1e-8, abs=1e-9 * abs(value) + 1e-12), field


def test_per_contact_stiffness_gradients_match_central_differences():
    x = point("60sym-mu0.7")
    shape, mu, _ = design(x)
    kn, kt = np.full(3, REF_K[0]), np.full(3, REF_K[1])
    split = G.five_numbers_jacobian(shape, mu, jd.Contacts(kn, kt))
    shared = G.five_numbers_jacobian(shape, mu, jd.Contacts(*REF_K))
    for name, base in (("kn", kn), ("kt", kt)):
        fd = np.zeros((len(FIVE), 3))
        for i in range(3):
            e = np.zeros(3)
            e[i] = 1e-6 * base[i]
            c = {name: base + e}
            plus = G.evaluate(shape, mu, jd.Contacts(**{"kn": kn, "kt": kt, **c}))[0]
            c = {name: base - e}
            minus = G.evaluate(shape, mu, jd.Contacts(**{"kn": kn, "kt": kt, **c}))[0]
            fd[:, i] = (np.array(plus[:5]) - np.array(minus[:5])) / (2 * e[i])
        ad = np.array([np.asarray(G.by_name(getattr(split.d, f))[name]) for f in FIVE])
        assert ad.shape == (len(FIVE), 3)
        row = np.abs(fd * base).max(axis=1, keepdims=True)
        assert np.max(np.abs(ad - fd) * base / (np.abs(fd) * base + row)) <= 1e-5, name
        # A shared stiffness moves all three contacts: its derivative is the sum.
        total = np.array([float(G.by_name(getattr(shared.d, f))[name]) for f in FIVE])
        assert_tree_allclose(ad.sum(axis=1), total, rtol=1e-12, atol=1e-15)


# ------------------------------------------------------------------ at a transition-sequence switch
@lru_cache(maxsize=None)
def mu_switch_74R():
    """Bisect mu in [0.3, 0.5] for 74R, where L1's back-slide in tract 0-A appears (Table 8 vs the
    mu = 0.3 column): the last mu with the old sequence and the first with the new one."""
    base = vector("74R", 0.3)
    lo, hi = 0.3, 0.5
    s_lo = signature(base)
    assert not same_sequence(signature(np.r_[base[:4], hi, base[5:]]), s_lo)
    while hi - lo > 4 * np.spacing(hi):
        mid = 0.5 * (lo + hi)
        if same_sequence(signature(np.r_[base[:4], mid, base[5:]]), s_lo):
            lo = mid
        else:
            hi = mid
    return lo, hi


def _one_sided(x, j, h, side):
    """Second-order one-sided difference along variable j (points only on one side of x)."""
    e = np.zeros(len(P))
    e[j] = side * h
    f0, f1, f2 = values(x, 1.0), values(x + e, 1.0), values(x + 2 * e, 1.0)
    return (-3 * f0 + 4 * f1 - f2) / (2 * side * h)


SWITCH_CASES = [("fwd", "lo"), ("fwd", "hi"), ("rev", "lo"), ("rev", "hi")]


@pytest.mark.parametrize("mode,side", SWITCH_CASES)
def test_at_a_switch_gradients_are_finite_and_bracketed(mode, side):
    lo, hi = mu_switch_74R()
    mu0 = lo if side == "lo" else hi
    x = np.r_[vector("74R", 0.3)[:4], mu0, REF_K]
    ad = ad_matrix(x, 1.0, mode)[:, P.index("mu")]
    assert np.all(np.isfinite(ad))
    # On the side where the new tract exists, its length grows like (mu - mu*) and, sitting at
    # tau ~ 0 of the harmonic integrals, it contributes ~ length**1.5 to k_Re,BC: one-sided
    # differences converge only like h**0.5 there, hence a small step.
    h = 1e-8
    left = _one_sided(x, P.index("mu"), h, -1.0)
    right = _one_sided(x, P.index("mu"), h, +1.0)
    # The two sides really differ (a kink), and the outputs are continuous across the switch.
    assert np.max(np.abs(left - right) / (np.abs(left) + np.abs(right) + 1e-300)) > 1e-2
    e = np.zeros(len(P))
    e[P.index("mu")] = 1e-6
    jump = np.abs(values(x + e, 1.0) - values(x - e, 1.0))
    assert np.all(jump <= 1.01e-6 * (np.abs(left) + np.abs(right)) + 1e-12)
    tol = 1e-5 * np.maximum(np.abs(left), np.abs(right))
    assert np.all(ad >= np.minimum(left, right) - tol), (ad, left, right)
    assert np.all(ad <= np.maximum(left, right) + tol), (ad, left, right)


def test_reverse_mode_converges_exactly_at_a_switch():
    # 74R with kn, kt = 17900, 3600 N/mm: mu found by bisection at the switch where L1's back-slide in
    # 0-A appears. The jit-compiled forward program converges here; check the reverse-mode one.
    shape, mu = jd.family_shape("74R"), 0.4811807371361943
    jac = G.five_numbers_jacobian(shape, mu, jd.Contacts(17900.0, 3600.0), mode="rev")
    assert jd.RESULTS.name_of(jac.status) == "ok"
    assert float(jac.d.psi_bc.mu) > 0.0


# ------------------------------------------------------------------ no NaN anywhere
def random_designs(n, seed):
    rng = np.random.default_rng(seed)
    return [rng.uniform(35, 90, n), rng.uniform(35, 90, n), rng.uniform(-0.3, 0.4, n),
            rng.uniform(0.6, 0.9, n), rng.uniform(0.1, 0.9, n), rng.uniform(1e4, 3e4, n),
            rng.uniform(2e3, 8e3, n)]


def as_designs(columns):
    """A batched Design from the seven columns of design vectors."""
    return jd.stack_designs(jd.DamperShape(*columns[:4]), columns[4],
                            [jd.Contacts(kn, kt) for kn, kt in zip(columns[5], columns[6])])


EDGE_CASES = [  # vertical flanks, both vertical, liftoff, zero-length tracts (90L), b_R = 0, tiny mu
    (90.0, 40.9, 0.15, 0.85, 0.5), (40.9, 90.0, 0.0, 0.8, 0.7), (90.0, 90.0, 0.0, 0.8, 0.5),
    (73.9, 49.1, 0.16, 0.8, 0.7), (45.0, 45.0, -0.2, 0.8, 0.7), (60.0, 60.0, 0.14, 0.8, 0.1),
    (35.0, 35.0, 0.4, 0.8, 0.9), (90.0, 35.0, -0.3, 0.6, 0.9), (35.0, 90.0, 0.4, 0.9, 0.1),
]


@pytest.mark.slow  # 42 worker-s (run of 2026-11-25)
def test_no_nan_in_forward_gradients_over_10000_random_designs():
    n = 10_000
    dv = random_designs(n, seed=7)
    dv = as_designs([np.concatenate([v, np.array([c[k] if k < 5 else REF_K[k - 5]
                                                  for c in EDGE_CASES])])
                     for k, v in enumerate(dv)])
    jac, (vals, status) = G.batch_jacobian(dv, psi_a=2.0, mode="fwd")
    for leaf in jax.tree_util.tree_leaves((jac, vals)):
        assert np.all(np.isfinite(np.asarray(leaf)))
    status = np.asarray(status)
    # The sample spans working dampers and liftoff (a status, not NaN); every cycle closed, lifted
    # off or failed.
    assert 0.1 < (status == jd.RESULTS.liftoff).mean() < 0.9
    assert np.all(status != jd.RESULTS.not_converged)


def test_no_nan_in_reverse_gradients_random_and_edge_cases():
    dv = random_designs(150, seed=8)
    points = [tuple(float(v[i]) for v in dv) for i in range(150)]
    points += [c + REF_K for c in EDGE_CASES]
    lifted = 0
    for x in points:
        jac = G.five_numbers_jacobian(*design(np.array(x)), mode="rev")
        for leaf in jax.tree_util.tree_leaves((jac.d, jac.values)):
            assert np.isfinite(float(leaf)), x
        lifted += jd.RESULTS.name_of(jac.status) == "liftoff"
    assert 0 < lifted < len(points)


def test_liftoff_is_flagged_with_finite_gradients():
    jac = G.five_numbers_jacobian(jd.family_shape("74L"), 0.7, jd.Contacts(*REF_K))
    assert jd.RESULTS.name_of(jac.status) == "liftoff"
    assert all(np.isfinite(float(v)) for v in jax.tree_util.tree_leaves(jac.d))


# ------------------------------------------------------------------ API errors and the CLI
def test_bad_inputs_raise_value_error_naming_the_parameter():
    s = jd.family_shape("60sym")
    with pytest.raises(ValueError, match="mode"):
        G.five_numbers_jacobian(s, 0.5, mode="central")
    with pytest.raises(ValueError, match="mu"):
        G.five_numbers_jacobian(s, -0.1)
    with pytest.raises(ValueError, match="theta_l"):
        G.five_numbers_jacobian(s._replace(theta_l=95.0), 0.5)
    with pytest.raises(ValueError, match="kt"):
        G.k_im_gradient_at(1.0, s, 0.5, jd.Contacts(1e4, -1.0))
    with pytest.raises(ValueError, match="psi_a"):
        G.k_im_gradient_at(-1.0, s, 0.5)
