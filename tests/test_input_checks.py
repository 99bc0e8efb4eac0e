"""Every exported function checks its inputs, takes a result made (and checked) already, or is an
unchecked traceable helper that says so in its docstring (issue 33; docs/architecture.md, "Input
checks"). The functions whose checks were added: a bad input is a one-line ValueError naming the
parameter, and float32 is refused, before anything is compiled."""

import inspect

import jax
import numpy as np
import pytest

import jaxdamp as jd
import jaxdamp.baselines as jb
from jaxdamp.batch import check_sweep_inputs
from jaxdamp.curves import prepare_curves_inputs
from jaxdamp.statics import full_slip_work_shape_factors_kernel

from helpers import assert_tree_allclose, count_compiles

# Raw inputs checked before any work (ValueError naming the parameter and its range; the ones that
# compute refuse float32 with Float64Required).
CHECKED = {
    "family_shape", "validate_mu", "validate_contacts", "validate_load", "validate_mode",
    "full_slip_statics", "design_br", "full_slip_work_shape_factors", "base_cycle",
    "cycle_numbers", "amplitude_cycle", "amplitude_curves", "amplitude_band",
    "stiffness_curve", "stack_designs", "base_cycles", "sweep", "centred_br",
    "five_numbers_jacobian", "k_im_gradient_at", "batch_jacobian", "path_gradient",
    "damper_stiffness",
    "design_peaks", "peak_band", "response_curves", "designer_diagram", "sample_scenarios",
    "peak_distribution", "fit_loops", "fit_problem", "sample_loop", "in_phase_motion",
    "interblade_motion", "straight_motion", "general_motion", "elliptic_cycle", "interblade_sweep",
    "validate_family", "nodal_scene", "row_response", "row_band", "row_gradient", "row_diagram",
    "prepare_scene",
    "engine_orders_of",
    "path_response_curves", "path_base_cycle", "check_design", "check_batch", "evaluate_designs",
    "validated_range_violations",
    # jaxdamp.baselines
    "hbm_aft", "hbm_aft_path", "regularized_aft", "time_march", "march_ellipse", "modal_family",
    "sector_matrices", "full_matrices", "ring_response",
}
# Take a result made (and checked) by a checked function: a BaseCycle, an EllipticCycle.
TAKES_A_RESULT = {"five_numbers", "transitions_chart", "complex_stiffness", "contact_energies"}
# Unchecked, traceable helpers (building blocks of the kernels, used inside jit/vmap/grad): their
# docstrings say "unchecked" and "traceable".
UNCHECKED = {
    "section_geometry", "platform_moment", "full_slip_state", "admissible_polytope",
    "polytope_vertices", "curve_at", "cycle_work", "moment",
    "work_shape_factors", "frf", "frf_amplitude_grid", "linear_frf", "stuck_damper",
    "scaled_stiffness", "tabulated_stiffness", "peak_response", "run_half", "path_damper",
    "pad_names",
    # jaxdamp.baselines
    "first_harmonic", "march", "march_model",
}
# No model inputs: configuration, data files, the batching utility, registries.
NO_MODEL_INPUTS = {"enable_x64", "paper_tables", "no_damper", "map_batched", "default_chunk",
                   "register_stiffness_method"}


def exported_functions():
    out = {}
    for module in (jd, jd.blocks, jb):
        for name in module.__all__:
            obj = getattr(module, name)
            if callable(obj) and not inspect.isclass(obj) and not name.endswith("_kernel"):
                out[name] = obj
    return out


def test_every_exported_function_is_sorted_once():
    """A new exported function must be sorted: checked, taking a checked result, or an unchecked
    traceable helper (or named *_kernel)."""
    groups = (CHECKED, TAKES_A_RESULT, UNCHECKED, NO_MODEL_INPUTS)
    assert not set.intersection(*map(set, groups))
    assert sum(map(len, groups)) == len(set().union(*groups))
    assert set(exported_functions()) == set().union(*groups)


@pytest.mark.parametrize("name", sorted(UNCHECKED))
def test_unchecked_helpers_say_so(name):
    doc = inspect.getdoc(exported_functions()[name]).lower()
    assert "unchecked" in doc and "traceable" in doc, name


SHAPE = jd.family_shape("60sym")
KEY = jax.random.PRNGKey(0)
IN_PHASE = jd.in_phase_motion()  # built in float64, before a test turns it off

BAD = [
    (lambda: jd.sample_scenarios(KEY, 4, contacts=jd.Contacts(kn=-1.0)),
     r"^kn must be in \(0, inf\) N/mm; got -1$"),
    (lambda: jd.sample_scenarios(KEY, 4, contacts=jd.Contacts(kt=np.nan)), r"^kt must be a finite"),
    (lambda: jd.sample_scenarios(KEY, 4, load=jd.LoadCase(F_D=0.0)), r"^F_D must be in \(0, inf\) N"),
    (lambda: jd.sample_scenarios(KEY, 4, load=jd.LoadCase(q_star=-5.0)), r"^q_star must be in"),
    (lambda: jd.full_slip_work_shape_factors(SHAPE, 0.0), r"^mu must be in \(0, 5\]; got 0$"),
    (lambda: jd.full_slip_work_shape_factors(SHAPE._replace(theta_l=120.0), 0.5),
     r"^theta_l must be in \(0, 90\] deg; got 120$"),
    (lambda: jd.path_base_cycle(SHAPE, 0.5, IN_PHASE, max_pairs=0),
     r"^max_pairs must be"),
    (lambda: jd.path_base_cycle(SHAPE, -0.5, IN_PHASE), r"^mu must be in \(0, 5\]"),
]


@pytest.mark.parametrize("call, message", BAD)
def test_a_bad_input_names_its_parameter_before_any_compile(call, message):
    with count_compiles() as compiled:
        with pytest.raises(ValueError, match=message):
            call()
    assert compiled == []


FLOAT32_REFUSED = [
    lambda: jd.sample_scenarios(KEY, 4),
    lambda: jd.full_slip_work_shape_factors(SHAPE, 0.5),
    lambda: jd.blocks.centred_br([60.0], [60.0]),
    lambda: check_sweep_inputs([60.0], [60.0], [0.5]),
    lambda: jd.sweep([60.0], [60.0], [0.5]),
    lambda: jd.base_cycles(SHAPE, np.array([0.4, 0.5])),
    lambda: jd.amplitude_curves(SHAPE, 0.5, [1e-3]),
    lambda: jd.amplitude_curves(SHAPE, 0.5, [1e-3], method="sequence"),
    lambda: jd.path_base_cycle(SHAPE, 0.5, IN_PHASE),
    lambda: prepare_curves_inputs(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), [1e-3], "gross_slip"),
]


@pytest.mark.parametrize("call", FLOAT32_REFUSED)
def test_float32_is_refused_before_any_compile(call):
    jax.config.update("jax_enable_x64", False)
    try:
        with count_compiles() as compiled:
            with pytest.raises(jd.Float64Required, match="enable_x64"):
                call()
        assert compiled == []
    finally:
        jax.config.update("jax_enable_x64", True)


def test_checked_work_shape_factors_equal_their_kernel_and_trace():
    """The checked entry point returns the kernel's numbers and still works under jit."""
    a = np.asarray(jd.full_slip_work_shape_factors(SHAPE, 0.5))
    b = np.asarray(full_slip_work_shape_factors_kernel(SHAPE, 0.5))
    c = np.asarray(jax.jit(jd.full_slip_work_shape_factors)(SHAPE, 0.5))
    np.testing.assert_array_equal(a, b)
    assert_tree_allclose(c, a, rtol=1e-14, atol=0.0)
