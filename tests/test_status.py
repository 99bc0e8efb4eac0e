"""RESULTS: codes, messages, promotion order, and the statuses the solver reports."""

import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.status import RESULTS


def test_conditions_become_the_most_severe_status_in_the_one_order():
    """RESULTS.first: the most severe condition that holds (SEVERITY), whatever order the
    conditions are written in."""
    from jaxdamp.status import SEVERITY

    lift, stuck = jnp.array([True, False, False]), jnp.array([True, True, False])
    for conditions in ({RESULTS.liftoff: lift, RESULTS.not_converged: stuck},
                       {RESULTS.not_converged: stuck, RESULTS.liftoff: lift}):
        s = RESULTS.first(conditions)
        assert list(np.asarray(s)) == [RESULTS.liftoff, RESULTS.not_converged, RESULTS.ok]
    assert SEVERITY.index(RESULTS.liftoff) < SEVERITY.index(RESULTS.not_converged)
    with pytest.raises(ValueError, match="problem codes"):
        RESULTS.first({RESULTS.ok: lift})


def test_statuses_combine_by_severity_not_by_code():
    """Combining statuses (two halves, a grid, a batch) keeps the most severe by SEVERITY, which is
    not the order of the codes: shakedown (5, valid numbers) ranks below liftoff (1); the
    optimiser's worst status used to be the largest code (issue 62)."""
    from jaxdamp.status import SEVERITY

    assert set(SEVERITY) == set(RESULTS) - {RESULTS.ok}
    for i, a in enumerate(SEVERITY):
        for b in SEVERITY[i:]:
            assert int(RESULTS.combine(a, b)) == a and int(RESULTS.combine(b, a)) == a
            assert int(RESULTS.combine(RESULTS.ok, b)) == b
    grid = jnp.array([[RESULTS.shakedown, RESULTS.liftoff], [RESULTS.ok, RESULTS.not_converged]])
    assert int(RESULTS.worst(grid)) == RESULTS.liftoff
    assert list(np.asarray(RESULTS.worst(grid, axis=1))) == [RESULTS.liftoff, RESULTS.not_converged]
    assert list(np.asarray(RESULTS.worst(grid, axis=0))) == [RESULTS.shakedown, RESULTS.liftoff]


def test_host_statuses_combine_in_numpy_as_traced_ones_do():
    """On host arrays RESULTS.first / combine / worst compute in NumPy (no XLA program compiled
    per operation: a blade row's response had 30 of them) and give the codes the same functions
    give under jit, where they must stay traceable."""
    import jax

    rng = np.random.default_rng(3)
    codes = np.array(list(RESULTS), np.int32)
    grid = rng.choice(codes, size=(5, 4)).astype(np.int32)
    other = rng.choice(codes, size=(5, 4)).astype(np.int32)
    lift, slow = rng.random((5, 4)) < 0.3, rng.random((5, 4)) < 0.5

    def all_of(g, o, a, b):
        return (RESULTS.first({RESULTS.liftoff: a, RESULTS.not_converged: b}, o),
                RESULTS.combine(g, o), RESULTS.worst(g), RESULTS.worst(g, axis=1),
                RESULTS.worst(g, axis=0))

    host = all_of(grid, other, lift, slow)
    traced = jax.jit(all_of)(grid, other, lift, slow)
    for h, t in zip(host, traced):
        assert isinstance(h, (np.ndarray, np.integer)) and not isinstance(h, jax.Array)
        assert np.asarray(h).dtype == np.int32
        np.testing.assert_array_equal(h, np.asarray(t))


def test_nothing_combines_statuses_by_their_codes():
    """No module ranks statuses by comparing codes (jnp.max / max of statuses): they combine
    through RESULTS.first / combine / worst only, in the one order."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    pattern = re.compile(r"\b(?:jnp\.|np\.)?max\((?:[^()]|\([^()]*\))*status", re.S)
    bad = [f"{path.relative_to(root)}: {m.group(0)[:60]!r}"
           for folder in ("jaxdamp", "optimize")
           for path in sorted((root / folder).rglob("*.py"))
           for m in pattern.finditer(path.read_text())]
    promote = [str(p.relative_to(root)) for folder in ("jaxdamp", "optimize")
               for p in sorted((root / folder).rglob("*.py")) if "RESULTS.promote(" in p.read_text()]
    assert not bad and not promote, bad + promote


def test_every_code_has_a_name_and_a_message():
    for code in RESULTS:
        assert RESULTS.name_of(jnp.int32(code)) == code.name
        assert RESULTS.message(code)
    assert bool(RESULTS.valid(RESULTS.shakedown)) and not bool(RESULTS.valid(RESULTS.liftoff))


def test_solver_statuses():
    ok = jd.base_cycle(jd.family_shape("60sym"), 0.5)
    lift = jd.base_cycle(jd.family_shape("74L"), 0.7)  # the left resultant leaves L1-L2
    assert RESULTS.name_of(ok.status) == "ok" and RESULTS.name_of(lift.status) == "liftoff"
    # a result that stopped part-way has no numbers; one that ran has them
    assert bool(RESULTS.stopped(lift.status)) and not bool(RESULTS.stopped(ok.status))
    assert float(jd.five_numbers(lift).psi_bc) == 0.0 and float(jd.five_numbers(ok).psi_bc) > 0.0


def test_no_public_result_stores_a_flag_beside_its_status():
    """Status is the one truth: no exported result type has a field or property that says whether
    its numbers hold (converged, liftoff, failed, valid, ok, ...; issue 33), and every other
    boolean-like field (found, covered, confirmed, solvable, inside, ...) is a mask listed in
    docs/api.md's "Statuses and masks" (issue 62)."""
    import inspect
    from pathlib import Path

    import jaxdamp.baselines as baselines

    forbidden = {"converged", "liftoff", "failed", "valid", "ok", "success", "feasible", "usable"}
    mask_words = {"found", "covered", "confirmed", "refined", "solvable", "inside", "gross_slip",
                  "reached", "seated", "closed", "exists", "unseated", "stopped"}
    table = (Path(__file__).resolve().parents[1] / "docs" / "api.md").read_text()
    table = table[table.index("## Statuses and masks"):]
    types = {obj for m in (jd, jd.blocks, baselines) for name in m.__all__
             if inspect.isclass(obj := getattr(m, name)) and hasattr(obj, "_fields")}
    assert len(types) > 10
    bad = []
    for t in types:
        fields = {f for f in set(t._fields) | {n for n, v in vars(t).items()
                                                 if isinstance(v, property)}
                  if not f.startswith("n_")}  # counts (n_valid, n_ok) are numbers, not flags
        bad += [f"{t.__name__}.{f} stores a flag beside the status" for f in fields
                if f in forbidden or f.split("_")[-1] in forbidden]
        bad += [f"{t.__name__}.{f} is not in docs/api.md's masks" for f in fields
                if (f in mask_words or f.split("_")[-1] in mask_words)
                and f"`{t.__name__}.{f}`" not in table]
    assert not bad, "\n".join(sorted(bad))


@pytest.mark.slow  # 12 worker-s (run of 2026-11-25)
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


# ---------------------------------------------------------------- every result prints in a line
# Status-free NamedTuples of jaxdamp.__all__ that are not results: inputs and settings (printed as
# given), geometry, and parts of a result whose own repr summarises them (FullSlipState inside
# FullSlipStatics, Half inside BaseCycle), sampled inputs (Scenarios) and an optimiser's state.
INPUTS_AND_PARTS = {"Design", "DamperShape", "SectionGeometry", "Contacts", "LoadCase", "BladeMode",
                    "Uncertainty", "FullSlipState", "Scenarios", "Motion", "ModalFamily",
                    "NodalScene"}
# Results without a status field of their own (they go with the status of what they were read
# off: a BaseCycle's energies and work shape factors; a sweep's points carry theirs in .summary).
# RowGradient's status is its row's (RowGradient.row.status); RowDiagram has one per point of
# each curve (status_vs_force, status_vs_fd).
STATUS_FREE_RESULTS = {"CycleEnergy", "WorkShapeFactors", "SweepResult", "RowGradient",
                       "RowDiagram"}


def _namedtuples():
    spaces = [(m, n) for m in (jd, jd.blocks) for n in m.__all__]
    return {n: getattr(m, n) for m, n in spaces if isinstance(getattr(m, n), type)
            and issubclass(getattr(m, n), tuple) and hasattr(getattr(m, n), "_fields")}


def test_every_exported_result_defines_its_repr():
    """Every NamedTuple result in jaxdamp.__all__ (a `status` field, or a listed status-free result)
    has a __repr__ of its own, not the one collections.namedtuple generates (which prints every
    array in full); every other NamedTuple is listed above as an input or a part, so a new type
    must be sorted into one of the two."""
    types = _namedtuples()
    assert {"BaseCycle", "LoopFit", "StiffnessCurve", "PeakDistribution"} <= set(types)
    unsorted = [n for n, cls in types.items() if "status" not in cls._fields
                and n not in INPUTS_AND_PARTS | STATUS_FREE_RESULTS]
    assert unsorted == []
    assert not INPUTS_AND_PARTS & STATUS_FREE_RESULTS
    assert all("status" not in types[n]._fields for n in INPUTS_AND_PARTS | STATUS_FREE_RESULTS)
    results = [n for n, cls in types.items() if "status" in cls._fields or n in STATUS_FREE_RESULTS]
    default = [n for n in results if types[n].__repr__.__module__ == "collections"]
    assert default == []
    assert len(results) >= 20


def _short(text):
    assert text.count("\n") <= 1 and len(text) < 400 and "Array(" not in text and "dtype" not in text, text
    return text


def test_new_reprs_give_numbers_with_units_and_status_by_name():
    """Hand-built results (no computation: numbers chosen here): the gradients, the sequence
    curve, the peak distribution, the loop fit and the status-free results."""
    import jax

    from jaxdamp.fit import FitSpec, analyse_loop

    liftoff = np.int32(RESULTS.liftoff)
    zeros = jax.tree_util.tree_map(np.zeros_like, jd.Design(jd.family_shape("60sym"), 0.5))
    d = zeros._replace(mu=np.float64(12.5))
    nums = jd.FiveNumbers(*map(np.float64, (0.5, 1000.0, 2.0, 800.0, 300.0)), liftoff)
    jac = jd.FiveNumbersJacobian(nums, jd.FiveNumbers(*[d] * 5, liftoff), liftoff)
    text = _short(repr(jac))
    assert text.startswith("FiveNumbersJacobian(status=liftoff, psi_fs=0.5 mrad, k_re_fs=1000 N mm/mrad")
    assert "d k_im_bc/d mu=12.5 N mm/mrad" in text and "d k_im_bc/d theta_l=0 N mm/mrad per deg" in text
    g = jd.KImGradient(np.float64(1.2), np.float64(250.0), d, np.int32(RESULTS.ok))
    assert _short(repr(g)).startswith("KImGradient(status=ok, psi_a=1.2 mrad, k_im=250 N mm/mrad; "
                                      "d k_im/d mu=12.5 N mm/mrad")

    start = np.array([0.0, 1.5, np.inf])
    curve = jd.StiffnessCurve(start, np.array([0.5, 2.0, 0.0]), np.zeros((3, 6, 4)), np.zeros((3, 6, 4)),
                              np.array([0, 5, 0], np.int32), np.array([True, True, False]),
                              np.float64(100.0), np.float64(0.1), np.float64(8.0), np.int32(7))
    assert _short(repr(curve)) == ("StiffnessCurve(status=[ok, shakedown], psi_a=0.1 mrad to 8 mrad, "
                                   "pieces=2 of 3, cycles=7)")

    dist = jd.PeakDistribution(np.array([2.0, 20.0]), np.zeros((6, 2)),
                               np.array([0, 0, 0, 0, 0, 1], np.int32), np.array([0.05, 0.5, 0.95]),
                               np.array([[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]]), np.array([0.7, 0.8]),
                               np.array([np.nan, np.nan]), 5)
    text = _short(repr(dist))
    assert text == ("PeakDistribution(status=ok: 5, liftoff: 1, n_ok=5, force_n=[2, 20] N, "
                    "median=[0.3, 0.4] mm/N, q95=[0.5, 0.6] mm/N, worst=[0.7, 0.8] mm/N)")
    with_limit = dist._replace(exceedance=np.array([0.0, 0.25]))
    assert _short(repr(with_limit)).endswith("worst=[0.7, 0.8] mm/N, exceedance=[0, 0.25])")

    t = np.linspace(0.0, 2.0, 200)
    loop = analyse_loop(np.cos(2 * np.pi * t), np.sin(2 * np.pi * t))
    fit = jd.LoopFit(["mu", "kn", "kt", "offset_0"], np.array([0.4, 25000.0, np.nan, 3.0]),
                     np.array([0.01, 900.0, np.nan, 1.0]), None, None, None,
                     np.array([True, True, False, True]), ["", "", "flat", ""], 0.4, None, None,
                     None, 2.5, None, [loop], None, None, [5, 3], [], FitSpec(), "gross_slip",
                     RESULTS.not_converged, ["kt"], None)
    assert _short(repr(fit)) == ("LoopFit(status=not_converged, mu=0.4 ± 0.01, kn=25000 ± 9e+02 N/mm, "
                                 "kt=not identifiable, sigma=2.5 N mm, loops=1)")

    w = jd.WorkShapeFactors(*map(np.float64, (0.25, 0.5, 0.25, 1.0)))
    assert _short(repr(w)) == "WorkShapeFactors(w_R1=0.25, w_L1=0.5, w_L2=0.25, w_M=1)"
    summary = jd.DesignSummary(*[np.zeros((1, 2, 2))] * 10, np.array([[[0, 1], [0, 0]]], np.int32))
    sw = jd.SweepResult(np.array([40.0, 60.0]), np.array([45.0, 90.0]), np.array([0.5]),
                        np.zeros((2, 2)), np.ones((2, 2), bool), np.ones((2, 2), bool), None, 0.8,
                        20000.0, 3500.0, summary)
    assert _short(repr(sw)) == ("SweepResult(theta_l=[40, 60] deg, theta_r=[45, 90] deg, mu=[0.5], "
                                "kn=20000 N/mm, kt=3500 N/mm, status=[ok, liftoff, ok, ok])")


def test_new_reprs_do_not_force_tracers():
    import jax

    def f(k):
        g = jd.KImGradient(k, k, jd.Design(jd.family_shape("60sym"), k), jax.numpy.int32(0))
        assert "<traced>" in repr(g)
        curve = jd.StiffnessCurve(*[k] * 10)
        assert "pieces=<traced>" in repr(curve)
        return k

    jax.jit(f)(1.0)
