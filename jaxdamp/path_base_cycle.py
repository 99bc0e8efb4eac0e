"""The Base-Cycle on any straight platform path, for any pad set (curved-flat damper or wedge).

The paper defines the Base-Cycle on its in-phase stroke: from full slip one way, the platforms
reverse and move until every pad slips the other way (gross slip), reverse again, and so on until
the end states repeat; its amplitude psi_BC is half the longer half's travel, and psi_fs, half the
first tract's travel, bounds the fully stuck cycles (`jaxdamp.cycle`). The same construction holds
on any straight relative path X = s X_r (MODEL.md, "Any in-plane motion": out-of-phase at 180 deg,
a real `general_motion`) and for a wedge, whose four pads make the full-slip statics indeterminate:

- state 0 is the gross-slip history's state (`elliptic_cycle(initial="gross_slip")`): F_D applied
  at X = 0, then a move along +X_r until every pad that can slip does;
- halves run along -X_r and +X_r to gross slip on the tract engine (pads open and close), pairs
  repeated until the end state repeats;
- a_BC (mrad of the path's parameter) is half the longer half's travel, a_fs half the forward
  half's first tract and k_Re,fs the modal force's slope over that tract (as the paper's numbers);
  the Base-Cycle's k_Re,BC, k_Im,BC, energy, slip and open fractions per pad and its tracts are
  those of the exact steady cycle at a_BC from the gross-slip state (`ellipse.elliptic_kernel`, the
  straight path as an ellipse of zero width).

Where a half never reaches gross slip there is no Base-Cycle (`unreachable`): e.g. a wedge at
180 deg whose R2 and L2 have opened, leaving R1 and L1, which cannot both slip (two pads cannot hold
three degrees of freedom in gross slip) and take turns to stick and slip along the whole move.

On the paper's in-phase path for the curved-flat damper this is the paper's Base-Cycle, reached by
another road (assembly and a move to gross slip instead of the full-slip statics; the elliptic
engine instead of the Base-Cycle's halves): tests/test_path_base_cycle.py checks the five numbers
against `five_numbers` and 74R's a_BC against Table B4.1. An elliptic path has no halves that end
in gross slip (the direction of motion turns all along it) and no Base-Cycle: `elliptic_cycle`.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ._validate import check_int
from .conventions import CENTRIFUGAL_LOAD, MRAD_PER_RAD, travel_mm
from .ellipse import EllipticCycle, along_line, elliptic_kernel, path_pads
from .engine import assemble
from .engine import run as run_tracts
from .geometry import DamperShape
from .loops import run_by_loop
from .periodic import iterate_to_periodic
from .motion import Motion, as_ellipse, motion_moment_coefficients, validate_motion
from .params import Contacts, LoadCase, prepare_inputs
from .paths import Line
from .status import RESULTS, number_repr, status_repr

MAX_TRACTS = 8  # per half: a wedge's halves see at most 6 events on the cases of the tests
MAX_PAIRS = 4  # forward + backward pairs until the end state repeats (1 usually)

__all__ = ["PathBaseCycle", "path_base_cycle", "path_base_cycle_kernel", "path_base_cycle_inputs"]


class PathBaseCycle(NamedTuple):
    """The Base-Cycle on a straight path (a pytree). Amplitudes in mrad of the path's parameter
    (psi in-phase, the left-hand blade's rotation with an interblade phase angle), stiffnesses in
    N mm/mrad, spans in mm of the path parameter s = a q*/1e3."""

    a_fs: jnp.ndarray  # half the forward half's first tract from gross slip
    k_re_fs: jnp.ndarray  # the modal force's slope over that tract
    a_bc: jnp.ndarray  # half the longer half's travel from gross slip to gross slip
    spans: jnp.ndarray  # (2,) the forward and backward halves' travel to gross slip, mm
    cycle: EllipticCycle  # the steady cycle at a_bc from the gross-slip state: the Base-Cycle
    pairs: jnp.ndarray  # forward + backward pairs run until the end state repeated
    # RESULTS code: ok, unseated, unreachable (a half never reaches gross slip), singular,
    # not_converged, ill_conditioned
    status: jnp.ndarray

    @property
    def k_re_bc(self):
        """The Base-Cycle's k_Re, N mm/mrad (0 where the status says it has no numbers)."""
        return jnp.where(RESULTS.valid(self.status), self.cycle.k_re, 0.0)

    @property
    def k_im_bc(self):
        """The Base-Cycle's k_Im, N mm/mrad (0 where the status says it has no numbers)."""
        return jnp.where(RESULTS.valid(self.status), self.cycle.k_im, 0.0)

    def __repr__(self) -> str:
        return (f"PathBaseCycle(status={status_repr(self.status)}, "
                f"a_fs={number_repr(self.a_fs, 'mrad')}, "
                f"k_re_fs={number_repr(self.k_re_fs, 'N mm/mrad')}, "
                f"a_bc={number_repr(self.a_bc, 'mrad')}, "
                f"k_re_bc={number_repr(self.k_re_bc, 'N mm/mrad')}, "
                f"k_im_bc={number_repr(self.k_im_bc, 'N mm/mrad')})")


def path_base_cycle_kernel(shape, mu, contacts, load, motion: Motion, *,
                           max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS,
                           loop: str = "auto") -> PathBaseCycle:
    """`path_base_cycle` without input checks (jit / vmap / jvp); motion straight (quadrature
    None). loop: as `amplitude_kernel`'s."""
    def impl(shape, mu, contacts, load, motion, loop):
        return _impl(shape, mu, contacts, load, motion, max_tracts, max_pairs, loop)

    return run_by_loop(impl, (shape, mu, contacts, load, motion), loop)


def _impl(shape, mu, contacts, load, motion, max_tracts, max_pairs, loop):
    pads = path_pads(shape, mu, contacts, load, (Motion(motion.direction, motion.h_l),))
    n_pads = pads.kn.shape[0]
    Na, Ta, seated = assemble(pads, CENTRIFUGAL_LOAD)
    fn, ft = motion_moment_coefficients(pads.nw[0], pads.tw[0], load)

    # One loop over moves to gross slip, so that the program holds one compiled run: move 0 from
    # assembly along +X_r, then pairs of halves, forward (-X_r) and backward (+X_r), until the
    # state at the start of a pair repeats (`periodic.iterate_to_periodic`).
    def leg(r, N, T, j, k, idle):
        forward = j % 2 == 1
        run = run_tracts(along_line(pads, jnp.where(forward, -1.0, 1.0)), Line(), N, T,
                         0.0, None, max_tracts=max_tracts, loop=loop, idle=idle)
        # A run that ends anywhere but in gross slip (its tracts ran out, e.g. two pads taking
        # turns to stick and slip) leaves no gross-slip state, and no Base-Cycle.
        unseated = run.status == RESULTS.unseated
        missed = ~unseated & ~(run.gross_slip & (run.status == RESULTS.ok))
        pair_end = ~forward & (j > 0)
        span = jnp.sum(jnp.where(run.active, run.dp, 0.0))
        # The modal force's rate over the forward half's first tract, per mm along -X_r.
        rate = jnp.sum(fn * run.dN[0, 0] + ft * run.dT[0, 0])
        bad = unseated | missed
        r = dict(spans=jnp.where(forward, r["spans"].at[0].set(span),
                                 jnp.where(pair_end, r["spans"].at[1].set(span), r["spans"])),
                 first_tract=jnp.where(forward, run.dp[0], r["first_tract"]),
                 rate=jnp.where(forward, rate, r["rate"]),
                 unseated=r["unseated"] | unseated, missed=r["missed"] | missed,
                 reached=jnp.where(j == 0, ~bad, r["reached"]))
        return run.N_end, run.T_end, bad, r

    no = jnp.array(False)
    records = dict(spans=jnp.zeros(2), first_tract=jnp.array(0.0), rate=jnp.array(0.0),
                   unseated=no, missed=no, reached=no)
    end = iterate_to_periodic(leg, jnp.where(seated, Na, jnp.ones(n_pads)),  # finite if masked
                              jnp.where(seated, Ta, 0.0), pads.mu, records, legs_per_round=2,
                              pre_legs=1, max_rounds=max_pairs, loop=loop, stop0=~seated)
    r = end["records"]
    reached = r["reached"]
    to_mrad = MRAD_PER_RAD / load.q_star
    a_bc = 0.5 * jnp.max(r["spans"]) * to_mrad
    a_fs = 0.5 * r["first_tract"] * to_mrad
    # The forward half runs along -X_r: the slope along +X_r per mrad of the path parameter.
    k_re_fs = -r["rate"] * travel_mm(1.0, load.q_star)
    cycle = elliptic_kernel(shape, mu, contacts, load,
                            jnp.where(end["closed"] & (a_bc > 0.0), a_bc, 1.0), as_ellipse(motion),
                            initial="gross_slip", loop=loop)
    # The history's causes (unseated at assembly; a move that never reaches gross slip, the
    # first one included; unseated on a later move: one at most, a bad move stops the loop),
    # the halves' (not periodic), then the cycle's own where it has no numbers.
    status = RESULTS.first({RESULTS.unseated: ~seated | (reached & r["unseated"]),
                            RESULTS.unreachable: seated & (~reached | r["missed"]),
                            RESULTS.not_converged: ~end["closed"]},
                           status=jnp.where(RESULTS.valid(cycle.status), RESULTS.ok, cycle.status))
    valid = RESULTS.valid(status)
    zero = lambda v: jnp.where(valid, v, jnp.zeros_like(v))  # noqa: E731
    return PathBaseCycle(zero(a_fs), zero(k_re_fs), zero(a_bc), zero(r["spans"]), cycle,
                         end["rounds"], status)


_kernel = jax.jit(path_base_cycle_kernel, static_argnames=("max_tracts", "max_pairs", "loop"))


def path_base_cycle_inputs(shape: DamperShape, mu, motion: Motion,
                           contacts: Contacts = Contacts(), load: LoadCase = LoadCase()) -> tuple:
    """The checked inputs of `path_base_cycle` as `path_base_cycle_kernel` takes them: (shape, mu,
    contacts, load, motion). ValueError naming the parameter and its range; an elliptic path
    refused (it has no Base-Cycle)."""
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load, wedge_ok=True)
    motion = validate_motion(motion, load)
    if motion.quadrature is not None:
        raise ValueError("motion must be a straight path for a Base-Cycle (in-phase, an interblade "
                         "phase angle of 0 or 180 deg, a real X_hat): on an ellipse no half ends "
                         "in gross slip; its exact cycles: elliptic_cycle")
    return shape, mu, contacts, load, motion


def path_base_cycle(shape: DamperShape, mu, motion: Motion, contacts: Contacts = Contacts(),
                    load: LoadCase = LoadCase(), *, max_tracts: int = MAX_TRACTS,
                    max_pairs: int = MAX_PAIRS) -> PathBaseCycle:
    """The Base-Cycle on the straight platform path of `motion` (`in_phase_motion`,
    `interblade_motion` at 0 or 180 deg, a real `general_motion`), for the curved-flat damper or a
    wedge (module docstring): a_fs, k_Re,fs, a_BC and the Base-Cycle itself (`.cycle`, an
    EllipticCycle: k_Re,BC, k_Im,BC, energy, slip and open fractions per pad, its tracts).
    Its status says whether the numbers are valid (ok) or not (unseated: no set of closed pads
    holds the damper; unreachable: a half never reaches gross slip; singular; not_converged).
    Inputs are checked here (ValueError naming the parameter and its range)."""
    check_int("max_tracts", max_tracts, 1)
    check_int("max_pairs", max_pairs, 1)
    return _kernel(*path_base_cycle_inputs(shape, mu, motion, contacts, load),
                   max_tracts=max_tracts, max_pairs=max_pairs)
