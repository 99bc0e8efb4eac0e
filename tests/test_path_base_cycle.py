"""The Base-Cycle on any straight path and for a wedge (`jaxdamp.path_base_cycle`): on the paper's
in-phase path it is the paper's Base-Cycle (reached another way: assembly and a move to gross slip,
the elliptic engine's cycle), above a_BC gross slip erases the history, the energy balances."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_cycle
from jaxdamp.ellipse import elliptic_cycle
from jaxdamp.geometry import is_wedge
from jaxdamp.motion import in_phase_motion, interblade_motion
from jaxdamp.params import Contacts
from jaxdamp.path_base_cycle import path_base_cycle

from helpers import assert_tree_allclose

PAPER_CONTACTS = Contacts(17900.0, 3600.0)
WEDGE = jd.family_shape("60sym")._replace(br_over_hr=0.0, br2_over_hr=0.8)
OUT_OF_PHASE = interblade_motion(180.0, 20.0, 100.0, 10.0)


def steady(shape, a, motion, initial):
    """The steady cycle at a from a history: a wedge on the elliptic engine, the curved-flat damper
    on the straight-path solver (`amplitude_cycle`, another road than the Base-Cycle's)."""
    if is_wedge(shape):
        return elliptic_cycle(shape, 0.5, a, motion, initial=initial)
    return amplitude_cycle(shape, 0.5, a, initial=initial, motion=motion)


def numbers(p):
    return jnp.stack([p.a_fs, p.k_re_fs, p.a_bc, p.k_re_bc, p.k_im_bc])


@pytest.mark.parametrize("name,mu", [("74R", 0.7), ("60sym", 0.5), ("74L", 0.3)])
def test_in_phase_it_is_the_papers_base_cycle(name, mu):
    shape = jd.family_shape(name)
    paper_route = jd.five_numbers(jd.base_cycle(shape, mu, PAPER_CONTACTS))
    p = path_base_cycle(shape, mu, in_phase_motion(100.0), PAPER_CONTACTS)
    assert jd.RESULTS.name_of(p.status) == "ok" and int(p.pairs) == 1
    assert_tree_allclose(numbers(p), jnp.stack(paper_route[:5]), rtol=1e-9, atol=0.0)
    if name == "74R":  # Table B4.1: psi_BC = 3.270 mrad (the paper's rounding of its own model)
        assert abs(float(p.a_bc) / 3.270 - 1.0) < 0.02


@pytest.mark.parametrize("shape,motion", [
    (jd.family_shape("60sym"), OUT_OF_PHASE),
    # two more elliptic programs (two histories, four pads): 25 worker-s
    pytest.param(WEDGE, in_phase_motion(100.0, 10.0), marks=pytest.mark.slow)],
                         ids=["curved-flat out-of-phase", "wedge in-phase"])
def test_above_a_bc_gross_slip_erases_the_history(shape, motion):
    p = path_base_cycle(shape, 0.5, motion)
    assert jd.RESULTS.name_of(p.status) == "ok"
    assert 0.0 < float(p.a_fs) <= float(p.a_bc)
    # The Base-Cycle's energy is the modal forces' work: sum of int T d(slip) = pi a^2 k_Im / 1e3.
    c = p.cycle
    assert_tree_allclose(jnp.sum(c.energy), c.work, rtol=1e-10, atol=1e-12 * float(p.k_re_bc))
    a = 1.25 * float(p.a_bc)
    from_gross, from_assembly = (steady(shape, a, motion, h) for h in ("gross_slip", "assembly"))
    scale = abs(float(from_gross.k_re)) + abs(float(from_gross.k_im))
    assert_tree_allclose((from_assembly.k_re, from_assembly.k_im),
                         (from_gross.k_re, from_gross.k_im), rtol=0.0, atol=1e-9 * scale)


def test_a_wedge_in_phase_slips_all_at_once():
    """The 60/60 wedge's four pads reach their friction limits in the same event on the in-phase
    stroke: the first tract from gross slip runs to gross slip the other way, so a_fs = a_BC and the
    Base-Cycle is elastic: its Fourier k_Re (the elliptic engine's integral over the period) is the
    first tract's slope k_Re,fs, and k_Im and every slip fraction are zero."""
    p = path_base_cycle(WEDGE, 0.5, in_phase_motion(100.0, 10.0))
    assert jd.RESULTS.name_of(p.status) == "ok"
    assert_tree_allclose(p.a_fs, p.a_bc, rtol=1e-12, atol=0.0)
    assert_tree_allclose(p.k_re_bc, p.k_re_fs, rtol=1e-10, atol=0.0)
    assert abs(float(p.k_im_bc)) <= 1e-10 * float(p.k_re_bc)
    assert np.all(np.asarray(p.cycle.slip_fraction) == 0.0)


def test_a_wedge_out_of_phase_has_none():
    """60/60 wedge at 180 deg: R2 and L2 open, R1 and L1 cannot both slip (two pads, three degrees
    of freedom) and take turns along the whole move: no half ends in gross slip."""
    p = path_base_cycle(WEDGE, 0.5, OUT_OF_PHASE)
    assert jd.RESULTS.name_of(p.status) == "unreachable"
    values = np.asarray(numbers(p))
    assert np.all(values == 0.0) and np.all(np.asarray(p.spans) == 0.0)


def test_an_ellipse_is_refused():
    with pytest.raises(ValueError, match="straight path.*elliptic_cycle"):
        path_base_cycle(jd.family_shape("60sym"), 0.5, interblade_motion(90.0, 20.0, 100.0, 10.0))


# 91 (fwd) and 133 (rev) worker-s, nearly all compiling the derivative programs of the elliptic
# engine's masked scan (2026-11-27), like the elliptic cycle's own derivative test (test_ellipse)
@pytest.mark.slow
@pytest.mark.parametrize("mode", ["fwd", "rev"])
def test_derivatives_match_central_differences(mode):
    """d(a_BC, k_Re,BC, k_Im,BC)/d(mu, kn) of 60sym out of phase, through the events (forward mode
    and reverse mode: the kernel's masked-scan derivative program), against central differences
    of the values (no pad changes its sequence of states within the step)."""
    from jaxdamp.params import prepare_inputs
    from jaxdamp.path_base_cycle import path_base_cycle_kernel

    from helpers import fd_jvp

    shape, _, _, load = prepare_inputs(jd.family_shape("60sym"), 0.5, Contacts(), jd.LoadCase())

    def outputs(x):
        mu, kn = x[0], x[1]
        p = path_base_cycle_kernel(shape, mu, Contacts(kn, 3492.1), load, OUT_OF_PHASE)
        return jnp.stack([p.a_bc, p.k_re_bc, p.k_im_bc])

    x = jnp.array([0.3, 20246.3])
    assert jd.RESULTS.name_of(path_base_cycle_kernel(
        shape, x[0], Contacts(x[1], 3492.1), load, OUT_OF_PHASE).status) == "ok"
    if mode == "fwd":
        ad = jax.jacfwd(outputs)(x)
    else:
        ad = jax.jacrev(outputs)(x)
    for k, (v, h) in enumerate(((jnp.array([1.0, 0.0]), 1e-6), (jnp.array([0.0, 1.0]), 1e-2))):
        fd = fd_jvp(lambda y: np.asarray(outputs(jnp.asarray(y))), x, v, h)
        assert_tree_allclose(ad[:, k], fd, rtol=1e-5, atol=1e-9 * np.abs(fd).max())
