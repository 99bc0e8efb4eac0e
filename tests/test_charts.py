"""transitions_chart: one contact-state chart for every cycle the library computes (issue 62:
it was written twice, and a third time for the ellipse)."""

import pytest

import jaxdamp as jd

jd.enable_x64()

SHAPE = jd.family_shape("60sym")


def test_the_base_cycle_chart_is_the_papers_table_2():
    """60sym at mu 0.5: tracts 0-A ... with every contact stick / slip / back-slide, and the
    forward and backward halves' travel adding up to twice psi_BC's (the five numbers)."""
    bc = jd.base_cycle(SHAPE, 0.5)
    rows = jd.transitions_chart(bc)
    assert rows[0]["tract"] == "0-A" and {r["half"] for r in rows} == {"forward", "backward"}
    assert all(r[c] in ("stick", "slip", "back-slide") for r in rows for c in ("R1", "L1", "L2"))
    travel = sum(r["dv_mm"] for r in rows)
    psi_bc = float(jd.five_numbers(bc).psi_bc)  # mrad of half the longer half's travel
    q = float(jd.LoadCase().q_star)
    assert travel == pytest.approx(4.0 * psi_bc * q / 1e3, rel=1e-9)


def test_an_amplitude_cycle_chart_covers_its_travel():
    ac = jd.amplitude_cycle(SHAPE, 0.5, 1.0)
    rows = jd.transitions_chart(ac)
    q = float(jd.LoadCase().q_star)
    for half in ("forward", "backward"):  # each half runs the whole travel 2 psi_a q*/1e3
        assert sum(r["dv_mm"] for r in rows if r["half"] == half) == pytest.approx(2.0 * q / 1e3)


def test_an_elliptic_chart_covers_the_period_and_names_every_pad():
    motion = jd.interblade_motion(90.0, 10.0, float(jd.LoadCase().q_star), 30.0)
    ec = jd.elliptic_cycle(SHAPE, 0.5, 2.0, motion)
    assert jd.RESULTS.valid(ec.status)
    rows = jd.transitions_chart(ec)
    assert rows[0]["tau_start_deg"] == pytest.approx(0.0, abs=1e-9)
    assert rows[-1]["tau_end_deg"] == pytest.approx(360.0)
    assert [a["tau_end_deg"] for a in rows[:-1]] == pytest.approx([b["tau_start_deg"] for b in rows[1:]])
    assert all(set(r) >= {"R1", "L1", "L2"} for r in rows)


def test_anything_else_is_refused_by_name():
    with pytest.raises(TypeError, match="BaseCycle, AmplitudeCycle or EllipticCycle; got dict"):
        jd.transitions_chart({})


def test_the_old_ellipse_name_still_works_with_a_deprecation():
    with pytest.warns(DeprecationWarning, match="jaxdamp.transitions_chart"):
        old = jd.elliptic_transitions_chart
    assert old is jd.transitions_chart
