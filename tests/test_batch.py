"""Batched and sharded evaluation (jaxdamp.batch): vmap equals a Python loop, no NaN over 10,000
random designs, two-device sharding (in a subprocess), sweeps against design-by-design calls, CLI.

k_Re,BC is compared separately (test_k_re_bc_matches_loop): its closed-form harmonic evaluates
sqrt(1 - x^2) at a breakpoint that lands within rounding of x = -1, so two compiled programs can
differ there by ~1e-7 relative (reported to the lead with a fix); every other number is held to 1e-12.
"""

import json
import os
import subprocess
import sys
import textwrap
from functools import lru_cache

import jax
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_leaf_close, assert_tree_allclose, count_compiles
from jaxdamp import batch as B

EXACT_FIELDS = ("psi_fs", "k_re_fs", "psi_bc", "k_im_bc", "w_R1", "w_L1", "w_L2", "w_M")
FLAGS = ("half_cycles", "status")


def random_designs(n, seed, per_design_contacts=True):
    rng = np.random.default_rng(seed)
    shape = jd.DamperShape(rng.uniform(35, 90, n), rng.uniform(35, 90, n), rng.uniform(-0.3, 0.4, n),
                           rng.uniform(0.6, 0.9, n))
    mu = rng.uniform(0.1, 0.9, n)
    contacts = ([jd.Contacts(a, b) for a, b in zip(rng.uniform(1e4, 3e4, n), rng.uniform(2e3, 8e3, n))]
                if per_design_contacts else jd.Contacts())
    return shape, mu, contacts


def with_family(shape, mu):
    """Append the paper's shapes at mu = 0.3, 0.5, 0.7 (vertical flanks need the second stage)."""
    fam = [jd.family_shape(n) for n in ("90L", "74L", "60sym", "74R", "90R", "45sym")]
    extra = [(s, m) for s in fam for m in (0.3, 0.5, 0.7)]
    shape = jd.DamperShape(*(np.concatenate([np.asarray(v), [getattr(s, f) for s, _ in extra]])
                             for f, v in zip(jd.DamperShape._fields[:4], shape[:4])))
    return shape, np.concatenate([mu, [m for _, m in extra]])


@lru_cache(maxsize=None)
def thousand():
    shape, mu, contacts = random_designs(1000, seed=3)
    shape, mu = with_family(shape, mu)
    contacts = contacts + [jd.Contacts()] * (len(mu) - len(contacts))
    return B.stack_designs(shape, mu, contacts)


def one_design(d: jd.Design, i):
    shape = jd.DamperShape(*(np.asarray(v)[i] for v in d.shape[:4]))
    return shape, d.mu[i], jd.Contacts(d.contacts.kn[i], d.contacts.kt[i]), jd.LoadCase(
        *(v[i] for v in d.load))


@lru_cache(maxsize=None)
def loop_cycles():
    d = thousand()
    return [jd.base_cycle(*one_design(d, i)) for i in range(d.size)]


def loop_summary(cycles):
    nums = np.array([np.asarray(jd.five_numbers(bc).numbers()) for bc in cycles])
    w = np.array([np.asarray(jd.work_shape_factors(bc)) for bc in cycles])
    cols = dict(zip(jd.FiveNumbers._fields, nums.T))
    cols.update(zip(("w_R1", "w_L1", "w_L2", "w_M"), w.T))
    for f in FLAGS:
        cols[f] = np.array([np.asarray(getattr(bc, f)) for bc in cycles])
    return cols


# ------------------------------------------------------------------ stacking
def test_stack_designs_layouts():
    shapes = [jd.family_shape(n) for n in ("60sym", "74R", "90R")]
    d = B.stack_designs(shapes, 0.5)
    assert d.size == 3 and d.shape.x_d is None
    np.testing.assert_array_equal(d.shape.theta_r, [60.0, 73.9, 90.0])
    np.testing.assert_array_equal(d.mu, [0.5] * 3)
    assert np.shape(d.contacts.kn) == (3,) and np.shape(d.load.F_D) == (3,)
    d = B.stack_designs(shapes, [0.3, 0.5, 0.7], jd.Contacts(np.array([1e4, 2e4, 3e4]), 3600.0))
    assert np.shape(d.contacts.kn) == (3, 3)  # one Contacts: (3,) is per contact (R1, L1, L2)
    np.testing.assert_array_equal(d.contacts.kn[1], [1e4, 2e4, 3e4])
    d = B.stack_designs(shapes, 0.5, [jd.Contacts(1e4 * (i + 1), 3600.0) for i in range(3)])
    np.testing.assert_array_equal(d.contacts.kn, [1e4, 2e4, 3e4])
    d = B.stack_designs(jd.DamperShape(np.array([50.0, 60.0]), 60.0, 0.1), 0.5,
                        load=jd.LoadCase(F_D=np.array([500.0, 1000.0])))
    np.testing.assert_array_equal(d.shape.theta_r, [60.0, 60.0])
    np.testing.assert_array_equal(d.load.F_D, [500.0, 1000.0])
    # vmap over the stacked pytree is the batched Base-Cycle.
    bc = jax.vmap(jd.base_cycle)(*B.stack_designs(shapes, 0.5))
    assert bc.forward.dv.shape[0] == 3


@pytest.mark.parametrize("kwargs,match", [
    (dict(shapes=[jd.family_shape("60sym")] * 2, mu=[0.3, 0.5, 0.7]), "lengths"),
    (dict(shapes=[jd.DamperShape(95.0, 60.0, 0.1)], mu=0.5), "theta_l"),
    (dict(shapes=[jd.family_shape("60sym")], mu=0.0), "mu"),
    (dict(shapes=[jd.family_shape("60sym")], mu=0.5, contacts=jd.Contacts(-1.0, 3600.0)), "kn"),
    (dict(shapes=[jd.DamperShape(60, 60, 0.1, 0.8, 0.5), jd.DamperShape(60, 60, 0.1)], mu=0.5), "x_d"),
    (dict(shapes=[], mu=0.5), "shapes"),
])
def test_stack_designs_rejects_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        B.stack_designs(**kwargs)


# ------------------------------------------------------------------ vmap == Python loop
@pytest.mark.slow  # 12 worker-s (run of 2026-11-25)
def test_vmap_base_cycle_equals_python_loop_1000_designs():
    d = thousand()
    batched = jax.jit(jax.vmap(jd.base_cycle))(*d)
    looped = jax.tree_util.tree_map(lambda *xs: np.stack(xs), *loop_cycles())
    leaves = jax.tree_util.tree_flatten_with_path(batched)[0]
    ref = jax.tree_util.tree_leaves(looped)
    assert len(leaves) == len(ref)
    for (path, a), b in zip(leaves, ref):
        assert_leaf_close(jax.tree_util.keystr(path), a, b)
    # The sample contains working dampers, liftoff and second-stage (frozen mechanism) cycles.
    assert 0 < int(np.sum(batched.status == jd.RESULTS.liftoff)) < d.size
    assert int(np.max(batched.half_cycles)) > 2


@pytest.mark.slow  # 23 worker-s (run of 2026-11-25)
def test_evaluate_designs_equals_python_loop():
    d = thousand()
    out = B.evaluate_designs(d, chunk_size=256)  # 1018 designs: 4 chunks, the last one padded
    ref = loop_summary(loop_cycles())
    for f in EXACT_FIELDS + FLAGS:
        assert_leaf_close(f, getattr(out, f), ref[f])


def test_k_re_bc_matches_loop():
    out = B.evaluate_designs(thousand(), chunk_size=256)
    ref = loop_summary(loop_cycles())
    ok = out.status != jd.RESULTS.liftoff
    assert_leaf_close("k_re_bc", out.k_re_bc[ok], ref["k_re_bc"][ok])


# ------------------------------------------------------------------ no NaN over 10,000 designs
@pytest.mark.slow  # 30 worker-s (run of 2026-11-25)
def test_no_nan_over_10000_random_designs():
    shape, mu, contacts = random_designs(10_000, seed=11)
    shape, mu = with_family(shape, mu)
    contacts = contacts + [jd.Contacts()] * (len(mu) - len(contacts))
    out = B.evaluate_designs(B.stack_designs(shape, mu, contacts))
    for f in B.DesignSummary._fields:
        assert np.all(np.isfinite(getattr(out, f))), f
    # Liftoff and non-convergence are statuses, and every design ends ok, lifted off or failed.
    assert 0.1 < (out.status == jd.RESULTS.liftoff).mean() < 0.9
    assert np.all(np.isin(out.status, (jd.RESULTS.ok, jd.RESULTS.liftoff, jd.RESULTS.singular)))
    assert (out.status == jd.RESULTS.singular).mean() < 0.01
    ok = out.status == jd.RESULTS.ok
    assert np.all(out.psi_bc[ok] >= out.psi_fs[ok]) and np.all(out.k_im_bc[ok] >= -1e-9)
    assert_tree_allclose(out.w_M[ok], (out.w_R1 + out.w_L1 + out.w_L2)[ok], rtol=1e-9, atol=1e-12)


# ------------------------------------------------------------------ two devices
TWO_DEVICE_SCRIPT = textwrap.dedent("""
    import json, sys
    import jax
    import numpy as np
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd
    from jaxdamp import batch as B

    assert len(jax.devices()) == 2, jax.devices()
    rng = np.random.default_rng(5)
    n = 37  # odd: padded to a multiple of the device count
    shape = jd.DamperShape(rng.uniform(40, 90, n), rng.uniform(40, 90, n), rng.uniform(-0.2, 0.3, n))
    # The last design is 90R, whose frozen-mechanism cycle needs the second stage.
    shape = jd.DamperShape(*(np.r_[v[:-1], w] for v, w in zip(shape, (40.9, 90.0, 0.0))))
    d = B.stack_designs(shape, np.r_[rng.uniform(0.2, 0.8, n - 1), 0.5])
    mesh = B.device_mesh()
    padded = B.take(d, np.r_[np.arange(n), [0] * (64 - n)])
    out = jax.jit(jax.vmap(lambda x: B.summary_kernel(x, 1)))(B.shard(padded, mesh))
    shards = sorted(s.data.shape[0] for s in out.psi_bc.addressable_shards)
    two = B.evaluate_designs(d)
    print(json.dumps({"devices": len(out.psi_bc.sharding.device_set), "shards": shards,
                      "designs": [np.asarray(v).tolist() for v in d.shape[:3]] + [d.mu.tolist()],
                      "two": {f: np.asarray(v).tolist() for f, v in two._asdict().items()}}))
""")


@pytest.mark.slow  # 36 worker-s (run of 2026-11-25)
def test_batch_is_sharded_over_two_devices():
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2", JAX_PLATFORMS="cpu")
    proc = subprocess.run([sys.executable, "-c", TWO_DEVICE_SCRIPT], env=env, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    assert res["devices"] == 2 and res["shards"] == [32, 32]
    two = res["two"]
    assert len(two["psi_bc"]) == 37 and max(two["half_cycles"]) > 2
    # Reference: this (one-device) process, design by design.
    cycles = [jd.base_cycle(jd.DamperShape(tl, tr, br), mu) for tl, tr, br, mu in zip(*res["designs"])]
    ref = loop_summary(cycles)
    for f in EXACT_FIELDS + FLAGS:
        assert_leaf_close(f, two[f], ref[f])


# ------------------------------------------------------------------ sweeps
def reference_point(theta_l, theta_r, br, mu):
    bc = jd.base_cycle(jd.DamperShape(theta_l, theta_r, br), mu)
    return bc, jd.five_numbers(bc), jd.work_shape_factors(bc)


def test_sweep_centred_br_matches_design_by_design():
    tl, tr, mus = [50.0, 60.0, 73.9], [49.1, 60.0, 73.9], [0.3, 0.7]
    res = B.sweep(tl, tr, mus, "centred")
    assert res.mu_max == 0.7 and res.summary.psi_bc.shape == (2, 3, 3)
    for i, t_l in enumerate(tl):
        for j, t_r in enumerate(tr):
            design = jd.design_br(jd.DamperShape(t_l, t_r, 0.0), 0.7)
            assert res.br_over_hr[i, j] == pytest.approx(float(design.br_over_hr), rel=1e-12, abs=1e-15)
            assert res.br_found[i, j] == bool(design.found)
            assert res.br_inside[i, j] == bool(design.inside)
            for k, mu in enumerate(mus):
                bc, nums, w = reference_point(t_l, t_r, res.br_over_hr[i, j], mu)
                s = res.summary
                assert s.status[k, i, j] == int(bc.status)
                for f in ("psi_fs", "psi_bc", "k_im_bc", "k_re_fs"):
                    assert getattr(s, f)[k, i, j] == pytest.approx(float(getattr(nums, f)), rel=1e-12)
                assert s.w_M[k, i, j] == pytest.approx(float(w.w_M), rel=1e-12)
    s = res.summary
    # valid is the status, and b_R found
    np.testing.assert_array_equal(res.status == jd.RESULTS.ok, (s.status == jd.RESULTS.ok) & res.br_found[None])
    assert (res.status[:, 1, 1] == jd.RESULTS.ok).all()  # 60sym with its centred b_R works at both mu


@pytest.mark.slow  # 11 worker-s (run of 2026-11-25)
def test_sweep_fixed_br_marks_74L_liftoff_at_mu_0p7():
    res = B.sweep([73.9], [49.1], [0.5, 0.7], 0.16)
    assert res.mu_max is None and res.br_over_hr[0, 0] == 0.16
    assert (res.summary.status[:, 0, 0] == jd.RESULTS.liftoff).tolist() == [False, True]
    assert (res.status[:, 0, 0] == jd.RESULTS.ok).tolist() == [True, False]


def test_sweep_rejects_bad_input():
    with pytest.raises(ValueError, match="br_over_hr"):
        B.sweep([60.0], [60.0], [0.5], "middle")
    with pytest.raises(ValueError, match="theta_r"):
        B.sweep([60.0], [], [0.5])
    with pytest.raises(ValueError, match="mu"):
        B.sweep([60.0], [60.0], [0.5, -0.2])


# ------------------------------------------------------------------ the one batching path

def test_batch_sizes_share_bucketed_programs():
    rng = np.random.default_rng(3)

    def designs(n):
        return jd.stack_designs(jd.DamperShape(rng.uniform(45, 85, n), rng.uniform(45, 85, n),
                                               rng.uniform(-0.1, 0.2, n)), 0.5)

    jd.evaluate_designs(designs(20))
    with count_compiles() as compiled:
        for n in (17, 25, 32):  # one bucket (32 designs)
            jd.evaluate_designs(designs(n))
    assert compiled == []


def test_bucket_sizes():
    assert B.bucket_size(1, 1, 1024) == B.MIN_BATCH
    assert B.bucket_size(100, 1, 1024) == 128
    assert B.bucket_size(5000, 1, 1024) == 1024
    assert B.bucket_size(37, 2, 1024) == 64
    assert B.bucket_size(3, 3, 1024) % 3 == 0


def test_default_chunk_by_platform_and_memory():
    assert B.default_chunk("cpu") == 1024
    assert B.default_chunk("gpu") == 131072
    # 80 GB free: the platform default stands; 1 GB free: bounded by memory, a power of two.
    assert B.default_chunk("gpu", free_bytes=80 * 2**30) == 131072
    small = B.default_chunk("gpu", free_bytes=2**30)
    assert small * B.BYTES_PER_DESIGN <= B.MEMORY_SHARE * 2**30 and small & (small - 1) == 0
    assert B.default_chunk("gpu", free_bytes=0) == B.MIN_BATCH
    assert B.default_chunk("unknown-accelerator") == 1024


def test_map_batched_matches_a_loop_and_rejects_bad_chunks():
    def f(x, y):
        return x * y

    x = np.arange(37.0)
    np.testing.assert_array_equal(jd.map_batched(f, x, 2.0, chunk_size=8), 2.0 * x)
    with pytest.raises(ValueError, match="chunk_size"):
        jd.map_batched(f, x, 2.0, chunk_size=0)



def test_map_batched_refuses_what_is_not_a_function_before_any_work():
    """A progress that is not a function failed after the first chunk had run."""
    with pytest.raises(ValueError, match=r"^fn must be a function; got int$"):
        jd.map_batched(5, np.ones(3))
    with pytest.raises(ValueError, match=r"^progress must be a function; got int$"):
        jd.map_batched(lambda x: x, np.ones(3), progress=5)
    for chunk in ("a", float("nan"), 2.5):  # int()'s own errors, or 2.5 taken as 2
        with pytest.raises(ValueError, match=r"^chunk_size must be an integer >= 1"):
            jd.map_batched(lambda x: x, np.ones(3), chunk_size=chunk)
