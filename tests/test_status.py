"""RESULTS: codes, messages, promotion order, and the statuses the solver reports."""

import jax.numpy as jnp
import numpy as np

import jaxdamp as jd
from jaxdamp.status import RESULTS, ok_status


def test_promote_keeps_the_first_problem():
    s = ok_status((3,))
    s = RESULTS.promote(s, jnp.array([True, False, False]), RESULTS.liftoff)
    s = RESULTS.promote(s, jnp.array([True, True, False]), RESULTS.not_converged)
    assert list(np.asarray(s)) == [RESULTS.liftoff, RESULTS.not_converged, RESULTS.ok]


def test_every_code_has_a_name_and_a_message():
    for code in RESULTS:
        assert RESULTS.name_of(jnp.int32(code)) == code.name
        assert RESULTS.message(code)
    assert bool(RESULTS.valid(RESULTS.shakedown)) and not bool(RESULTS.valid(RESULTS.liftoff))


def test_solver_statuses():
    ok = jd.base_cycle(jd.family_shape("60sym"), 0.5)
    lift = jd.base_cycle(jd.family_shape("74L"), 0.7)  # the left resultant leaves L1-L2
    assert RESULTS.name_of(ok.status) == "ok" and bool(ok.converged)
    assert RESULTS.name_of(lift.status) == "liftoff" and bool(lift.liftoff)


def test_results_print_short_with_units_and_status_by_name():
    """A user printing a result reads its status by name and its numbers with units, in a line or
    two: never `Array(..., dtype=float64)`, a bare status integer or hundreds of lines."""
    shape = jd.family_shape("60sym")
    bc = jd.base_cycle(shape, 0.5)
    lift = jd.base_cycle(jd.family_shape("74L"), 0.7)
    results = [bc, jd.five_numbers(bc), jd.five_numbers(lift), jd.cycle_numbers(shape, 0.5),
               jd.contact_energies(bc), jd.full_slip_statics(shape, 0.5),
               jd.design_br(jd.DamperShape(60.0, 60.0, 0.0), 0.7),
               jd.amplitude_cycle(shape, 0.5, 1.0),
               jd.amplitude_curves(shape, 0.5, np.linspace(0.5, 5.0, 12)),
               jd.evaluate_designs(jd.stack_designs([shape] * 5, [0.3, 0.4, 0.5, 0.6, 0.7]))]
    for r in results:
        text = repr(r)
        assert len(text) < 400 and "Array(" not in text and "dtype" not in text, text
        if hasattr(r, "status"):
            assert "status=" in text and "status=<" not in text, text
    assert "status=liftoff" in repr(jd.five_numbers(lift))
    assert "psi_bc=2.18016 mrad" in repr(jd.five_numbers(bc))  # Table B4.1: psi_BC = 2.18 mrad
    assert "status=ok: 5" in repr(results[-1])


def test_reprs_do_not_force_tracers():
    import jax

    shape = jd.family_shape("60sym")

    def f(mu):
        nums = jd.five_numbers_kernel(jd.base_cycle_kernel(*jd.Design(shape, mu).prepared()))
        assert "<traced>" in repr(nums)
        return nums.k_im_bc

    jax.jit(f)(0.5)
