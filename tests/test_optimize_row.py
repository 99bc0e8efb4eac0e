"""Robust design over a blade row (jaxdamp_optimize.row_objective; issue 35).

References: the in-phase robust objective (`robust_objective.robust_values`: the one-mode blade,
the straight engine's exact curve with its IFT peak search, the F_D scaling law), which a row of
one engine order on an in-phase family must reproduce; the quasi-static contact problem's
homogeneity in F_D and the amplitude (A*(F; s F_D) = s A*(F / s) on every path), which the
descent relies on to cover the F_D spread without running it."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.modal_file import load_modal_family
from jaxdamp.response.modes import family_from_blade_mode
from jaxdamp_optimize.design import shape_of_vector
from jaxdamp_optimize.problem import make_problem
from jaxdamp_optimize.robust_objective import RobustSpec, objective_args, robust_values
from jaxdamp_optimize.row_objective import (IN_PHASE_ROBUST_OPTIMUM, RowTask, certify_row,
                                            optimize_row, row_magnification, row_values)

from helpers import assert_tree_allclose

SIXTY = tuple(jd.family_shape("60sym")[:3]) + (0.8,)


@pytest.mark.parametrize("kwargs, needle", [
    (dict(spec=RobustSpec(history="gross_slip")), "--history must be one of assembly, band"),
    (dict(spec=RobustSpec(objective="q95")), "--objective must be peak:worst with --modes"),
    (dict(corners="some"), "corners must be one of nominal, all"),
    (dict(engine_orders=[30], h_l_mm=10.0), "engine_order 30 excites nodal diameter"),
    (dict(h_l_mm=0.0), "h_l must be"),
])
def test_bad_inputs_are_refused_before_any_row_runs(kwargs, needle):
    family = family_from_blade_mode(jd.BladeMode(), 100.0, 20.0, n_blades=4)
    args = dict(engine_orders=[0], h_l_mm=10.0) | kwargs
    with pytest.raises(ValueError, match=needle):
        optimize_row(family, args.pop("engine_orders"), args.pop("h_l_mm"), **args)


@pytest.mark.slow  # the row's straight programs from both histories and the in-phase values program
def test_one_in_phase_engine_order_is_the_in_phase_robust_objective():
    """Nodal diameter 0 of an in-phase family is the one-mode blade on the paper's path: the
    row's hard maximum over mu, every contact corner, both histories and the descent's forces is
    the in-phase robust objective's (another program: the straight engine from the Base-Cycle's
    gross-slip state, the IFT peak search)."""
    mode = jd.BladeMode()
    family = family_from_blade_mode(mode, 100.0, 20.0, n_blades=4)
    problem = make_problem(mus=(0.3, 0.6))
    spec = RobustSpec(n_forces=4)
    V = np.array([SIXTY, IN_PHASE_ROBUST_OPTIMUM])
    _, hard, feasible = row_values(V, problem, spec, RowTask(family, (0,), 10.0), corners="all")
    ref, ref_feasible = robust_values(V, problem, spec, objective_args(problem, spec, mode))
    assert feasible.tolist() == ref_feasible.tolist() == [True, True]
    assert_tree_allclose(hard, ref, rtol=1e-8, atol=0)


@pytest.mark.slow  # the example row's programs from both histories
@pytest.mark.parametrize("initial", ["assembly", "gross_slip"])
def test_the_fd_spread_is_a_force_scaling_at_every_engine_order(initial):
    """A*(F; s F_D)/F = A*(F/s; F_D)/(F/s): the contact forces and the slips scale with F_D, so
    every cycle, straight or elliptic, scales with it at s times the amplitude."""
    family = load_modal_family("example")
    task = RowTask(family, (0, 5, 12), 10.0)
    s, forces = 1.2, np.array([3.0, 12.0])
    scaled, st_scaled = row_magnification(SIXTY, task, 0.5, jd.Contacts(),
                                          jd.LoadCase(1000.0 * s), forces, initial)
    base, st_base = row_magnification(SIXTY, task, 0.5, jd.Contacts(), jd.LoadCase(), forces / s,
                                      initial)
    assert np.array_equal(st_scaled, st_base) and bool(np.all(jd.RESULTS.valid(st_base)))
    assert_tree_allclose(scaled, base, rtol=1e-8, atol=0)


@pytest.mark.slow  # a small optimisation: grid, descent and certification of three designs
def test_a_small_row_optimisation_improves_and_is_certified_everywhere():
    family = load_modal_family("example")
    problem = make_problem(mus=(0.5,))
    spec = RobustSpec(force_range_n=(3.0, 10.0), fd_spread=0.1, history="assembly", n_forces=4)
    res = optimize_row(family, [0, 12], 10.0, problem, spec, grid_points=3, steps=2,
                       certify_options=dict(n_mu=1, n_k=1, n_fd=1, n_forces=4))
    values = [v for _, _, v in res.history]
    assert values == sorted(values, reverse=True)  # only improvements are accepted
    for d in [res.best] + res.references:
        assert len(d.worst_band) == 2 and d.engine_order == (0, 12)
        if d.feasible:
            assert d.worst == max(x for x in d.worst_band if x is not None)
    # One grid point is the nominal scenario: the certified worst per engine order is the
    # largest A*/F of the public row response at the certification's forces.
    assert res.best.feasible and res.best.scenarios == 1
    row = jd.row_response(shape_of_vector(np.asarray(res.best.shape)), 0.5,
                          modes=family, engine_orders=[0, 12], force_n=res.best.force_n,
                          h_l_mm=10.0, initial="assembly")
    expected = np.max(row.peaks.peak_amplitude_mm / np.asarray(res.best.force_n)[None], axis=1)
    assert_tree_allclose(np.array(res.best.worst_by_history["assembly"]), expected, rtol=1e-12,
                         atol=0)
    # The binding scenario is named: the row from its history at its force peaks at the worst.
    ws = res.best.worst_scenario
    assert (ws["mu"], ws["kn_factor"], ws["kt_factor"]) == (0.5, 1.0, 1.0)
    bind = jd.row_response(shape_of_vector(np.asarray(res.best.shape)), 0.5, modes=family,
                           engine_orders=[0, 12], force_n=[ws["force_n"]], h_l_mm=10.0,
                           initial=ws["history"])
    assert_tree_allclose(np.max(bind.peaks.peak_amplitude_mm) / ws["force_n"],
                         np.float64(res.best.worst), rtol=1e-12, atol=0)


@pytest.mark.slow  # the example row's values and derivative programs from assembly
def test_the_descent_gradient_is_that_of_the_smooth_maximum():
    """d log(smooth max) / dv from the peaks' implicit-function derivatives (`row_gradient`)
    against central differences of the smooth maximum row_values computes from values alone,
    at a design away from switches (engine orders 0 and 3 of the example disk, two forces)."""
    family = load_modal_family("example")
    problem = make_problem(mus=(0.5,))
    spec = RobustSpec(force_range_n=(3.0, 6.0), fd_spread=0.0, history="assembly", n_forces=2)
    task = RowTask(family, (0, 3), 10.0)
    v = np.array(IN_PHASE_ROBUST_OPTIMUM)
    smooth, _, feasible, grad = row_values(v, problem, spec, task, gradient=True)
    assert feasible[0] and np.all(np.isfinite(grad))
    steps = np.array([1e-3, 1e-3, 1e-5, 1e-5])
    central = []
    for j in range(4):
        e = np.zeros(4)
        e[j] = steps[j]
        up, down = (row_values(np.stack([v + e, v - e]), problem, spec, task)[0])
        central.append((np.log(up) - np.log(down)) / (2 * steps[j]))
    central = np.array(central)
    assert np.max(np.abs(central)) > 0
    assert_tree_allclose(grad[0], central, rtol=0.0, atol=1e-6 * np.max(np.abs(central)))


@pytest.mark.slow  # two scenarios of a two-engine-order row, both histories
def test_certify_row_hands_each_scenario_its_rows():
    """on_scenario sees every scenario once with both histories' rows, and those rows are what
    the certificate's worst per engine order and history is the maximum of."""
    family = load_modal_family("example")
    problem = make_problem(mus=(0.3, 0.7))
    spec = RobustSpec(force_range_n=(3.0, 10.0))
    task = RowTask(family, (0, 12), 10.0)
    seen = []
    cert = certify_row("60sym", SIXTY, problem, spec, task, n_forces=2, n_mu=2, n_k=1, n_fd=1,
                       on_scenario=lambda s, rows: seen.append((s, rows)))
    assert [s["mu"] for s, _ in seen] == [0.3, 0.7]
    assert all((s["kn_factor"], s["kt_factor"]) == (1.0, 1.0) for s, _ in seen)
    assert all(set(rows) == {"gross_slip", "assembly"} for _, rows in seen)
    for h in ("gross_slip", "assembly"):
        mags = [np.where(jd.RESULTS.valid(st), mag, -np.inf) for _, rows in seen
                for mag, st in [rows[h]]]
        worst = np.max(np.stack(mags), axis=(0, 2))
        got = np.array([-np.inf if x is None else x for x in cert.worst_by_history[h]])
        assert_tree_allclose(got, worst, rtol=0, atol=0)
