"""`jaxdamp response --uncertainty`: the JSON agrees with `jaxdamp.uncertainty` called directly on
the same samples; bad flags are one line naming the flag, exit 2, before any work."""

import jax
import numpy as np
import pytest

from jaxdamp import Contacts, LoadCase, family_shape
from jaxdamp.uncertainty import Uncertainty, peak_distribution, sample_scenarios

from helpers import assert_tree_allclose, one_error_line, run_cli, strict_json


@pytest.mark.slow  # 82 worker-s (run of 2026-11-25)
def test_json_matches_the_library_on_the_same_samples(capsys):
    code, out, _ = run_cli(capsys, "response", "--shape", "60sym", "--force-n", "3,9",
                           "--uncertainty", "--samples", "6", "--seed", "4",
                           "--peak-limit-mm-per-n", "0.5", "--json")
    assert code == 0
    d = strict_json(out)
    assert d["status"] == "ok" and d["n_ok"] == 6
    scen = sample_scenarios(jax.random.PRNGKey(4), 6, Uncertainty(), Contacts(), LoadCase())
    ref = peak_distribution(family_shape("60sym"), scen, force_n=[3.0, 9.0], limit_mm_per_n=0.5)
    # JSON numbers as float64 arrays, as np.testing.assert_allclose read them
    assert_tree_allclose(np.asarray(d["quantiles_mm_per_n"], float), ref.quantiles, rtol=1e-12, atol=0.0)
    assert_tree_allclose(np.asarray(d["worst_mm_per_n"], float), ref.worst, rtol=1e-12, atol=0.0)
    assert_tree_allclose(np.asarray(d["exceedance"], float), ref.exceedance, rtol=1e-7, atol=0.0)


@pytest.mark.parametrize("argv, needle", [
    (["--samples", "1"], "--samples must be an integer in [2, 1000000]"),
    (["--mu-range", "0.7:0.3"], "--mu-range"),
    (["--mu-range", "x"], "--mu-range must be LOW:HIGH"),
    (["--fd-spread", "1"], "--fd-spread must be in [0, 1)"),
    (["--kn-range", "0.5"], "--kn-range must be in [1, 100]"),
    (["--kt-range", "1000"], "--kt-range must be in [1, 100]"),
    (["--peak-limit-mm-per-n", "0"], "--peak-limit-mm-per-n must be > 0"),
])
def test_bad_uncertainty_flags_are_one_line_errors(capsys, argv, needle):
    code, out, err = run_cli(capsys, "response", "--shape", "60sym", "--uncertainty", *argv)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)
