"""jaxdamp.sequence: k(psi_a) as pieces whose loop corners are affine in psi_a (issue 24), against
the per-amplitude cycles (the reference method: `amplitude_curves`, `amplitude_kernel`).

The full acceptance sweep (five shapes x 3 mu x 2 histories x 200 amplitudes, 500 random designs,
explicit states) is benchmarks/sequence_check.py (results/sequence_check.json); this is a reduced
version."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_kernel
from jaxdamp.curves import broadcast_designs
from jaxdamp.band import admissible_polytope, polytope_vertices
from jaxdamp.sequence import (curve_at, probe_kernel, refit_kernel, sequence_curves,
                              stiffness_curve)

from helpers import assert_tree_allclose

CASES = [("60sym", 0.5), ("74R", 0.7), ("90R", 0.5)]
TOL = 1e-9


def _stack(names, mus):
    shape = jax.tree_util.tree_map(lambda *x: np.array(x, float), *[jd.family_shape(s) for s in names])
    return shape, np.asarray(mus, float)


def _psi_bc(shape, mu):
    s = jd.evaluate_designs(jd.stack_designs(shape, mu))
    return np.asarray(s.psi_bc, float)


def _err(a_re, a_im, b_re, b_im):
    scale = np.max(np.maximum(np.abs(b_re), np.abs(b_im)), axis=-1, keepdims=True)
    return np.max(np.maximum(np.abs(a_re - b_re), np.abs(a_im - b_im)) / scale)


@pytest.mark.slow  # 114 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("initial", ["gross_slip", "assembly"])
def test_sequence_curves_equal_per_amplitude_cycles(initial):
    shape, mu = _stack(*zip(*CASES))
    psi = np.linspace(0.02, 3.0, 200)[None] * _psi_bc(shape, mu)[:, None]
    ref = jd.amplitude_curves(shape, mu, psi, initial=initial)
    seq = sequence_curves(shape, mu, psi, initial=initial)
    assert _err(np.asarray(seq.k_re), np.asarray(seq.k_im), np.asarray(ref.k_re),
                np.asarray(ref.k_im)) <= TOL
    np.testing.assert_array_equal(np.asarray(seq.status), np.asarray(ref.status))
    assert np.all(np.isfinite(np.asarray(seq.k_re))) and np.all(np.isfinite(np.asarray(seq.k_im)))


@pytest.mark.slow  # 83 worker-s (run of 2026-11-25)
def test_free_curve_at_any_amplitude_and_cycles_per_curve():
    """The curve built on [psi_lo, psi_hi] (probes placed by the method, not on the grid)
    evaluated at 200 other amplitudes: every one covered, equal to the cycles, status for status,
    from a handful of cycles."""
    shape, mu = _stack(*zip(*CASES))
    n = len(mu)
    pbc = _psi_bc(shape, mu)
    designs = broadcast_designs((shape, mu, jd.Contacts(), jd.LoadCase()), n, np)
    cur = stiffness_curve(designs, 0.02 * pbc, 3.0 * pbc, initial="gross_slip")
    psi = np.linspace(0.021, 2.99, 200)[None] * pbc[:, None]
    pt = curve_at(cur, jnp.asarray(psi))
    ref = jd.amplitude_curves(shape, mu, psi, initial="gross_slip")
    assert bool(np.all(np.asarray(pt.covered)))
    assert _err(np.asarray(pt.k_re), np.asarray(pt.k_im), np.asarray(ref.k_re),
                np.asarray(ref.k_im)) <= TOL
    np.testing.assert_array_equal(np.asarray(pt.status), np.asarray(ref.status))
    assert int(np.max(cur.cycles)) <= 30  # against 200 cycles per curve amplitude by amplitude


@pytest.mark.slow  # 26 worker-s (run of 2026-11-25)
def test_explicit_initial_states():
    shape1 = jd.family_shape("60sym")
    P, n0, G, h = admissible_polytope(shape1, 0.5)
    V, ok = polytope_vertices(G, h)
    V = np.asarray(V)[np.asarray(ok)]
    w = np.random.default_rng(3).dirichlet(np.full(len(V), 0.5), 3)
    T = w @ V
    N = T @ np.asarray(P).T + np.asarray(n0)
    shape, mu = _stack(["60sym"] * 3, [0.5] * 3)
    designs = broadcast_designs((shape, mu, jd.Contacts(), jd.LoadCase()), 3, np)
    psi = np.linspace(0.05, 2.0, 60)
    cur = stiffness_curve(designs, grid=np.broadcast_to(psi, (3, 60)), initial="explicit",
                          N_init=N, T_init=T)
    pt = curve_at(cur, jnp.asarray(psi))

    @jax.jit
    def ref(n, t):
        run = lambda p: amplitude_kernel(shape1, 0.5, jd.Contacts(), jd.LoadCase(), p, n, t,  # noqa: E731
                                         initial="explicit")
        ac = jax.vmap(run)(jnp.asarray(psi))
        return ac.k_re, ac.k_im, ac.status

    for i in range(3):
        k_re, k_im, st = (np.asarray(x) for x in ref(N[i], T[i]))
        cov = np.asarray(pt.covered[i])
        assert cov.all()
        assert _err(np.asarray(pt.k_re[i]), np.asarray(pt.k_im[i]), k_re, k_im) <= TOL
        np.testing.assert_array_equal(np.asarray(pt.status[i]), st)


@pytest.mark.slow  # 18 worker-s (run of 2026-11-25)
def test_corners_affine_within_a_piece():
    """The structure: within one sequence the loop's corners (tract lengths, moments) are affine in
    psi_a. The forward-mode model of one cycle predicts another cycle's corners in the same piece
    exactly (rounding), here for a microslip amplitude of 60sym from assembly."""
    shape = jd.family_shape("60sym")
    pr = [probe_kernel(shape, 0.5, jd.Contacts(), jd.LoadCase(), p, initial="assembly")
          for p in (1.2, 1.35)]
    assert pr[0].seq_lo < 1.2 < 1.35 < pr[0].seq_hi
    pred = pr[0].corners + 0.15 * pr[0].slopes
    scale = np.max(np.abs(np.asarray(pr[1].corners)), axis=1, keepdims=True)
    assert np.max(np.abs(np.asarray(pred - pr[1].corners)) / scale) < 1e-12


@pytest.mark.slow  # 76 worker-s (run of 2026-11-25)
def test_gradients_psi_and_design_match_finite_differences():
    shape1 = jd.family_shape("60sym")
    shape, mu = _stack(["60sym"], [0.5])
    designs = broadcast_designs((shape, mu, jd.Contacts(), jd.LoadCase()), 1, np)
    cur = stiffness_curve(designs, 0.1, 3.0, initial="gross_slip")
    one = jax.tree_util.tree_map(lambda x: x[0], cur)
    psi0 = jnp.asarray(1.2)  # microslip, away from the breaks

    @jax.jit  # one program, not the kernel's loops op by op
    def k_ref(p, m):
        ac = amplitude_kernel(shape1, jnp.asarray(m, float), jd.Contacts(), jd.LoadCase(),
                              jnp.asarray(p, float))
        return jnp.stack([ac.k_re, ac.k_im])

    d_psi = jax.jit(jax.jacfwd(lambda p: jnp.stack(one.at(p)[:2])))(psi0)
    h = 1e-6
    fd = (k_ref(psi0 + h, 0.5) - k_ref(psi0 - h, 0.5)) / (2 * h)
    assert_tree_allclose(d_psi, fd, rtol=1e-5, atol=1e-3)

    def k_design(m):
        c = refit_kernel(one, shape1, m, jd.Contacts(), jd.LoadCase())
        return jnp.stack(c.at(psi0)[:2])

    assert_tree_allclose(k_design(0.5), k_ref(psi0, 0.5), rtol=1e-12, atol=0.0)
    g = jax.jit(jax.jacrev(k_design))(0.5)
    fd = (k_ref(psi0, 0.5 + h) - k_ref(psi0, 0.5 - h)) / (2 * h)
    assert np.all(np.isfinite(np.asarray(g)))
    assert_tree_allclose(g, fd, rtol=1e-5, atol=1e-3)


@pytest.mark.parametrize("change,says", [
    ({"mu": 0.0}, "mu must be in (0, 5]"),
    ({"kn": -1.0}, "kn must be in (0, inf) N/mm"),
    ({"psi_hi": 2e4}, "psi_hi must be in (0, 10000] mrad"),
    ({"initial": "sideways"}, "initial must be one of"),
])
def test_stiffness_curve_checks_its_inputs(change, says):
    """The exported builder checks every input before any work (one-line ValueError naming the
    parameter and its range); stiffness_curve_unchecked is the unchecked one."""
    shape, mu = _stack(["60sym"], [change.get("mu", 0.5)])
    contacts = jd.Contacts(np.array([change.get("kn", 2e4)]), np.array([3.5e3]))
    load = jd.LoadCase(np.array([1000.0]), np.array([100.0]), np.array([0.0]))
    with pytest.raises(ValueError) as e:
        stiffness_curve((shape, mu, contacts, load), 0.1, change.get("psi_hi", 3.0),
                        initial=change.get("initial", "gross_slip"))
    assert str(e.value).startswith(says) and "\n" not in str(e.value)



def test_stiffness_curve_refuses_an_interval_or_grid_the_wrong_way_round():
    shape, mu = _stack(["60sym"], [0.5])
    design = (shape, mu, jd.Contacts(np.array([2e4]), np.array([3.5e3])),
              jd.LoadCase(np.array([1000.0]), np.array([100.0]), np.array([0.0])))
    with pytest.raises(ValueError, match=r"^psi_hi must be >= psi_lo \(mrad\); got psi_lo 5.0, psi_hi 1.0$"):
        stiffness_curve(design, 5.0, 1.0)
    with pytest.raises(ValueError, match=r"^grid must be ascending along its last axis \(mrad\)$"):
        stiffness_curve(design, grid=np.array([[3.0, 1.0]]))
    # Not a batch, a count that is text, a start for another history (was ignored)
    with pytest.raises(ValueError, match=r"^designs must be a batch of designs"):
        stiffness_curve("60sym", 1.0, 5.0)
    with pytest.raises(ValueError, match=r"^max_pairs must be an integer in \[1, inf\)"):
        stiffness_curve(design, 1.0, 5.0, max_pairs="8")
    with pytest.raises(ValueError, match=r'^N_init and T_init are for initial="explicit"'):
        stiffness_curve(design, 1.0, 5.0, N_init=np.ones((1, 3)), T_init=np.zeros((1, 3)))
