"""The band of responses over the statically admissible initial states (jaxdamp.band)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_cycle, check_admissible
from jaxdamp.band import admissible_polytope, amplitude_band, polytope_vertices

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(17900.0, 3580.0)


def test_polytope_vertices_are_admissible_and_include_full_slip():
    shape, mu = jd.family_shape("60sym"), 0.5
    P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
    V, ok = (np.asarray(v) for v in polytope_vertices(G, h))
    assert ok.sum() >= 8
    for T in V[ok]:
        res, cone, n_min = check_admissible(shape, mu, P @ T + n0, T)
        assert float(res) < 1e-12 and float(cone) < 1e-12 and float(n_min) > -1e-12
    # Both full-slip states of the Base-Cycle (all three contacts on their limits) are vertices.
    for signs in (jd.statics.START_FRICTION_SIGNS, -jd.statics.START_FRICTION_SIGNS):
        st = jd.blocks.full_slip_state(shape, mu, signs)
        assert np.min(np.max(np.abs(V[ok] - np.asarray(st.T)), axis=1)) < 1e-12


@pytest.mark.slow  # 43 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name,mu,psi", [("60sym", 0.5, 1.2), ("74R", 0.7, 1.5)])
def test_band_contains_named_states(name, mu, psi):
    shape = jd.family_shape(name)
    band = amplitude_band(shape, mu, psi, CONTACTS)
    assert band.status == 0 and band.n_valid > 32 and np.all(band.confirmed)
    lo_re, hi_re, lo_im, hi_im = band.bounds
    assert hi_im > lo_im + 100.0  # a real band in the microslip range
    for initial in ("gross_slip", "assembly"):
        ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
        slack = 1e-9 * abs(float(ac.k_re))
        assert lo_re - slack <= float(ac.k_re) <= hi_re + slack
        assert lo_im - slack <= float(ac.k_im) <= hi_im + slack
    # The states reported for the bounds give those bounds.
    for j, (N, T) in enumerate(zip(band.N, band.T)):
        ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=(N, T))
        assert [float(ac.k_re), float(ac.k_re), float(ac.k_im), float(ac.k_im)][j] == \
            pytest.approx(band.bounds[j], rel=1e-12, abs=1e-9)


@pytest.mark.slow  # 28 worker-s (run of 2026-11-25)
def test_band_closes_above_psi_bc():
    shape, mu = jd.family_shape("60sym"), 0.5
    n = jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS))
    psi = 1.4 * float(n.psi_bc)
    band = amplitude_band(shape, mu, psi, CONTACTS, n_samples=64, refine=False)
    ref = np.asarray(jd.complex_stiffness(jd.base_cycle(shape, mu, CONTACTS), psi,
                                          method="interpolated"))
    assert_tree_allclose(band.bounds, np.array([ref[0], ref[0], ref[1], ref[1]]), rtol=1e-9, atol=0.0)


def test_self_locked_state_keeps_the_band_open_above_psi_bc():
    """74R at mu 0.7 self-locks: the full-slip state with friction signs (+, +, -) is admissible
    with contact forces of ~24 F_D. From it the cycle at 3.5 mrad (> psi_BC = 3.29) settles, after
    a transient, on an elastic cycle, so the band's k_Im reaches 0 above psi_BC. The time marcher
    confirms it (200 pairs without acceleration; the direct method needs 3 with Aitken's)."""
    from jaxdamp.status import RESULTS
    from jaxdamp.baselines.timemarch import march_amplitude

    shape, mu, psi = jd.family_shape("74R"), 0.7, 3.5
    assert float(jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS)).psi_bc) < psi
    st = jd.blocks.full_slip_state(shape, mu, jnp.array([1.0, 1.0, -1.0]))
    N, T = np.asarray(st.N), np.asarray(st.T)
    assert np.min(N) > 1.0 and float(check_admissible(shape, mu, N, T)[0]) < 1e-12
    ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=(N, T))
    assert RESULTS.name_of(ac.status) == "shakedown" and int(ac.cycles) == 3
    tm = march_amplitude(shape, mu, psi, CONTACTS, initial=(N, T), n_steps=1000, max_pairs=200)
    assert float(np.asarray(tm.closure)[-1]) < 1e-9
    assert_tree_allclose(tm.N_start, ac.N_start, rtol=1e-7, atol=1e-9)
    assert float(tm.k_re) == pytest.approx(float(ac.k_re), rel=1e-9)
    assert abs(float(tm.k_im)) < 1e-9 * float(ac.k_re)


def _uniform_admissible_states(shape, mu, n, seed=1, enlarge=0.0):
    """n initial states uniform in the admissible set: numpy's generator, rejection from the
    vertices' axis-aligned bounding box, enlarged by `enlarge` times its size on every side
    (independent of the band's own sampling)."""
    P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
    V, ok = (np.asarray(v) for v in polytope_vertices(G, h))
    lo, hi = V[ok].min(0), V[ok].max(0)
    size = np.max(hi - lo)
    lo, hi = lo - enlarge * size, hi + enlarge * size
    rng = np.random.default_rng(seed)
    out = np.zeros((0, 3))
    while len(out) < n:
        X = rng.uniform(lo, hi, (20 * n, 3))
        out = np.concatenate([out, X[np.all(X @ G.T + h >= 0.0, axis=1)]])
    return P, n0, out[:n]


@jax.jit
def _k_of_states_kernel(shape, mu, psi, P, n0, T):
    """k of every initial state T (n, 3) by the plain cycle: one program for every case (shape,
    mu and psi are arguments, not constants of a new closure per case)."""
    def one(t):
        ac = jd.amplitude_kernel(shape, mu, CONTACTS, jd.LoadCase(), psi, P @ t + n0, t,
                                 initial="explicit")
        return ac.k_re, ac.k_im, ac.status
    return jax.vmap(one)(T)


def _k_of_states(shape, mu, psi, P, n0, T):
    args = (jnp.asarray(v, float) for v in (mu, psi, P, n0, T))
    return (np.asarray(v) for v in _k_of_states_kernel(shape, *args))


@pytest.mark.slow  # 11 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name,mu,psi,enlarge", [("74L", 0.5, 1.2, 0.0), ("74L", 0.3, 1.0, 0.0),
                                                ("90L", 0.5, 2.0828537, 4.0)])
def test_band_is_never_narrower_than_ten_thousand_random_states(name, mu, psi, enlarge):
    """Issue 24's criterion: the band holds k of 10^4 uniformly drawn admissible states. 74L at
    mu 0.5, 1.2 mrad: its k_Re minimum sits in a small sequence region next to a plateau (about 0.1 %
    of the states), which the trust region reaches by crossing from sequence to sequence. 90L at
    mu 0.5 self-locks (the admissible set is unbounded): at psi_BC, 17 % of the states in a box 9
    times the vertices' own stick (k_Re,fs, k_Im = 0), which the vertices' hull never holds."""
    shape = jd.family_shape(name)
    band = amplitude_band(shape, mu, psi, CONTACTS)
    P, n0, T = _uniform_admissible_states(shape, mu, 10_000, enlarge=enlarge)
    k_re, k_im, status = _k_of_states(shape, mu, psi, P, n0, T)
    valid = np.asarray(jd.RESULTS.valid(status))
    assert band.status == 0 and valid.sum() > 1000 and np.all(band.confirmed)
    lo_re, hi_re, lo_im, hi_im = band.bounds
    tol = 1e-9 * max(abs(hi_re), abs(hi_im))
    assert lo_re <= k_re[valid].min() + tol and hi_re >= k_re[valid].max() - tol
    assert lo_im <= k_im[valid].min() + tol and hi_im >= k_im[valid].max() - tol


@pytest.mark.slow  # 70 worker-s (run of 2026-11-25)
def test_band_grid_is_the_bands_one_by_one():
    """One program for a grid gives each amplitude's band, also where the grid spans two of the
    CPU's chunks (band.CPU_CHUNK amplitudes each, the last one padded). To 1e-9 (the band's stated
    precision, band.CONFIRM_TOL), not to rounding: k_Re is not quadratic within a sequence, so
    the six trust-region steps end within ~1e-10 of its optimum, by paths that batching's
    different rounding can move."""
    from jaxdamp.band import CPU_CHUNK

    shape, mu, grid = jd.family_shape("60sym"), 0.5, [0.8, 1.2, 1.6, 2.0]
    assert CPU_CHUNK < len(grid) < 2 * CPU_CHUNK
    bands = jd.amplitude_band(shape, mu, grid, CONTACTS)
    for psi, b in zip(grid, bands):
        one = amplitude_band(shape, mu, psi, CONTACTS)
        assert b.psi_a == psi and b.status == one.status
        assert_tree_allclose(b.bounds, one.bounds, rtol=1e-9, atol=1e-9)


@pytest.mark.slow  # 42 worker-s (run of 2026-11-25)
def test_k_im_is_quadratic_in_the_initial_state_within_one_sequence():
    """The structure the band uses (issue 24): along a line of initial states on which every
    half runs the same tract sequence, the steady cycle's start state is affine and the dissipated
    energy (k_Im) quadratic. Third differences of k_Im and second differences of the steady start
    state vanish to rounding."""
    shape, mu, psi = jd.family_shape("74L"), 0.3, 1.0
    P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
    V, ok = (np.asarray(v) for v in polytope_vertices(G, h))
    centre = V[ok].mean(axis=0)
    direction = np.array([0.6, -0.3, 0.74]) / np.linalg.norm([0.6, -0.3, 0.74])
    checked = 0
    for t0 in np.linspace(-0.05, 0.05, 6):
        ts = t0 + np.arange(5) * 2e-4
        cycles = [jd.amplitude_kernel(shape, mu, CONTACTS, jd.LoadCase(), jnp.asarray(psi),
                                      P @ (centre + t * direction) + n0, centre + t * direction,
                                      initial="explicit") for t in ts]
        patterns = {tuple(np.asarray(c.history_dv > 0).ravel()) for c in cycles}
        if len(patterns) != 1 or not all(bool(jd.RESULTS.valid(c.status)) for c in cycles):
            continue  # a sequence change inside this stencil
        k_im = np.array([float(c.k_im) for c in cycles])
        start = np.array([np.concatenate([np.asarray(c.N_start), np.asarray(c.T_start)]) for c in cycles])
        assert abs(np.diff(k_im, 3)).max() <= 1e-9 * max(abs(k_im).max(), 1.0)
        assert abs(np.diff(start, 2, axis=0)).max() <= 1e-11
        checked += 1
    assert checked >= 3


@pytest.mark.slow  # 71 worker-s (run of 2026-11-25)
def test_no_admissible_state_with_a_valid_cycle_says_why():
    """theta_L = theta_R = 90, b_R/h_R = -0.5: the damper's statics are singular, so no state is
    admissible (tests/test_status_paths.py drives the same design through every path). No bound
    exists: the band says singular, with zeros, nothing confirmed and None by name."""
    band = amplitude_band(jd.DamperShape(90.0, 90.0, -0.5), 0.5, 1.5, CONTACTS)
    assert jd.RESULTS.name_of(band.status) == "singular" and band.n_valid == 0
    assert np.all(band.bounds == 0.0) and not np.any(band.confirmed)
    assert all(v is None for v in band.as_dict().values())


@pytest.mark.slow  # 82 worker-s (run of 2026-11-25)
def test_a_self_locking_wedge_has_an_unbounded_admissible_set_whose_far_states_stick():
    """90L at mu 0.5: the recession cone is not empty (so the vertices' hull is not the admissible
    set). Far along a ray every contact sticks: the cycle is the stuck line, k_Re = k_Re,fs of the
    Base-Cycle (a physics identity) and k_Im = 0, and the band reaches both."""
    from jaxdamp.band import recession_rays

    shape, mu = jd.family_shape("90L"), 0.5
    P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
    R, ok = (np.asarray(v) for v in recession_rays(G))
    assert ok.any() and np.all(R[ok] @ G.T >= -1e-12)
    assert not np.any(recession_rays(admissible_polytope(shape, 0.3)[2])[1])
    fn = jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS))
    psi = float(fn.psi_bc)
    V, vok = (np.asarray(v) for v in polytope_vertices(G, h))
    T = V[vok].mean(axis=0) + 50.0 * R[ok][0]
    ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=(P @ T + n0, T))
    assert jd.RESULTS.name_of(ac.status) == "shakedown"
    assert float(ac.k_re) == pytest.approx(float(fn.k_re_fs), rel=1e-9)
    band = amplitude_band(shape, mu, psi, CONTACTS)
    assert band.bounds[1] == pytest.approx(float(fn.k_re_fs), rel=1e-9)
    assert abs(band.bounds[2]) <= 1e-9 * float(fn.k_re_fs)


def test_sparse_weights_are_convex_exchangeable_and_as_sparse_as_dirichlet():
    """The samples' combination weights: non-negative, summing to 1 over the masked slots and 0
    elsewhere (all zeros with no slot), each slot 1/m on average (exchangeable), and at the
    alphas the band uses as concentrated as Dirichlet(alpha) (numpy's sampler, the reference):
    the mean largest of 10 weights within 0.04 of Dirichlet's (0.59 at alpha 0.15, 0.38 at 0.5)."""
    from jaxdamp.admissible import sparse_weights

    mask = jnp.asarray([True] * 10 + [False] * 3)
    key = jax.random.PRNGKey(7)
    for alpha in (0.15, 0.5):
        w = np.asarray(sparse_weights(key, alpha, mask, 4000))
        assert np.all(w >= 0.0) and np.all(w[:, 10:] == 0.0)
        assert_tree_allclose(w.sum(axis=1), np.ones(4000), rtol=0.0, atol=1e-12)
        assert_tree_allclose(w[:, :10].mean(axis=0), np.full(10, 0.1), rtol=0.0, atol=0.02)
        ref = np.random.default_rng(1).dirichlet(np.full(10, alpha), 40000)
        assert abs(w.max(axis=1).mean() - ref.max(axis=1).mean()) < 0.04
    assert np.all(np.asarray(sparse_weights(key, 0.15, jnp.zeros(4, bool), 3)) == 0.0)


def test_band_refuses_a_refine_that_is_not_a_bool_and_a_bad_seed():
    """"no" was taken as True; a text seed failed inside jax.random."""
    shape = jd.family_shape("60sym")
    with pytest.raises(ValueError, match=r"^refine must be True or False; got 'no'$"):
        amplitude_band(shape, 0.5, 1.0, refine="no")
    for seed in ("a", -1, 1.5):
        with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, inf\)"):
            amplitude_band(shape, 0.5, 1.0, seed=seed)
