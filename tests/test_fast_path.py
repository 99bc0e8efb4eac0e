"""The batched fast path against the reference path.

Fast: `evaluate_designs`, whose first stage runs one pair of half-cycles of at most
`FIRST_STAGE_TRACTS` tracts and reruns the designs that did not finish at full length, with the
elementwise 3-term dot products (`jaxdamp.linalg.rowdot`) in the tract solve.
Reference: `summary_kernel` at MAX_TRACTS and MAX_PAIRS for every design (one vmap, no stages).
Values to 1e-12 relative (k_Re,BC as in tests/test_batch.py: its breakpoint at x = -1 may differ by
rounding between two compiled programs), flags exactly, and forward-mode gradients to 1e-12.
"""

from functools import lru_cache

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp import batch as B
from jaxdamp.cycle import MAX_PAIRS, MAX_TRACTS
from helpers import assert_leaf_close, assert_tree_allclose
from jaxdamp.linalg import rowdot

EXACT_FIELDS = ("psi_fs", "k_re_fs", "psi_bc", "k_im_bc", "w_R1", "w_L1", "w_L2", "w_M")
FLAGS = ("half_cycles", "status")
HARD = (("90L", 0.5), ("90R", 0.5), ("90R", 0.3), ("74R", 0.7), ("60sym", 0.02), ("74L", 0.05),
        ("45sym", 0.9), ("90L", 0.7))


@lru_cache(maxsize=None)
def designs():
    """1000 random designs (random per-contact stiffness) plus the hard cases."""
    rng = np.random.default_rng(15)
    n = 1000
    fam = [jd.family_shape(s) for s, _ in HARD]
    cols = [np.r_[rng.uniform(35, 90, n), [getattr(s, f) for s in fam]]
            for f in ("theta_l", "theta_r")]
    br = np.r_[rng.uniform(-0.3, 0.4, n), [s.br_over_hr for s in fam]]
    bl = np.r_[rng.uniform(0.6, 0.9, n), [s.bl2_over_hl for s in fam]]
    mu = np.r_[rng.uniform(0.01, 0.9, n), [m for _, m in HARD]]
    contacts = [jd.Contacts(a, b) for a, b in zip(rng.uniform(1e4, 3e4, n + len(HARD)),
                                                   rng.uniform(2e3, 8e3, n + len(HARD)))]
    return B.stack_designs(jd.DamperShape(*cols, br, bl), mu, contacts)


def _reference(design):
    return B.summary_kernel(design, MAX_PAIRS, MAX_TRACTS)


@pytest.mark.slow  # 38 worker-s (run of 2026-11-25)
def test_fast_path_equals_reference_over_1000_designs_and_hard_cases():
    d = designs()
    fast = B.evaluate_designs(d)
    ref = jax.tree_util.tree_map(np.asarray, jax.jit(jax.vmap(_reference))(d))
    for f in FLAGS:
        assert_leaf_close(f, getattr(fast, f), getattr(ref, f))
    for f in EXACT_FIELDS:
        assert_leaf_close(f, getattr(fast, f), getattr(ref, f))
    ok = np.asarray(fast.status) != jd.RESULTS.liftoff
    assert_leaf_close("k_re_bc", fast.k_re_bc[ok], ref.k_re_bc[ok], rtol=1e-6)
    # The set covers what the fast path must hand on: liftoff, a second stage (frozen mechanisms,
    # half-cycles longer than the first stage's tracts) and plain one-pair cycles.
    first = jax.jit(jax.vmap(B.first_stage_summary))(d)
    rerun = B.needs_second_stage(first)
    assert 0.1 < (np.asarray(fast.status) == jd.RESULTS.liftoff).mean() < 0.9
    assert rerun[-len(HARD):].any() and 0 < rerun.mean() < 0.2
    assert (np.asarray(ref.status) == jd.RESULTS.ok).sum() > 300


def test_rowdot_is_a_dot_product():
    rng = np.random.default_rng(0)
    x, y = rng.normal(size=(50, 8, 3)), rng.normal(size=(3, 3))
    got = np.asarray(rowdot(jnp.asarray(x)[..., None, :], jnp.asarray(y)))
    assert_tree_allclose(got, x @ y.T, rtol=1e-14, atol=1e-14)


@pytest.mark.slow  # 86 worker-s (run of 2026-11-25)
def test_fast_path_gradients_equal_reference():
    """Forward-mode derivatives of the five numbers and work factors w.r.t. the whole Design, on
    designs the first stage finishes (so the fast kernel itself is differentiated)."""
    d = designs()
    first = jax.jit(jax.vmap(B.first_stage_summary))(d)
    done = np.nonzero(np.asarray(first.status) == jd.RESULTS.ok)[0]
    idx = np.r_[done[:6], [i for i in done if i >= 1000][:4]]
    sub = B.take(d, idx)

    def jac(fn):
        def one(design):
            f = lambda x: jnp.stack([getattr(fn(x), k) for k in EXACT_FIELDS])  # noqa: E731
            return jax.jacfwd(f)(design)
        return jax.tree_util.tree_map(np.asarray, jax.jit(jax.vmap(one))(sub))

    got, want = jac(B.first_stage_summary), jac(_reference)
    for g, w in zip(jax.tree_util.tree_leaves(got), jax.tree_util.tree_leaves(want)):
        assert np.all(np.isfinite(g))
        assert_leaf_close("jacobian", g, w)
