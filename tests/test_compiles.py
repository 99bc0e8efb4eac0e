"""A second call of each public function and cheap CLI command, with new values of the same shapes,
compiles nothing: every compiled program lives at module level or in one cache, and inputs are
converted to one form before they reach it (a plain number and an array of the same value meet the
same program)."""

import contextlib
import io

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.cli import main

from helpers import count_compiles

S60, S74R = jd.family_shape("60sym"), jd.family_shape("74R")

# name -> (first call, second call with other values of the same shapes)
CALLS = {
    "base_cycle": (lambda: jd.base_cycle(S60, 0.5), lambda: jd.base_cycle(S74R, 0.3)),
    "five_numbers": (lambda: jd.five_numbers(jd.base_cycle(S60, 0.5)),
                     lambda: jd.five_numbers(jd.base_cycle(S74R, 0.4))),
    "cycle_numbers": (lambda: jd.cycle_numbers(S60, 0.5), lambda: jd.cycle_numbers(S74R, 0.6)),
    "full_slip_statics": (lambda: jd.full_slip_statics(S60, 0.5),
                          lambda: jd.full_slip_statics(S74R, 0.7)),
    "design_br": (lambda: jd.design_br(S60, 0.7), lambda: jd.design_br(S74R, 0.6)),
    "amplitude_cycle": (lambda: jd.amplitude_cycle(S60, 0.5, 1.0),
                        lambda: jd.amplitude_cycle(S74R, 0.3, 1.7)),
    "amplitude_curves": (lambda: jd.amplitude_curves(S60, 0.5, np.array([0.5, 1.0, 4.0])),
                         lambda: jd.amplitude_curves(S74R, 0.4, np.array([0.3, 2.0, 6.0]))),
    "complex_stiffness": (
        lambda: jd.complex_stiffness(jd.base_cycle(S60, 0.5), np.array([0.5, 3.0])),
        lambda: jd.complex_stiffness(jd.base_cycle(S74R, 0.3), np.array([0.7, 5.0]))),
    "evaluate_designs": (
        lambda: jd.evaluate_designs(jd.stack_designs([S60, S74R], [0.5, 0.3])),
        lambda: jd.evaluate_designs(jd.stack_designs([S74R, S60], [0.6, 0.7]))),
    "five_numbers_jacobian": (lambda: jd.five_numbers_jacobian(S60, 0.5),
                              lambda: jd.five_numbers_jacobian(S74R, 0.4)),
    "contact_energies": (lambda: jd.contact_energies(jd.base_cycle(S60, 0.5)),
                         lambda: jd.contact_energies(jd.base_cycle(S74R, 0.3))),
    "peak_band": (lambda: jd.peak_band(S60, 0.5, force_n=np.array([5.0])),
                  lambda: jd.peak_band(S74R, 0.4, force_n=np.array([7.0]))),
    "fit_loops": (lambda: _fit(S60, 0.5), lambda: _fit(S74R, 0.4)),
    "robust_objective": (lambda: _robust(S60), lambda: _robust(S74R)),
}


def _fit(shape, mu):
    """A fit of one model loop (the same number of samples each time), a few steps."""
    psi, m = jd.sample_loop(shape, mu, 2.0, t=np.linspace(0.0, 2.0, 241))
    return jd.fit_loops([(psi, m)], shape, max_steps=3)


def _robust(shape):
    """The robust objective's values of a design vector (the optimiser's inner evaluation)."""
    from jaxdamp_optimize.problem import make_problem
    from jaxdamp_optimize.robust_objective import RobustSpec, objective_args, robust_values

    problem = make_problem(mus=(0.4, 0.6))
    spec = RobustSpec(force_range_n=(4.0, 12.0), n_forces=2)
    v = [shape.theta_l, shape.theta_r, shape.br_over_hr, shape.bl2_over_hl]
    return robust_values(np.asarray([v], float), problem, spec, objective_args(problem, spec))


@pytest.mark.slow  # 36 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name", sorted(CALLS))
def test_second_call_of_a_public_function_compiles_nothing(name):
    first, second = CALLS[name]
    first()
    with count_compiles() as compiled:
        second()
    assert compiled == [], (name, compiled)


def _cli(*argv):
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(list(argv)) == 0


COMMANDS = {
    "cycle": (["cycle", "--shape", "60sym", "--mu", "0.5", "--json"],
              ["cycle", "--shape", "74R", "--mu", "0.3", "--kt", "4000", "--json"]),
    "statics": (["statics", "--shape", "60sym", "--mu", "0.5", "--json"],
                ["statics", "--shape", "74R", "--mu", "0.3", "--json"]),
    "design-br": (["design-br", "--shape", "60sym", "--json"],
                  ["design-br", "--shape", "74R", "--mu-max", "0.6", "--json"]),
    "amplitude": (["amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "1,2", "--json"],
                  ["amplitude", "--shape", "74R", "--mu", "0.3", "--psi-a", "0.5,3", "--json"]),
    "grad": (["grad", "--shape", "60sym", "--mu", "0.5", "--json"],
             ["grad", "--shape", "74R", "--mu", "0.4", "--json"]),
}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_second_call_of_a_command_compiles_nothing(name):
    first, second = COMMANDS[name]
    _cli(*first)
    with count_compiles() as compiled:
        _cli(*second)
    assert compiled == [], (name, compiled)
