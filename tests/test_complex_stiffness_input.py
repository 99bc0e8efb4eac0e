"""complex_stiffness refuses amplitudes that have no cycle with one ValueError line (issue #23), and
works on a traced cycle at concrete amplitudes."""

import jax
import numpy as np
import pytest

import jaxdamp as jd

from helpers import assert_tree_allclose


@pytest.fixture(scope="module")
def bc():
    return jd.base_cycle(jd.family_shape("60sym"), 0.5)


@pytest.mark.parametrize("psi, method", [([-1.0, 2.0], "exact"), ([0.0], "exact"), (float("nan"), "exact"),
                                         ([-1.0, 2.0], "interpolated"), (float("inf"), "interpolated")])
def test_bad_amplitude_is_one_line_error(bc, psi, method):
    with pytest.raises(ValueError, match="psi_a_mrad must be finite and") as err:
        jd.complex_stiffness(bc, psi, method=method)
    assert "\n" not in str(err.value)


def test_interpolated_zero_is_full_stick(bc):
    # psi_a = 0 is the full-stick limit of the paper's curve: k_Im = 0 and k_Re = k_Re,fs, the value
    # it holds anywhere below psi_fs
    n = jd.five_numbers(bc)
    k_re, k_im = jd.complex_stiffness(bc, [0.0, 0.5 * float(n.psi_fs)], method="interpolated")
    assert_tree_allclose(k_im, np.zeros(2), rtol=1e-7, atol=1e-12)
    assert_tree_allclose(k_re[0], k_re[1], rtol=1e-12, atol=0.0)


def test_mu_of_wrong_length_is_one_line_error():
    # per-contact mu is 3 values; 2 used to fail inside the kernel as a JAX TypeError. The one
    # message of every per-pad input of one design (params.check_one_design) says so.
    with pytest.raises(ValueError, match=r"mu: one value, or one per pad \(3 for this damper\)") as err:
        jd.base_cycle(jd.family_shape("60sym"), [0.3, 0.5])
    assert "\n" not in str(err.value)



def test_a_traced_cycle_at_concrete_amplitudes():
    """Inside jit, a traced Base-Cycle with amplitudes given as numpy: the padded call is sliced
    in the trace (a host-side cut of a traced result would fail), and equals the plain call."""
    from jaxdamp.params import prepare_inputs

    s, m, c, ld = prepare_inputs(jd.family_shape("60sym"), 0.5, jd.Contacts(), jd.LoadCase())
    psi = np.array([1.0, 2.0, 6.0])
    traced = jax.jit(lambda mu: jd.complex_stiffness(jd.base_cycle_kernel(s, mu, c, ld), psi,
                                                     method="interpolated"))(m)
    plain = jd.complex_stiffness(jd.base_cycle(jd.family_shape("60sym"), 0.5), psi,
                                 method="interpolated")
    for got, want in zip(traced, plain):
        assert_tree_allclose(got, want, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("call", [lambda x: jd.five_numbers(x), lambda x: jd.complex_stiffness(x, 1.0),
                                  lambda x: jd.contact_energies(x)])
def test_a_number_for_the_base_cycle_is_one_line_naming_bc(call):
    """A number where the Base-Cycle goes failed inside with an AttributeError on a tracer."""
    with pytest.raises(TypeError, match=r"^bc must be a jaxdamp.BaseCycle \(from base_cycle\); got int$"):
        call(5)
