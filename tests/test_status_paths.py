"""One truth: for every status, an input that produces it, driven through every public function and
CLI command that can meet it; the same status must come out of each.

The inputs are physical cases, not the code's output: 74L at mu 0.7 lifts off (MODEL.md predicts
it; the paper's family b_R/h_R puts the cycle-start resultant outside L1-L2); kt = 1e12 N/mm is
far above the validated stiffness range (docs/model.md); vertical flanks on both sides with
b_R/h_R = -0.5 leave the full-slip statics without a solution (the lines of action are parallel);
90R with kt/kn = 100 at mu 0.7 is the validated range's one non-converging corner; an assembly
history at 0.3 mrad never slips (the stick travel of 60sym is psi_fs = 0.67 mrad); two 10-degree
flanks leave the design rule without a root in its bracket.
"""

import contextlib
import io
import json

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.cli import main

R = jd.RESULTS

# status -> (shape flags, DamperShape, mu, Contacts): the design-level statuses
DESIGNS = {
    "ok": (["--shape", "60sym"], jd.family_shape("60sym"), 0.5, jd.Contacts()),
    "liftoff": (["--shape", "74L"], jd.family_shape("74L"), 0.7, jd.Contacts()),
    "ill_conditioned": (["--shape", "60sym", "--kt", "1e12"], jd.family_shape("60sym"), 0.5,
                        jd.Contacts(kt=1e12)),
    "singular": (["--theta-l", "90", "--theta-r", "90", "--br", "-0.5"],
                 jd.DamperShape(90.0, 90.0, -0.5), 0.5, jd.Contacts()),
    "not_converged": (["--shape", "90R", "--kn", "1e4", "--kt", "1e6"], jd.family_shape("90R"),
                      0.7, jd.Contacts(1e4, 1e6)),
}
# Statuses that belong to the design (its statics or its contacts), not to one cycle's iteration:
# every amplitude and the statics-based paths must say them too.
DESIGN_LEVEL = ("ok", "liftoff", "ill_conditioned", "singular")
STATICS_LEVEL = {"ok": "ok", "liftoff": "liftoff", "singular": "singular"}


def cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    assert code == 0, (argv, err.getvalue())
    doc = json.loads(out.getvalue())
    # every non-ok status says its cause (null for ok), also as the last warning; outside the
    # validated range (kt = 1e12 N/mm: kt/F_D = 1e9 per mm at F_D = 1000 N) it names that limit
    reason = doc["status_reason"]
    assert (reason is None) == (doc["status"] == "ok"), (argv, doc["status"], reason)
    if reason is not None:
        assert doc["warnings"][-1] == reason
    if doc["status"] == "ill_conditioned":
        assert "kt/F_D = 1e+09 per mm above the validated range" in reason, reason
    return doc


@pytest.mark.slow  # 67 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_cycle_paths_agree(name):
    _, shape, mu, contacts = DESIGNS[name]
    bc = jd.base_cycle(shape, mu, contacts)
    assert R.name_of(bc.status) == name
    assert R.name_of(jd.five_numbers(bc).status) == name
    assert R.name_of(jd.cycle_numbers(shape, mu, contacts).status) == name
    jac = jd.five_numbers_jacobian(shape, mu, contacts)
    assert R.name_of(jac.status) == name and R.name_of(jac.values.status) == name
    batch = jd.evaluate_designs(jd.stack_designs([shape, jd.family_shape("60sym")], [mu, 0.5],
                                                 [contacts, jd.Contacts()]))
    assert [R.name_of(s) for s in batch.status] == [name, "ok"]
    if name != "ok":  # a result that is not ok shows no numbers as if they were valid
        assert not bool(R.valid(bc.status))


@pytest.mark.slow  # 22 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name", DESIGN_LEVEL)
def test_amplitude_paths_agree(name):
    """From gross slip every amplitude meets the design's status. From assembly, liftoff needs an
    amplitude that reaches full slip (6 mrad): at 1.5 mrad 74L works from assembly (ok), as a
    damper whose contacts never reach the lifting full-slip state would."""
    _, shape, mu, contacts = DESIGNS[name]
    for initial in ("gross_slip", "assembly"):
        ac = jd.amplitude_cycle(shape, mu, 6.0, contacts, initial=initial)
        assert R.name_of(ac.status) == name, initial
        curves = jd.amplitude_curves(shape, mu, np.array([1.5, 6.0]), contacts, initial=initial)
        expect = ["ok" if (name, initial) == ("liftoff", "assembly") else name, name]
        assert [R.name_of(s) for s in np.ravel(curves.status)] == expect, initial


@pytest.mark.parametrize("name", sorted(STATICS_LEVEL))
def test_statics_paths_agree(name):
    flags, shape, mu, _ = DESIGNS[name]
    assert R.name_of(jd.full_slip_statics(shape, mu).status) == STATICS_LEVEL[name]
    assert cli("statics", *flags, "--mu", str(mu), "--json")["status"] == STATICS_LEVEL[name]


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_cli_commands_agree(name, tmp_path):
    flags, shape, mu, _ = DESIGNS[name]
    assert cli("cycle", *flags, "--mu", str(mu), "--json")["status"] == name
    assert cli("grad", *flags, "--mu", str(mu), "--json")["status"] == name
    if name in DESIGN_LEVEL:
        doc = cli("amplitude", *flags, "--mu", str(mu), "--psi-a", "1.5", "--json")
        assert doc["status"] == name and doc["amplitudes"][0]["status"] == name
    if name in STATICS_LEVEL:
        out = tmp_path / "section.png"
        doc = cli("section", *flags, "--mu", str(mu), "--out", str(out), "--json")
        assert doc["status"] == STATICS_LEVEL[name] and out.exists()


def test_shakedown_through_every_amplitude_path():
    shape = jd.family_shape("60sym")
    assert R.name_of(jd.amplitude_cycle(shape, 0.5, 0.3, initial="assembly").status) == "shakedown"
    curves = jd.amplitude_curves(shape, 0.5, np.array([0.3]), initial="assembly")
    assert R.name_of(np.ravel(curves.status)[0]) == "shakedown"
    doc = cli("amplitude", "--shape", "60sym", "--mu", "0.5", "--psi-a", "0.3", "--initial",
              "assembly", "--json")
    assert doc["amplitudes"][0]["status"] == "shakedown"
    assert doc["status"] == "ok"  # shakedown numbers are valid numbers (k_Im = 0)
    k = doc["amplitudes"][0]
    assert abs(k["k_im"]) <= 1e-9 * k["k_re"]  # elastic: no energy lost, to rounding


def test_unreachable_gross_slip_through_every_path_history():
    """Out-of-phase (relative rotation and horizontal motion only), 60sym at mu 0.7: pushed along
    the path from assembly, a pad opens before every pad slips, so there is no gross-slip state
    to start from (the assembly history exists: its cycle is valid)."""
    shape = jd.family_shape("60sym")
    motion = jd.interblade_motion(180.0, 20.0, 100.0, 10.0)
    gross = jd.amplitude_cycle(shape, 0.7, 5.0, motion=motion, initial="gross_slip")
    assert R.name_of(gross.status) == "unreachable" and float(gross.k_im) == 0.0
    assert bool(R.valid(jd.amplitude_cycle(shape, 0.7, 5.0, motion=motion,
                                           initial="assembly").status))
    tilted = jd.interblade_motion(175.0, 20.0, 100.0, 10.0)  # an ellipse near out-of-phase
    assert R.name_of(jd.elliptic_cycle(shape, 0.7, 5.0, tilted, initial="gross_slip").status) \
        == "unreachable"
    doc = cli("amplitude", "--shape", "60sym", "--mu", "0.7", "--psi-a", "5", "--ibpa", "180",
              "--h-c", "20", "--h-l", "10", "--initial", "gross_slip", "--json")
    assert doc["amplitudes"][0]["status"] == "unreachable" and doc["status"] == "unreachable"


def test_unseated_through_every_elliptic_path():
    """A curved-flat design (found by benchmarks/pads_vs_marcher.py) that fails the paper's
    no-liftoff rule: its full-slip statics need N = -0.16 F_D at a pad. Driven into gross slip on
    a path, that pad opens and the two left cannot hold the damper: the tract engine says
    `unseated` (the time marcher's Newton finds no equilibrium there either), the straight-path
    solver and the design check say liftoff; below gross slip (5 mrad in-phase) the cycle is
    valid. Every path reports the status, with no numbers."""
    shape = jd.DamperShape(68.45, 66.48, -0.15, 0.87)
    contacts = jd.Contacts(17900.0, 3580.0)
    assert R.name_of(jd.full_slip_statics(shape, 0.645).status) == "liftoff"
    motion = jd.interblade_motion(8.4, 22.3, 100.0, 13.0)
    ec = jd.elliptic_cycle(shape, 0.645, 15.5, motion, contacts)
    assert R.name_of(ec.status) == "unseated" and float(ec.k_im) == 0.0
    assert bool(R.stopped(ec.status)) and "unseated" in R.message(ec.status)
    sweep = jd.interblade_sweep(shape, 0.645, 15.5, [8.4, 0.0], 22.3, 13.0, contacts)
    assert [R.name_of(v) for v in sweep.status] == ["unseated", "unseated"]
    small = jd.interblade_sweep(shape, 0.645, 5.0, [8.4, 0.0], 22.3, 13.0, contacts)
    assert R.name_of(small.status[1]) == "ok"
    straight = jd.amplitude_cycle(shape, 0.645, 15.5, contacts, initial="assembly")
    assert R.name_of(straight.status) == "liftoff"
    doc = cli("amplitude", "--theta-l", "68.45", "--theta-r", "66.48", "--br=-0.15", "--bl2",
              "0.87", "--mu", "0.645", "--kn", "17900", "--kt", "3580", "--psi-a", "15.5",
              "--ibpa", "8.4", "--h-c", "22.3", "--h-l", "13", "--json")
    row = doc["amplitudes"][0]
    assert doc["status"] == row["status"] == "unseated" and row["k_im"] is None
    assert row["open_fraction"] == {"R1": None, "L1": None, "L2": None}


def test_no_root_through_the_design_rule():
    shape = jd.DamperShape(10.0, 10.0, 0.0)
    res = jd.design_br(shape, 0.7)
    assert R.name_of(res.status) == "no_root" and not bool(res.found)
    doc = cli("design-br", "--theta-l", "10", "--theta-r", "10", "--mu-max", "0.7", "--json")
    assert doc["status"] == "no_root" and doc["br_over_hr"] is None


# ------------------------------------------------------------ one order where problems meet
def _statuses_on_every_path(shape, mu, contacts):
    """The status of one design on every path kind: the Base-Cycle, a steady cycle in phase
    (both histories), on a straight out-of-phase path, on an ellipse, and the path Base-Cycle."""
    q = float(jd.LoadCase().q_star)
    straight = jd.interblade_motion(180.0, 20.0, q, 10.0)
    ellipse = jd.interblade_motion(90.0, 20.0, q, 10.0)
    return {
        "base_cycle": jd.base_cycle(shape, mu, contacts).status,
        "in_phase gross_slip": jd.amplitude_cycle(shape, mu, 1.0, contacts).status,
        "in_phase assembly": jd.amplitude_cycle(shape, mu, 1.0, contacts, initial="assembly").status,
        "straight": jd.amplitude_cycle(shape, mu, 10.0, contacts, initial="assembly",
                                       motion=straight).status,
        "ellipse": jd.elliptic_cycle(shape, mu, 10.0, ellipse, contacts).status,
        "path_base_cycle": jd.path_base_cycle(shape, mu, straight, contacts).status,
    }


def test_where_problems_meet_every_path_kind_reports_the_most_severe():
    """Ill-conditioning ranks first in the one order (jaxdamp.status.SEVERITY): a design that
    lifts off (74L at mu 0.7) or works (60sym) with a contact pair outside the validated range
    (kt/kn = 5.6e-5 < 1e-4) is ill_conditioned on every path kind, whatever else happens there;
    with the calibrated pair the same paths report the liftoff (or the ellipse's own problem)
    that the ill-conditioning hid."""
    outside = jd.Contacts(jd.REFERENCE_KN, 1.0)
    for shape in (jd.family_shape("74L"), jd.family_shape("60sym")):
        got = {k: R.name_of(s) for k, s in _statuses_on_every_path(shape, 0.7, outside).items()}
        assert set(got.values()) == {"ill_conditioned"}, got
    plain = {k: R.name_of(s) for k, s in
             _statuses_on_every_path(jd.family_shape("74L"), 0.7, jd.Contacts()).items()}
    assert plain["base_cycle"] == plain["in_phase gross_slip"] == "liftoff", plain
    assert "ill_conditioned" not in plain.values(), plain


@pytest.mark.slow  # the straight row program (tests/test_row_diagram.py's), about 1 min to build
def test_large_rotation_through_the_row():
    """A row peak that turns the platforms beyond the small-rotation model has the status
    large_rotation, with its numbers: the example disk at 200 N per blade (nodal diameter 0: the
    platforms turn by about 280 mrad; 12, out of phase: about 200 mrad relative to each other).
    At 1 and 20 N both stay within 30 mrad (at 1 N nodal diameter 12's damper sticks: shakedown,
    a valid peak). The row's worst peak is over the peaks inside the model (none at 200 N). The
    CLI's side (the numbers with the status, a line counting them, the document's status and
    reason): tests/test_cli_response_row.py::test_row_diagram_json_table_and_figure."""
    from jaxdamp.conventions import SMALL_ROTATION_MRAD
    from jaxdamp.modal_file import load_modal_family

    res = jd.row_response(jd.family_shape("60sym"), 0.5, modes=load_modal_family("example"),
                          engine_orders=[0, 12], force_n=[1.0, 20.0, 200.0], h_l_mm=10.0)
    rotation = np.asarray(res.rotation_mrad)
    assert np.all(rotation[:, 2] > SMALL_ROTATION_MRAD) and np.all(rotation[:, :2] < 30.0), rotation
    names = [[R.name_of(s) for s in row] for row in res.status]
    assert names == [["ok", "ok", "large_rotation"], ["shakedown", "ok", "large_rotation"]], names
    assert not bool(R.valid(res.status[1, 2])) and bool(R.has_numbers(res.status[1, 2]))
    assert np.all(np.isfinite(res.peaks.peak_amplitude_mm)) and np.all(res.peaks.peak_amplitude_mm > 0)
    assert list(res.worst) == [1, 1, -1]
