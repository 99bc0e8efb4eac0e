"""HBM-AFT on any platform path: the conventional baseline for `jaxdamp.elliptic_cycle`.

`hbm_aft` is the friction-damper codes' alternating frequency-time step on the paper's in-phase
path. This is the same step on a general path X(tau) = a (X_r cos tau - X_i sin tau) (an
ellipse, `interblade_motion` at a phase angle other than 0 or 180 degrees, or a straight path as
an ellipse of zero width), for both dampers (curved-flat R1 | L1, L2 and the wedge R1, R2 |
L1, L2) and with pads that open and close: the history (`ellipse_march`: assembly, or from
assembly a gross-slip move), then n_periods periods of the path at n_time uniform samples per
period, each sample the damper's quasi-static equilibrium by Newton with the contacts' return
mapping (`ellipse_march.path_step`: no events, no closed forms), and the first harmonic of the
modal forces of the last period (the rectangle rule on the uniform samples: the DFT's first bin,
as an FFT gives it). The samples are summed as they are made (no sample arrays), so n_time and
n_periods are traced: one compiled program serves every sampling.

Periodicity is measured, not assumed: the largest change over the last period of the pads'
forces at its end (units of F_D) and of k (relative to max |k_Re|, |k_Im|). Above PERIODIC_TOL
the status is not_converged (more periods needed); a sample where Newton found no equilibrium
(e.g. a damper left as a mechanism on two slipping pads when the others open) makes it singular.
An open pad is part of a valid cycle (`open_fraction`), not liftoff.

The gross-slip history is `march_ellipse`'s: a straight move of GROSS_SLIP_TRAVEL_MM beyond the
amplitude. On the wedge a pad may open during that move and its gap keep growing, so that the
cycle after it depends on the move's length (60/60 wedge, mu 0.5, phi 60 deg, 2 mrad: k_Im 320,
8890, 10700, 10540 N mm/mrad after 5, 1, 0.2, 0.05 mm; `elliptic_cycle`, which stops the move
at gross slip, gives 2413): compare wedges from assembly.

Conventions as `elliptic_cycle`'s: k in N mm/mrad with M ~ a (k_Re cos tau - k_Im sin tau)
along the path's modal force, energies in N mm per cycle.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from .._validate import check_int, check_range
from ..conventions import travel_mm
from ..motion import Motion, as_ellipse, validate_motion
from ..params import Contacts, LoadCase, prepare_inputs
from ..status import RESULTS, number_repr, status_repr
from .ellipse_march import HISTORIES, path_model, path_start, path_step
from .hbm import PERIODIC_TOL
from .timemarch import MAX_NEWTON


class HBMPathResult(NamedTuple):
    """HBM-AFT on a path at one amplitude a (mrad): first-harmonic k_Re, k_Im (N mm/mrad) of the
    last period, its energy per pad (N mm, trapezoids of T d(slip)), the work pi a^2 k_Im (N mm),
    the fractions of its samples in which each pad slips and is open, the periodicity reached,
    Newton failures and a `jaxdamp.RESULTS` status. Per-pad arrays in `geometry.pad_names` order."""

    k_re: jnp.ndarray  # N mm/mrad
    k_im: jnp.ndarray
    energy: jnp.ndarray  # (P,) N mm per cycle
    work: jnp.ndarray  # N mm per cycle, pi a^2 k_Im
    slip_fraction: jnp.ndarray  # (P,)
    open_fraction: jnp.ndarray  # (P,)
    # max of the forces' change over the last period (units of F_D) and of k's change (relative
    # to max |k_Re|, |k_Im|)
    periodicity: jnp.ndarray
    newton_failures: jnp.ndarray
    # RESULTS code: singular (Newton failed at a sample), else not_converged (periodicity above
    # PERIODIC_TOL), else ok
    status: jnp.ndarray

    def __repr__(self) -> str:
        return (f"HBMPathResult(status={status_repr(self.status)}, "
                f"k_re={number_repr(self.k_re, 'N mm/mrad')}, "
                f"k_im={number_repr(self.k_im, 'N mm/mrad')})")


@partial(jax.jit, static_argnames=("initial", "n_load", "max_newton"))
def hbm_aft_path_kernel(shape, mu, contacts, load, amplitude, motion: Motion, n_time, n_periods,
                        initial: str = "assembly", n_load: int = 16,
                        max_newton: int = MAX_NEWTON) -> HBMPathResult:
    """`hbm_aft_path` on prepared inputs: amplitude (mrad) and the motion's arrays (a straight
    path as a zero quadrature); n_time (even) and n_periods (>= 2) may be traced integers.
    Unchecked, traceable (jit, vmap)."""
    pm = path_model(shape, mu, contacts, load, motion)
    s_a = travel_mm(amplitude, load.q_star)
    m0, s, shift, fails = path_start(pm, s_a, initial, n_time, n_load, max_newton)
    h = 2.0 * jnp.pi / n_time
    zeros = jnp.zeros_like(pm.m.kn)

    def sample(j, tau0, c):
        """The sample at tau0 + j h from the previous one's state, its numbers added to the sums."""
        (q, p, _, T), (acc, energy, n_slip, n_open, fails) = c
        tau = tau0 + h * j
        (q, p_new), (N, T_new, _, M_r, M_i, ok, opened, slipping) = path_step(
            pm, m0, s_a, shift, (q, p), tau, max_newton)
        acc = acc + jnp.exp(-1j * tau) * jnp.stack([M_r, M_i])
        energy = energy - load.F_D * 0.5 * (T_new + T) * (p_new - p)  # trapezoid of T d(slip)
        return (q, p_new, N, T_new), (acc, energy, n_slip + slipping, n_open + opened,
                                      fails + jnp.where(ok, 0, 1))

    def run(carry, first, last, tau0, fails):
        sums = (jnp.zeros(2, complex), zeros, zeros, zeros, fails)
        return jax.lax.fori_loop(first, last + 1, lambda j, c: sample(j, tau0, c), (carry, sums))

    carry = (s.q, s.p, s.N, s.T)
    if initial == "assembly":  # the path from tau = pi, where the straight move ended, to 2 pi
        carry, (*_, fails) = run(carry, 1, n_time // 2, jnp.pi, fails)

    def period(_, c):
        carry, k, _, _, fails = c
        new, (acc, energy, n_slip, n_open, fails) = run(carry, 1, n_time, 0.0, fails)
        k_new = (acc[0] - 1j * acc[1]) * h / (jnp.pi * amplitude)
        scale = jnp.maximum(jnp.maximum(jnp.abs(k_new.real), jnp.abs(k_new.imag)), 1e-300)
        # The change over this period: of the forces at tau = 2 pi (units of F_D), and of k.
        change = jnp.maximum(jnp.maximum(jnp.max(jnp.abs(new[2] - carry[2])),
                                         jnp.max(jnp.abs(new[3] - carry[3]))),
                             jnp.abs(k_new - k) / scale)
        return new, k_new, change, (energy, n_slip / n_time, n_open / n_time), fails

    init = (carry, jnp.zeros((), complex), jnp.asarray(jnp.inf), (zeros, zeros, zeros), fails)
    _, k, periodicity, (energy, slip_fraction, open_fraction), fails = jax.lax.fori_loop(
        0, n_periods, period, init)
    periodic = periodicity <= PERIODIC_TOL
    return HBMPathResult(k.real, k.imag, energy, jnp.pi * amplitude ** 2 * k.imag * 1e-3,
                         slip_fraction, open_fraction, periodicity, fails,
                         RESULTS.first({RESULTS.singular: fails > 0,
                                       RESULTS.not_converged: ~periodic}))


def hbm_aft_path(shape, mu, amplitude_mrad, motion: Motion, contacts: Contacts = Contacts(),
                 load: LoadCase = LoadCase(), *, n_time: int = 256, n_periods: int = 3,
                 initial: str = "assembly", n_load: int = 16,
                 max_newton: int = MAX_NEWTON) -> HBMPathResult:
    """k_Re, k_Im (N mm/mrad) at amplitude a (mrad) on the path `motion` (elliptic or straight)
    by HBM-AFT (module docstring): the history `initial` ("assembly", or "gross_slip", as
    `hbm_aft`'s start at the top of the motion; module docstring on the wedge), then n_periods
    periods at n_time (even) samples per period, the first harmonic of the last one. shape:
    curved-flat or wedge; pads may open. Inputs are checked here (ValueError naming the parameter
    and its range); the status says whether the numbers are valid: ok, not_converged (not
    periodic to PERIODIC_TOL: more periods), singular (Newton found no equilibrium at a sample)."""
    if initial not in HISTORIES:
        raise ValueError(f"initial must be one of {', '.join(HISTORIES)}; got {initial!r}")
    n_time = check_int("n_time", n_time, 4)
    if n_time % 2:
        raise ValueError(f"n_time must be an even integer in [4, inf); got {n_time}")
    n_periods = check_int("n_periods", n_periods, 2)
    n_load = check_int("n_load", n_load, 1)
    max_newton = check_int("max_newton", max_newton, 1)
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load, wedge_ok=True)
    check_range("amplitude_mrad", amplitude_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    motion = as_ellipse(validate_motion(motion))  # a straight path: an ellipse of zero width
    return hbm_aft_path_kernel(shape, mu, contacts, load, jnp.asarray(float(amplitude_mrad)),
                               motion, n_time, n_periods, initial=initial, n_load=n_load,
                               max_newton=max_newton)


__all__ = ["HBMPathResult", "hbm_aft_path", "hbm_aft_path_kernel", "PERIODIC_TOL"]
