"""HBM-AFT on a general path (`jaxdamp.baselines.hbm_path`): its error against the exact engine
(`jaxdamp.elliptic_cycle`, an independent method: events in closed form, no sampling) within
10 / Nt^2 of max(|k_Re|, |k_Im|) and shrinking as Nt grows, on a path where no pad opens and on
one where pads open and close; the same numbers as the stepper it is built from
(`march_ellipse`); the work identity (energy dissipated at the pads = pi a^2 k_Im) to the same
order; the statuses that keep a wrong number from passing silently (singular where Newton finds
no equilibrium at a sample, not_converged where the last period is not periodic); input checks.

The tolerance: the samples' rectangle rule is exact for the harmonics of a sampled loop, the
loop itself carries the marcher's second-order error (its kinks fall between samples), so the
error is C / Nt^2; C is below 10 on these cases (measured 0.4-6, 2026-11-26)."""

import warnings

import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.baselines import hbm_aft_path, march_ellipse

from helpers import assert_tree_allclose, count_compiles

CONTACTS = jd.Contacts(17900.0, 3580.0)
CURVED_FLAT = jd.family_shape("60sym")
WEDGE = CURVED_FLAT._replace(br_over_hr=0.0, br2_over_hr=0.8)  # 60/60, R1, R2 | L1, L2


def path(phi_deg):
    """The paper's Fig. 4 kinematics: h_C = 20 mm, q* = 100 mm, h_L = 10 mm."""
    return jd.interblade_motion(phi_deg, 20.0, 100.0, 10.0)


def tolerance(n_time):
    return 10.0 / n_time ** 2


def name(r):
    return jd.RESULTS.name_of(r.status)


BAD = [
    (dict(n_time=7), r"^n_time must be an even integer in \[4, inf\); got 7$"),
    (dict(n_time=2), r"^n_time must be"),
    (dict(n_periods=1), r"^n_periods must be"),
    (dict(initial="rest"), r"^initial must be one of assembly, gross_slip; got 'rest'$"),
    (dict(amplitude_mrad=0.0), r"^amplitude_mrad must be in \(0, 10000\] mrad"),
    (dict(mu=-0.5), r"^mu must be in"),
    (dict(motion=(0.0, 0.1, 0.0)), r"^motion must be a jaxdamp.Motion"),
    (dict(n_load=0), r"^n_load must be"),
    (dict(max_newton=0), r"^max_newton must be"),
]


@pytest.mark.parametrize("change, message", BAD)
def test_a_bad_input_names_its_parameter_before_any_compile(change, message):
    args = dict(shape=WEDGE, mu=0.5, amplitude_mrad=2.0, motion=path(90), contacts=CONTACTS)
    args.update(change)
    with count_compiles() as compiled:
        with pytest.raises(ValueError, match=message):
            hbm_aft_path(**args)
    assert compiled == []


def test_statuses_and_the_work_identity_on_the_wedge():
    """One compiled program for every sampling (n_time and n_periods are traced). Where pads open
    (phi 90 deg, 10 mrad) 64 samples leave the damper without equilibrium at some samples: the
    status says singular (never a silent number); at 256 and more the cycle is valid and the
    pads' energy matches pi a^2 k_Im to 10 / Nt^2. Three periods from assembly at 2 mrad are not
    periodic (the wedge settles over several periods): not_converged, ok at eight. Below slip
    (0.02 mrad) the loop is linear: k_Im = 0 and k_Re the same at any sampling."""
    with count_compiles() as compiled:
        coarse = hbm_aft_path(WEDGE, 0.5, 10.0, path(90), CONTACTS, n_time=64, initial="assembly")
        fine = [hbm_aft_path(WEDGE, 0.5, 10.0, path(90), CONTACTS, n_time=n, initial="assembly")
                for n in (256, 1024)]
    assert [c for c in compiled if "hbm" in c] == ["jit(hbm_aft_path_kernel)"]
    assert name(coarse) == "singular" and int(coarse.newton_failures) > 0
    for n, r in zip((256, 1024), fine):
        assert name(r) == "ok" and int(r.newton_failures) == 0
        assert float(r.open_fraction[0]) > 0.3  # R1 is open over a third of the period
        assert_tree_allclose(np.sum(np.asarray(r.energy)), np.asarray(float(r.work)),
                             rtol=tolerance(n), atol=0.0)

    short = hbm_aft_path(WEDGE, 0.5, 2.0, path(90), CONTACTS, n_time=64, n_periods=3,
                         initial="assembly")
    long = hbm_aft_path(WEDGE, 0.5, 2.0, path(90), CONTACTS, n_time=64, n_periods=8,
                        initial="assembly")
    assert name(short) == "not_converged" and 1e-9 < float(short.periodicity) < 1e-3
    assert name(long) == "ok" and float(long.periodicity) <= 1e-9

    stuck = [hbm_aft_path(WEDGE, 0.5, 0.02, path(90), CONTACTS, n_time=n, initial="assembly")
             for n in (16, 256)]
    assert all(name(r) == "ok" for r in stuck)
    k_re = float(stuck[0].k_re)
    assert_tree_allclose(np.asarray([float(r.k_re) for r in stuck]), np.full(2, k_re),
                         rtol=1e-12, atol=0.0)
    assert_tree_allclose(np.asarray([float(r.k_im) for r in stuck]), np.zeros(2),
                         rtol=0.0, atol=1e-12 * k_re)


@pytest.mark.slow  # 12 + 13 worker-s alone (2026-11-26, load 1.4; 19 + 13 at load 5): the engine's programs
@pytest.mark.parametrize("shape, mu, phi, amplitude, samplings", [
    (CURVED_FLAT, 0.5, 90.0, 2.0, (64, 256, 1024)),  # no pad opens
    (WEDGE, 0.5, 90.0, 10.0, (256, 1024)),  # R1 open 36 %, R2 10 % of the period
], ids=["60sym-closed", "wedge-opening"])
def test_converges_to_the_engine(shape, mu, phi, amplitude, samplings):
    """k within 10 / Nt^2 of the engine's (relative to max |k_Re|, |k_Im|), the error at least
    halving with each fourfold Nt (measured 3.6x and 9.4x on 60sym, 13x on the wedge), and the
    open fractions within two samples."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        ec = jd.elliptic_cycle(shape, mu, amplitude, path(phi), CONTACTS, initial="assembly")
    assert name(ec) == "ok"
    exact = np.asarray([float(ec.k_re), float(ec.k_im)])
    scale = float(np.max(np.abs(exact)))
    errors = []
    for n in samplings:
        r = hbm_aft_path(shape, mu, amplitude, path(phi), CONTACTS, n_time=n, initial="assembly")
        assert name(r) == "ok"
        got = np.asarray([float(r.k_re), float(r.k_im)])
        assert_tree_allclose(got, exact, rtol=0.0, atol=tolerance(n) * scale, err_msg=f"Nt={n}")
        assert_tree_allclose(np.asarray(r.open_fraction), np.asarray(ec.open_fraction),
                             rtol=0.0, atol=2.0 / n)
        errors.append(float(np.max(np.abs(got - exact))))
    assert all(b < a / 2 for a, b in zip(errors, errors[1:])), errors


@pytest.mark.slow  # 9 worker-s alone (2026-11-26, load 1.4; 12 at load 5): march_ellipse's program, and ours
def test_is_the_stepper_it_reuses():
    """HBM-AFT from assembly with four periods is `march_ellipse` (its steps, its history, its
    harmonics): the same k, energies and fractions to rounding."""
    motion = path(90)
    tm = march_ellipse(CURVED_FLAT, 0.5, 2.0, motion, CONTACTS, n_steps=256, periods=4)
    r = hbm_aft_path(CURVED_FLAT, 0.5, 2.0, motion, CONTACTS, n_time=256, n_periods=4,
                     initial="assembly")
    assert name(r) == name(tm) == "ok"
    scale = max(abs(float(tm.k_re)), abs(float(tm.k_im)))
    assert_tree_allclose(jnp.stack([r.k_re, r.k_im]), jnp.stack([tm.k_re, tm.k_im]), rtol=0.0,
                         atol=1e-11 * scale)
    assert_tree_allclose(r.energy, tm.energy, rtol=0.0, atol=1e-11 * float(r.work))
    assert_tree_allclose((r.slip_fraction, r.open_fraction), (tm.slip_fraction, tm.open_fraction),
                         rtol=0.0, atol=0.0)
