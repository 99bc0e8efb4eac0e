"""Moment Base-Cycle, closed-form first harmonic (complex stiffness) and the five numbers.

Sign conventions. psi = dv / q* with dv = v_PR - v_PL (MODEL.md). M_P = (F_R1,v - F_L,v)(q*/2 + r sin
beta), with F the forces the platforms exert on the damper; this is the moment that imposes psi, so
the stick stiffness k_Re is positive and the loop is traversed with positive work W = oint M dpsi.
For psi = psi_c + psi_a cos(tau) the first harmonic is M ~ psi_a (k_Re cos tau - k_Im sin tau),
i.e. the phasor relation M = (k_Re + i k_Im) psi, with k_Im = W / (pi psi_a^2) > 0.
Units: psi in mrad, M in N mm, k in N mm/mrad.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .amplitude import amplitude_kernel
from .conventions import psi_mrad, travel_mm
# The small-rotation limit lives with the conventions (below amplitude.py, which warns too).
from .conventions import SMALL_ROTATION_MRAD as SMALL_ROTATION_MRAD
from .conventions import SmallRotationWarning as SmallRotationWarning
from .conventions import warn_small_rotation as warn_small_rotation
from .cycle import BaseCycle, base_cycle_kernel, check_base_cycle
from .design import as_design
from .geometry import DamperShape
from .params import Contacts, LoadCase, check_types, fast_ok, prepare_inputs, require_x64
from .runtime import batch_jit, padded_size
from .status import RESULTS, number_repr, status_repr
# The stretched Base-Cycle lives in its own module, below this one and below jaxdamp.amplitude
# (which uses it above psi_BC); these names stay importable from here.
from .stretch import MomentHalf as MomentHalf
from .stretch import base_cycle_amplitude as base_cycle_amplitude
from .stretch import gross_slip_stiffness
from .stretch import moment as moment
from .stretch import moment_half as moment_half
from .stretch import stretched_cycle as stretched_cycle


# Units of the five numbers, in FiveNumbers' order (psi_fs, k_Re,fs, psi_BC, k_Re,BC, k_Im,BC).
UNITS = ("mrad", "N mm/mrad", "mrad", "N mm/mrad", "N mm/mrad")


class FiveNumbers(NamedTuple):
    """The paper's characteristic numbers (psi in mrad, k in N mm/mrad) and the status (RESULTS)
    of the Base-Cycle they come from: only `ok` numbers describe a damper (zero after liftoff or
    a failed solve)."""

    psi_fs: jnp.ndarray
    k_re_fs: jnp.ndarray
    psi_bc: jnp.ndarray
    k_re_bc: jnp.ndarray
    k_im_bc: jnp.ndarray
    status: jnp.ndarray

    def numbers(self) -> tuple:
        """The five numbers without the status, in the paper's order."""
        return tuple(self[:5])

    def __repr__(self) -> str:
        parts = [f"{f}={number_repr(v, u)}" for f, v, u in zip(self._fields, self, UNITS)]
        return f"FiveNumbers(status={status_repr(self.status)}, " + ", ".join(parts) + ")"


def five_numbers(bc: BaseCycle) -> FiveNumbers:
    """psi_fs, k_Re,fs, psi_BC, k_Re,BC, k_Im,BC; all zero where the damper lifts off.

    Called on concrete values, warns (SmallRotationWarning) when psi_BC exceeds the small-rotation
    limit SMALL_ROTATION_MRAD (e.g. kt = 1 N/mm gives psi_BC ~ 7000 mrad). Traceable: inside
    jit/vmap/grad it is `five_numbers_kernel`."""
    nums = five_numbers_kernel(check_base_cycle(bc))
    warn_small_rotation(nums.psi_bc, stacklevel=3)
    return nums


@jax.jit
def five_numbers_kernel(bc: BaseCycle) -> FiveNumbers:
    """`five_numbers` without the warning check, for use inside jit/vmap/grad."""
    q = bc.load.q_star
    psi_fs = psi_mrad(bc.forward.dv[0] / 2.0, q)
    # Moment rate per mm of travel, with the forward half's travel running in -dv.
    k_re_fs = -moment(bc, bc.forward.dN[0], bc.forward.dT[0]) * travel_mm(1.0, q)
    psi_bc = base_cycle_amplitude(bc)
    k_re_bc, k_im_bc, _ = gross_slip_stiffness(bc, psi_bc)
    nums = (psi_fs, k_re_fs, psi_bc, k_re_bc, k_im_bc)
    # A cycle that lifted off (or failed) stopped part-way: its numbers would look valid but mean
    # nothing.
    stopped = RESULTS.stopped(bc.status)
    return FiveNumbers(*(jnp.where(stopped, 0.0, v) for v in nums), bc.status)


def complex_stiffness(bc: BaseCycle, psi_a_mrad, method="exact", initial="gross_slip"):
    """(k_Re, k_Im) in N mm/mrad at platform rotation amplitude(s) psi_a (mrad). Accepts an array.

    method="exact" (default): the steady cycle at each amplitude by the direct method with
    travel-limited half-cycles (`jaxdamp.amplitude`), started from `initial` ("gross_slip": the
    Base-Cycle's state 0; "assembly"); numbers are zero where that cycle is not valid (liftoff,
    not converged). method="interpolated": the paper's numbers, for comparison with it:
    psi_a <= psi_fs full stick (k_Re,fs, 0); psi_fs < psi_a < psi_BC the paper's linear microslip
    interpolation; psi_a >= psi_BC the Base-Cycle stretched by full slip at both ends, exact first
    harmonic. Both agree at psi_a >= psi_BC, where gross slip erases the history.
    """
    check_base_cycle(bc)
    if not isinstance(psi_a_mrad, jax.core.Tracer):
        # checked on concrete input only: a negative amplitude (or, for the exact cycle, zero) has no
        # cycle and came back as a silent 0 stiffness; psi_a = 0 is the full-stick limit when
        # interpolated (summary.psi_grid starts there)
        if psi_a_mrad is None or isinstance(psi_a_mrad, (str, bytes)):
            raise ValueError(f"psi_a_mrad must be a number or an array of numbers in mrad; got "
                             f"{psi_a_mrad!r}")
        try:
            psi = np.asarray(psi_a_mrad, float)
        except (TypeError, ValueError):
            raise ValueError(f"psi_a_mrad must be a number or an array of numbers in mrad; got "
                             f"{type(psi_a_mrad).__name__}") from None
        if psi.size == 0:
            raise ValueError("psi_a_mrad must hold at least one amplitude (mrad); got none")
        low_ok = psi >= 0 if method == "interpolated" else psi > 0
        if not (np.all(np.isfinite(psi)) and np.all(low_ok)):
            bound = ">= 0" if method == "interpolated" else "> 0"
            raise ValueError(f"psi_a_mrad must be finite and {bound} mrad; got {psi_a_mrad!r}")
        # as amplitude_cycle: a number outside the model's validity says so
        warn_small_rotation(float(np.max(psi)), "psi_a", stacklevel=3)
    if method == "interpolated":
        return _bucketed(_interpolated_stiffness, bc, psi_a_mrad)
    if method != "exact":
        raise ValueError(f"method must be exact or interpolated; got {method!r}")
    if initial not in ("gross_slip", "assembly"):
        raise ValueError(f"initial must be gross_slip or assembly; got {initial!r}")
    return _bucketed(partial(_exact_stiffness, initial=initial), bc, psi_a_mrad)


def _bucketed(kernel, bc, psi_a_mrad):
    """kernel(bc, psi) on concrete amplitudes padded (`runtime.padded_size`: a power of two, at
    least 8, repeating the last one), so that a new number of amplitudes does not compile anew."""
    if isinstance(psi_a_mrad, jax.core.Tracer):
        return kernel(bc, psi_a_mrad)
    psi = np.asarray(psi_a_mrad, float)
    flat = psi.reshape(-1)
    size = padded_size(flat.size, 8)
    padded = np.concatenate([flat, np.full(size - flat.size, flat[-1] if flat.size else 1.0)])
    out = kernel(bc, padded)
    if any(isinstance(k, jax.core.Tracer) for k in out):  # a traced cycle: slice in the trace
        return tuple(k[: flat.size].reshape(psi.shape) for k in out)
    # Concrete results: cut the padding off on the host and transfer with device_put. Slicing the
    # device arrays, or jnp.asarray of the host copy, compiles a small program for every new
    # number of amplitudes (jax 0.10.2; tests/test_design.py counts the compiles).
    return tuple(jax.device_put(np.asarray(k)[: flat.size].reshape(psi.shape)) for k in out)


@batch_jit(static_argnames=("initial",))
def _exact_stiffness(bc: BaseCycle, psi_a_mrad, initial):
    psi = jnp.asarray(psi_a_mrad, float)
    flat = psi.reshape(-1)
    one = lambda p: amplitude_kernel(bc.shape, bc.mu, bc.contacts, bc.load, p,  # noqa: E731
                                     initial=initial)
    ac = jax.vmap(one)(flat)
    return ac.k_re.reshape(psi.shape), ac.k_im.reshape(psi.shape)


@jax.jit
def _interpolated_stiffness(bc: BaseCycle, psi_a_mrad):
    """The paper's k(psi_a): see `complex_stiffness(..., method="interpolated")`."""
    nums = five_numbers(bc)

    def one(psi):
        big = jnp.maximum(psi, nums.psi_bc)
        k_re_g, k_im_g, _ = gross_slip_stiffness(bc, big)
        width = nums.psi_bc - nums.psi_fs
        ok = width > 0
        frac = jnp.clip((psi - nums.psi_fs) / jnp.where(ok, width, 1.0), 0.0, 1.0)
        k_re_m = nums.k_re_fs + frac * (nums.k_re_bc - nums.k_re_fs)
        k_im_m = frac * nums.k_im_bc
        micro = psi < nums.psi_bc
        return jnp.where(micro, k_re_m, k_re_g), jnp.where(micro, k_im_m, k_im_g)

    psi = jnp.asarray(psi_a_mrad, float)
    flat = psi.reshape(-1)
    k_re, k_im = jax.vmap(one)(flat)
    return k_re.reshape(psi.shape), k_im.reshape(psi.shape)


@jax.jit
def cycle_work(bc: BaseCycle, psi_a_mrad=None):
    """oint M dpsi (N mm) of the (stretched) cycle at psi_a (default: the Base-Cycle).
    Unchecked, traceable (jit, vmap, grad): takes a BaseCycle (checked when it was made); psi_a
    (>= psi_BC) is not checked."""
    psi = base_cycle_amplitude(bc) if psi_a_mrad is None else psi_a_mrad
    return gross_slip_stiffness(bc, psi)[2]


class CycleNumbers(NamedTuple):
    """The five numbers of one design's Base-Cycle and its status (Python floats, float64: psi in
    mrad, k in N mm/mrad; status a jaxdamp.RESULTS code; the numbers are zero where the damper lifts
    off or the solve failed)."""

    psi_fs: float
    k_re_fs: float
    psi_bc: float
    k_re_bc: float
    k_im_bc: float
    status: int

    def __repr__(self) -> str:
        return FiveNumbers.__repr__(self).replace("FiveNumbers(", "CycleNumbers(", 1)


# The packed input vector of `cycle_numbers`: shape (4), mu, kn (3), kt (3), F_D, q*, r sin beta.
_PACKED = 14


@jax.jit
def _numbers_packed(v):
    """Base-Cycle + five numbers of one design from one packed vector, as one stacked vector.

    One input and one output buffer, and loops that stop when done (loop="while"): a single call's
    cost is the number of small kernels and buffers it runs (benchmarks/bench_single.py)."""
    bc = base_cycle_kernel(DamperShape(v[0], v[1], v[2], v[3]), v[4],
                           Contacts(v[5:8], v[8:11]), LoadCase(v[11], v[12], v[13]), loop="while")
    nums = five_numbers_kernel(bc)
    return jnp.stack([*nums.numbers(), bc.status.astype(float)])


def cycle_numbers(shape, mu=None, contacts=None, load=None) -> CycleNumbers:
    """psi_fs, k_Re,fs, psi_BC, k_Re,BC, k_Im,BC and the status of one design, for a single
    design fast (one compiled call: ~50 us warm on a CPU core, against ~150 us for
    `five_numbers(base_cycle(...))`, which returns the whole cycle).

    shape: a DamperShape (mu required) or a Design; inputs as for `base_cycle`, checked the same
    way (ValueError naming the parameter and range; Float64Required in float32). The same numbers
    as `five_numbers(base_cycle(...))` (the same arithmetic, loops that stop when done). For values
    only: under jit, vmap or grad use `five_numbers_kernel(base_cycle_kernel(...))`; for many
    designs, `jaxdamp.evaluate_designs`.
    """
    # The imports are module-level: inside the function they cost ~1 us of a ~45 us call.
    design = as_design(shape, mu, Contacts() if contacts is None else contacts,
                       LoadCase() if load is None else load)
    s, m, c, ld = design
    check_types(shape=s, contacts=c, load=ld)  # before fast_ok reads their fields
    if fast_ok(*design):  # plain numbers in range: no array work before the call
        require_x64()
        kn, kt = ((k,) * 3 if type(k) in (float, int) else tuple(k) for k in c)
        v = np.array((s.theta_l, s.theta_r, s.br_over_hr, s.bl2_over_hl, m, *kn, *kt, *ld), float)
    else:
        s, m, c, ld = prepare_inputs(*design)
        leaves = jax.tree_util.tree_leaves((s[:4], m, c, ld))
        if s.x_d is not None or any(isinstance(x, jax.core.Tracer) for x in leaves):
            raise ValueError("cycle_numbers takes one concrete design without x_d; under jit, "
                             "vmap or grad, or with x_d, use five_numbers(base_cycle(...))")
        v = np.concatenate([np.ravel(np.asarray(x, float)) for x in leaves])
        if v.shape != (_PACKED,):
            raise ValueError("cycle_numbers takes one design (scalar shape, mu and load; kn, kt "
                             "scalar or (3,)); for many designs use jaxdamp.evaluate_designs")
    # One host copy and plain floats: unpacking numpy scalars costs ~1 us of the call.
    psi_fs, k_re_fs, psi_bc, k_re_bc, k_im_bc, status = np.asarray(_numbers_packed(v)).tolist()
    if psi_bc > SMALL_ROTATION_MRAD:
        warn_small_rotation(psi_bc, stacklevel=3)
    return CycleNumbers(psi_fs, k_re_fs, psi_bc, k_re_bc, k_im_bc, int(status))


__all__ = ["UNITS", "SMALL_ROTATION_MRAD", "SmallRotationWarning", "warn_small_rotation", "MomentHalf",
           "base_cycle_amplitude", "moment", "moment_half", "stretched_cycle", "FiveNumbers",
           "five_numbers", "five_numbers_kernel", "complex_stiffness", "cycle_work",
           "CycleNumbers", "cycle_numbers"]
