"""`path_gradient`: a path cycle's k_Re, k_Im, energy per pad and work, and their derivatives with
respect to the design and the path. The derivatives are checked against float64 central
differences of the elliptic kernel's value pass (while loops that choose each tract's set: no
replay, no derivative code), forward against reverse mode, and bad inputs are refused before any compile."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose, count_compiles
from jaxdamp.motion import as_ellipse
from jaxdamp.params import prepare_inputs
from jaxdamp.path_gradients import PathOutputs

jd.enable_x64()

SHAPE = jd.family_shape("60sym")
WEDGE = jd.DamperShape(60.0, 60.0, 0.0, 0.8, None, 0.8)
ELLIPSE = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
STRAIGHT = jd.interblade_motion(180.0, 20.0, 100.0, 10.0)
F_D = float(jd.LoadCase().F_D)
KERNEL = jax.jit(jd.elliptic_kernel, static_argnames=("initial", "loop"))


@pytest.mark.parametrize("call, message", [
    (lambda: jd.path_gradient(SHAPE, 0.5, 0.0, ELLIPSE), r"^amplitude_mrad must be in \(0, 10000\]"),
    (lambda: jd.path_gradient(SHAPE, 0.5, None, ELLIPSE), r"^amplitude_mrad must be given"),
    (lambda: jd.path_gradient(SHAPE, 0.5, 2.0, None), r"^motion must be given"),
    (lambda: jd.path_gradient(SHAPE, None, 2.0, ELLIPSE), r"^mu is required: the friction coefficient, in \(0, 5\]$"),
    (lambda: jd.path_gradient(SHAPE, 7.0, 2.0, ELLIPSE), r"^mu must be in \(0, 5\]"),
    (lambda: jd.path_gradient(SHAPE, 0.5, 2.0, ELLIPSE, mode="central"), r"^mode must be one of fwd, rev"),
    (lambda: jd.path_gradient(SHAPE, 0.5, 2.0, ELLIPSE, initial="explicit"),
     r"^initial must be one of assembly, gross_slip"),
    (lambda: jd.path_gradient(SHAPE, 0.5, 2.0, ELLIPSE, max_periods=0), r"^max_periods must be"),
    (lambda: jd.path_gradient(jd.Design(SHAPE, 0.5), 0.5, 2.0, ELLIPSE), r"^give either a Design"),
])
def test_a_bad_input_names_its_parameter_before_any_compile(call, message):
    with count_compiles() as compiled:
        with pytest.raises(ValueError, match=message):
            call()
    assert compiled == []


def test_float32_is_refused_before_any_compile():
    jax.config.update("jax_enable_x64", False)
    try:
        with count_compiles() as compiled:
            with pytest.raises(jd.Float64Required, match="enable_x64"):
                jd.path_gradient(SHAPE, 0.5, 2.0, ELLIPSE)
        assert compiled == []
    finally:
        jax.config.update("jax_enable_x64", True)


def test_the_repr_names_the_status_and_units():
    values = PathOutputs(np.float64(1.0e4), np.float64(1.5e3), np.zeros(3), np.float64(2.0))
    d = jd.Design(SHAPE, np.float64(-2.0e3))
    motion = jd.Motion(np.zeros(3), np.float64(-0.8), np.zeros(3))
    g = jd.PathGradient(values, PathOutputs(d, d, d, d),
                        PathOutputs(motion, motion, motion, motion), np.int32(0))
    text = repr(g)
    assert text.startswith("PathGradient(status=ok, k_re=10000 N mm/mrad, k_im=1500 N mm/mrad; ")
    assert "d k_im/d mu=-2000 N mm/mrad" in text and "d k_im/d h_l=-0.8 N mm/mrad per mm" in text
    assert repr(values) == ("PathOutputs(k_re=10000 N mm/mrad, k_im=1500 N mm/mrad, "
                            "energy=[0, 0, 0] N mm, work=2 N mm)")
    assert repr(g.d_design) == ("PathOutputs(k_re=<Design>, k_im=<Design>, energy=<Design>, "
                                "work=<Design>)")


def _central(f, x, h):
    """(central difference, smooth) of a vector f: smooth where the two one-sided differences
    agree within 1e-4 of their size (no switch of the cycle's sequence of events within the step)."""
    f0, fp, fm = f(x), f(x + h), f(x - h)
    up, down = (fp - f0) / h, (f0 - fm) / h
    smooth = np.max(np.abs(up - down)) <= 1e-4 * max(np.max(np.abs(up)), np.max(np.abs(down)),
                                                      1e-12)
    return (fp - fm) / (2.0 * h), smooth


@pytest.mark.slow  # four derivative programs (two histories, two modes) and the checked cycle's
def test_derivatives_agree_with_central_differences_and_between_modes():
    """On the curved-flat damper and a wedge, an elliptic (phi 90 deg) and a straight (phi 180
    deg) path, from assembly and from gross slip: d k_Im and d energy by mu, theta_L, F_D, kn and
    the path's h_L and X_hat real part against central differences (step 1e-6 of the value) where
    smooth, at least 20 of them; forward and reverse mode give the same derivatives."""
    rng = np.random.default_rng(60)
    checked = 0
    for shape in (SHAPE, WEDGE):
        for motion in (ELLIPSE, STRAIGHT):
            for initial in ("assembly", "gross_slip"):
                mu, amplitude = rng.uniform(0.35, 0.65), rng.uniform(1.0, 8.0)
                kw = dict(contacts=jd.Contacts(17900.0, 3580.0), initial=initial)
                g = jd.path_gradient(shape, mu, amplitude, motion, **kw)
                if not jd.RESULTS.valid(int(g.status)):
                    continue
                r = jd.path_gradient(shape, mu, amplitude, motion, mode="rev", **kw)
                assert_tree_allclose((r.values, r.d_design, r.d_motion),
                                     (g.values, g.d_design, g.d_motion), rtol=1e-9, atol=1e-9)

                def cycle(mu=mu, shape=shape, kn=17900.0, F_D=F_D, motion=motion):
                    # The value pass alone (while loops, no derivative code); a straight path as
                    # an ellipse of zero width, as path_gradient runs it.
                    design = prepare_inputs(shape, mu, jd.Contacts(kn, 3580.0),
                                            jd.LoadCase(F_D=F_D), wedge_ok=True)
                    path = jd.Motion(*(jnp.asarray(v, float) for v in as_ellipse(motion)))
                    c = KERNEL(*design, jnp.asarray(amplitude), path, initial=initial,
                               loop="while")
                    return np.array([float(c.k_im), *np.asarray(c.energy)])

                moved = lambda k, v: motion._replace(  # noqa: E731
                    direction=np.asarray(motion.direction, float) + v * np.eye(3)[k])
                variables = [
                    ("mu", lambda v: cycle(mu=v), mu, g.d_design.k_im.mu, g.d_design.energy.mu),
                    ("theta_l", lambda v: cycle(shape=shape._replace(theta_l=v)),
                     shape.theta_l, g.d_design.k_im.shape.theta_l,
                     g.d_design.energy.shape.theta_l),
                    ("F_D", lambda v: cycle(F_D=v), F_D, g.d_design.k_im.load.F_D,
                     g.d_design.energy.load.F_D),
                    ("kn", lambda v: cycle(kn=v), 17900.0, g.d_design.k_im.contacts.kn,
                     g.d_design.energy.contacts.kn),
                    ("h_l", lambda v: cycle(motion=motion._replace(h_l=v)), float(motion.h_l),
                     g.d_motion.k_im.h_l, g.d_motion.energy.h_l),
                    ("direction_u", lambda v: cycle(motion=moved(0, v)), 0.0,
                     g.d_motion.k_im.direction[0], g.d_motion.energy.direction[:, 0]),
                ]
                # On the gradient's scale: each derivative times its variable's size (the change
                # of k_Im and the energies for a relative change of it), as in
                # benchmarks/path_derivatives.py: a derivative thousands of times smaller than the
                # others is not checked to 1e-6 of itself (the cycle's closure, 1e-9 of F_D,
                # bounds the central difference's accuracy).
                rows = []
                for name, f, x, dk, de in variables:
                    size = max(abs(x), 1e-2)
                    cd, smooth = _central(f, x, 1e-6 * size)
                    rows.append((name, size * np.array([float(dk), *np.asarray(de)]), size * cd,
                                 smooth))
                scale = max(np.max(np.abs(cd)) for _, _, cd, _ in rows)
                for name, got, cd, smooth in rows:
                    if smooth:
                        assert np.max(np.abs(got - cd)) <= 1e-6 * scale, (
                            shape, motion, initial, name, got, cd)
                        checked += 1
    assert checked >= 20


def _sequence(c):
    """The steady period's sequence of state sets (one tuple per tract that ran)."""
    active = np.asarray(c.period.active)
    return tuple(map(tuple, np.asarray(c.period.state)[active].tolist()))


@pytest.mark.slow  # a derivative program and some 60 value passes
def test_at_a_switch_the_derivative_is_the_one_sided_derivative_of_the_sequence_taken():
    """60sym at phi 90 deg, 5 mrad from assembly: between mu 0.45 and 0.48 the order in which L1
    and L2 start to slip while R1 slips swaps (pads R1, L1, L2: sets 100, 101, 111 below the
    switch; 100, 110, 111 above it), found by bisection on the steady period's sequence. On
    either side of the switch, where the tract between the two events is some 1e-8 rad long,
    the derivative of k_Im and of the energy per pad with respect to mu is the one-sided
    derivative (second-order differences of the value pass, into that side) of the sequence the
    cycle took there. Between the two sides lies a band about 4e-10 wide where the engine takes
    the two events as one (a tie within its tolerance), whose derivative is that merged
    sequence's (docs/motions.md, "Derivatives"): the points checked are 1e-8 outside it."""
    design = lambda mu: prepare_inputs(SHAPE, mu, jd.Contacts(17900.0, 3580.0), jd.LoadCase())  # noqa: E731
    path = jd.Motion(*(jnp.asarray(v, float) for v in as_ellipse(ELLIPSE)))

    def cycle(mu):
        return KERNEL(*design(mu), jnp.asarray(5.0), path, initial="assembly", loop="while")

    def values(mu):
        c = cycle(mu)
        return np.array([float(c.k_im), *np.asarray(c.energy)])

    below = _sequence(cycle(0.45))
    assert _sequence(cycle(0.48)) != below
    lo, hi = 0.45, 0.48
    while hi - lo > 4 * np.spacing(hi):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _sequence(cycle(mid)) == below else (lo, mid)
    # Above the switch, past the band of the merged events: the first point whose sequence has
    # the third tract's other successor (ten tracts, as below).
    above = hi
    for _ in range(100):
        if len(_sequence(cycle(above))) == len(below):
            break
        above += 1e-10
    assert above - lo < 1e-8
    sequences = set()
    for mu0, side in ((lo - 1e-8, -1.0), (above + 1e-8, +1.0)):
        c = cycle(mu0)
        taken = _sequence(c)
        sequences.add(taken)
        assert jd.RESULTS.name_of(int(c.status)) == "ok" and len(taken) == 10
        # Near the switch: the tract between the two events is short.
        assert np.min(np.asarray(c.period.dp)[np.asarray(c.period.active)]) < 1e-7
        g = jd.path_gradient(SHAPE, mu0, 5.0, ELLIPSE, jd.Contacts(17900.0, 3580.0))
        assert jd.RESULTS.name_of(int(g.status)) == "ok"
        got = np.array([float(g.d_design.k_im.mu), *np.asarray(g.d_design.energy.mu)])
        h = 1e-5
        assert _sequence(cycle(mu0 + 2 * side * h)) == taken  # the differences stay on its side
        f0, f1, f2 = values(mu0), values(mu0 + side * h), values(mu0 + 2 * side * h)
        one_sided = (-3.0 * f0 + 4.0 * f1 - f2) / (2.0 * side * h)
        assert np.max(np.abs(got - one_sided)) <= 1e-6 * np.max(np.abs(one_sided)), (
            side, got, one_sided)
    assert len(sequences) == 2 and below in sequences
