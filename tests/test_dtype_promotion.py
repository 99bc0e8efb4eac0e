"""Strict dtype promotion on the core's public paths: no int32 status meets an int64 index and no
float32 leaks in without a cast. (The whole suite cannot run strict: optax's L-BFGS and Adam mix
int32 and int64 counters under x64; 24 tests of calibration and optimize/ fail there, none in
jaxdamp's own code. So this file runs the core strict, and conftest keeps "standard".)"""

import jax
import numpy as np
import pytest

import jaxdamp as jd

S60 = jd.family_shape("60sym")

CALLS = {
    "base_cycle+five_numbers": lambda: jd.five_numbers(jd.base_cycle(S60, np.array([0.4, 0.5, 0.6]))),
    "cycle_numbers": lambda: jd.cycle_numbers(S60, 0.5),
    "statics": lambda: (jd.full_slip_statics(S60, 0.5), jd.design_br(S60, 0.7)),
    "amplitude_curves": lambda: (jd.amplitude_curves(S60, 0.5, np.array([0.3, 1.0, 3.0])),
                                 jd.amplitude_curves(S60, 0.5, np.array([0.3, 1.0]),
                                                     initial="assembly")),
    "complex_stiffness": lambda: jd.complex_stiffness(jd.base_cycle(S60, 0.5), np.array([0.5, 3.0])),
    "amplitude_band": lambda: jd.amplitude_band(S60, 0.5, 1.0, n_samples=32, refine=False),
    "evaluate_designs": lambda: jd.evaluate_designs(jd.stack_designs([S60, S60], [0.3, 0.5])),
    # One mode each of the costlier programs (a strict trace compiles anew): forward Jacobians,
    # and the peak search that once compared an int64 index with an int32 count.
    "jacobians": lambda: jd.five_numbers_jacobian(S60, 0.5, mode="fwd"),
    "design_peaks": lambda: jd.design_peaks(S60, 0.5, force_n=[2.0]),
}


@pytest.mark.slow  # 152 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name", sorted(CALLS))
def test_core_public_paths_run_with_strict_dtype_promotion(name):
    with jax.numpy_dtype_promotion("strict"):
        out = CALLS[name]()
    leaves = jax.tree_util.tree_leaves(out)
    assert leaves and all(np.all(np.isfinite(np.asarray(x, float))) for x in leaves
                          if np.asarray(x).dtype.kind == "f")


def test_the_peak_search_runs_under_strict_promotion():
    """The peak search (its bracketed root loop counted its steps as int32 + bool, which strict
    promotion refuses; the slow design_peaks case above caught it) on the cheapest curve, a stuck
    damper: the blade's peak is then the linear one, F / (eta k_b) (an identity, not a number of
    the code's)."""
    from helpers import assert_tree_allclose

    mode = jd.BladeMode()
    with jax.numpy_dtype_promotion("strict"):
        peaks = jd.peak_response(jd.blocks.stuck_damper(1e4), mode, np.array([2.0, 5.0]))
    assert_tree_allclose(np.asarray(peaks.peak_amplitude_mm),
                         np.array([2.0, 5.0]) / (mode.eta * mode.k_b), rtol=1e-9, atol=0.0)
