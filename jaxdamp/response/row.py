"""The forced response across a blade row: one peak per engine order, each on its own nodal
diameter's blade mode and platform path (`modes.nodal_scene`), with and without the damper.

Engine orders whose paths share a kind (straight or elliptic) run as one vmapped program
(`row_program`), so that a whole row is one or two compiled calls.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import numpy as np

from .._validate import check_int, check_values
from ..conventions import SMALL_ROTATION_MRAD
from ..runtime import batch_jit, compile_ahead, padded_size, run_program
from ..status import RESULTS, number_repr, status_repr
from .modes import ModalFamily, nodal_scenes
from .peaks import Peaks, path_peaks
from .scene import BladeMode, prepare_scene
from .stiffness import base_scale, check_history

# Engine orders of one path kind, and forces, are padded to at least 4, then to a multiple of a
# quarter of their power of two (`runtime.padded_size(n, 4, BUCKETS_PER_OCTAVE)`: 5-8 -> 8,
# 9-12 -> 12, 13-16 -> 16, 17-20 -> 20, ...): a padded order costs what a real one does. The
# example disk's 11 elliptic orders padded to 12 instead of 16 (powers of two until 2026-11-29):
# its row's values and derivatives for 3 mu 2.49-2.64 -> 1.79-2.16 s (2-core VM, same hour).
ENGINE_ORDER_BUCKET = 4
FORCE_BUCKET = 4
BUCKETS_PER_OCTAVE = 4
# The cycles a step of each engine order's peak search evaluates (`root_search.grid_then_roots`):
# a step's batch is every order's slots, so a row needs fewer per order than one design's 16. On
# the example disk's row (4 forces, 3 mu; 2-core VM, 2026-11-29) the values program ran 2.85 s
# in all with 16 (12 of a search step's 16 brackets empty), 1.74 s with 4, 1.94 s with 8 and
# 2.41 s with 2 (more steps).
ROW_SEARCH_WIDTH = 4

__all__ = ["RowResponse", "row_program", "row_response", "engine_orders_of", "run_by_path_kind",
           "check_engine_orders", "prepare_row", "row_of_prepared", "flexible_row",
           "outside_small_rotation", "beyond_small_rotation"]


class RowResponse(NamedTuple):
    """Peak tip response per engine order (leading axis m) and force (second axis n_f).

    engine_order, nodal_diameter, ibpa_deg: (m,); frequency_hz: (m,) the nodal diameter's natural
    frequency with the platforms free. peaks: `Peaks` with fields (m, n_f) (mm, Hz, mrad of the
    path's parameter), its status the damper's unless the steady cycle at the peak says more
    (liftoff where a pad opens there on a straight path; on an elliptic one a pad that opens
    is part of the cycle, and unseated says that no set of pads holds the damper; not_converged;
    shakedown where the damper sticks). free_peak_mm: (m, n_f) the peak without the
    damper, F_tip / (eta k_b) (a stuck damper gives the same peak, at its stiffened frequency).
    tip_force_n: (m, n_f) the tip force of each excitation. worst: (n_f,) index of the engine
    order with the largest valid damped peak (-1 where none is valid). elliptic: (m,) whether the
    damper's path is an ellipse (else straight). initial: the contact history.
    residual_mrad_per_nmm: (m,) the path's residual flexibility c (`modes`; 0 where the family
    has no platform_residual): where non-zero, psi_a_mrad is the damper's own amplitude.
    rotation_mrad: (m, n_f) the platforms' largest rotation amplitude at the peak (A* times the
    scene's `rotation_mrad_per_mm`): a valid peak where it exceeds SMALL_ROTATION_MRAD is
    large_rotation (`outside_small_rotation`). psi_a_mrad is a scale of the whole path, not a
    rotation: off nodal diameter 0 it is about ten times this.
    """

    engine_order: np.ndarray
    nodal_diameter: np.ndarray
    ibpa_deg: np.ndarray
    frequency_hz: np.ndarray
    force_n: np.ndarray
    tip_force_n: np.ndarray
    peaks: Peaks
    free_peak_mm: np.ndarray
    worst: np.ndarray
    elliptic: np.ndarray
    initial: str
    status: np.ndarray
    residual_mrad_per_nmm: np.ndarray
    rotation_mrad: np.ndarray

    def __repr__(self):
        w = int(np.asarray(self.worst).reshape(-1)[0])
        worst = (f"worst engine order {int(self.engine_order[w])} (ND {int(self.nodal_diameter[w])})"
                 if w >= 0 else "no valid peak")
        return (f"RowResponse({len(self.engine_order)} engine orders, A* "
                f"{number_repr(self.peaks.peak_amplitude_mm, 'mm')}, {worst}, "
                f"status {status_repr(self.status)})")


def engine_orders_of(text: str, n_blades: int) -> list[int]:
    """Engine orders from 'a:b' (inclusive), 'a,b,c' or 'all' (0 ... N/2: every nodal diameter
    once). ValueError naming engine_order and the valid form otherwise; n_blades an integer >= 2."""
    n_blades = check_int("n_blades", n_blades, 2)
    t = str(text).strip()
    if t == "all":
        return list(range(n_blades // 2 + 1))
    try:
        if ":" in t:
            lo, hi = (int(v) for v in t.split(":"))
            orders = list(range(lo, hi + 1))
        else:
            orders = [int(v) for v in t.split(",") if v.strip()]
    except ValueError:
        raise ValueError(f"engine_order must be 'a:b', 'a,b,...' or 'all' with integers >= 0; got "
                         f"{text!r}") from None
    if not orders or min(orders) < 0:
        raise ValueError(f"engine_order must be 'a:b', 'a,b,...' or 'all' with integers >= 0; got "
                         f"{text!r}")
    return orders


@functools.cache
def row_program(initial: str = "assembly", residual: bool = False):
    """One compiled program per contact history: (shape, mu, contacts, load, modes, motions,
    tip_forces (m, n_f)) -> Peaks with fields (m, n_f), vmapped over the m engine orders (modes
    and motions stacked; all straight or all elliptic: the path's kind is the pytree's
    structure, so each kind compiles once). residual: the program takes one more argument, the
    paths' residual flexibilities (m,) (mrad per N mm, `modes`), and puts the damper in series
    with them; a family without platform_residual runs the program without. base_status,
    base_psi_ref: the damper's Base-Cycle's (`stiffness.base_scale`), the same for every engine
    order, from a program of its own: inside both path kinds' programs it was a third of their
    XLA compile (the example row, 2026-12-02)."""
    def run(shape, mu, contacts, load, modes, motions, tip_forces, base_status, base_psi_ref,
            *residuals):
        base = (base_status, base_psi_ref)

        def one(mode, motion, forces, *c):
            return path_peaks(shape, mu, contacts, load, mode, motion, forces, initial,
                              residual=c[0] if c else None, search_width=ROW_SEARCH_WIDTH,
                              base=base)[1]

        return jax.vmap(one)(modes, motions, tip_forces, *residuals)

    return batch_jit(run)


def _stack(trees):
    # NumPy on the host: a program's inputs need no XLA program of their own to be built.
    return jax.tree_util.tree_map(lambda *v: np.stack([np.asarray(x, float) for x in v]), *trees)


def run_by_path_kind(program, design, scenes, tip, residual, extra=(), runner=None,
                     buckets=(ENGINE_ORDER_BUCKET, FORCE_BUCKET, BUCKETS_PER_OCTAVE),
                     per_order=(), extra_later=None) -> list:
    """Run a row program on the engine orders of each path kind (straight, elliptic) as one
    batch: program(*design, modes, motions, tip forces (m, n_f), *extra[, residuals (m,)]) with
    the engine orders and the forces padded (repeating the last) to `runtime.padded_size(n,
    minimum, steps per octave)` with buckets = (the orders' minimum, the forces' minimum, steps
    per octave; 1 would be powers of two); residual: the (m,) residual flexibilities, or None
    for the program without them (`flexible_row`). per_order: arrays (m, n_f) per engine order and force
    (the values' roots, `row_gradient`), padded as the tip forces and passed after extra.
    extra_later: a function returning the extra arguments, called once the programs have started
    compiling (extra then holds placeholders of their shapes and dtypes: a row's Base-Cycle runs
    while its programs compile). runner(program, args): how to call it (default program(*args)).
    Returns each scene's slice of its batch's host outputs (force axes still padded), in scenes'
    order."""
    n_f = padded_size(tip.shape[1], buckets[1], buckets[2])
    forces = np.minimum(np.arange(n_f), tip.shape[1] - 1)
    tip = tip[:, forces]
    per_order = [np.asarray(v)[:, forces] for v in per_order]
    elliptic = np.array([not s.straight for s in scenes])
    rows = [None] * len(scenes)
    batches = []
    for kind in (False, True):
        idx = np.flatnonzero(elliptic == kind)
        if not idx.size:
            continue
        # Padding repeats the last engine order: its numbers are dropped below.
        take = np.concatenate([idx, np.full(padded_size(idx.size, buckets[0], buckets[2])
                                            - idx.size, idx[-1])])
        part = [scenes[i] for i in take]
        modes_k = _stack([s.mode for s in part])
        residuals = () if residual is None else (np.asarray(residual[take], float),)
        batches.append((idx, (*design, modes_k, _stack([s.motion for s in part]),
                              np.asarray(tip[take], float), *extra,
                              *(np.asarray(v[take], float) for v in per_order), *residuals)))
    # Through a runner of saved programs (the CLI's) the elliptic batch compiles on a thread of
    # its own while the straight one compiles and runs: the example row's first call 27 -> 23 s on
    # 2 cores. A plain call traces both first, holding Python's lock, and gained nothing (45-48 s
    # either way), so it starts no thread on every call of a loop.
    if runner is not None:
        for _, args in batches[1:]:
            compile_ahead(program, args, runner)
    if extra_later is not None:
        at = len(design) + 3  # after the modes, motions and tip forces
        values = tuple(extra_later())
        batches = [(idx, args[:at] + values + args[at + len(values):]) for idx, args in batches]
    for idx, args in batches:
        got = jax.device_get(run_program(program, args, runner))
        for j, i in enumerate(idx):
            rows[i] = jax.tree_util.tree_map(lambda v: np.asarray(v)[j], got)
    return rows


def beyond_small_rotation(status, rotation_mrad):
    """status with large_rotation where a valid peak turns the platforms by more than
    SMALL_ROTATION_MRAD (rotation_mrad: the platforms' largest rotation amplitude, mrad)."""
    beyond = np.asarray(RESULTS.valid(status)) & (np.asarray(rotation_mrad) > SMALL_ROTATION_MRAD)
    return np.asarray(RESULTS.first({RESULTS.large_rotation: beyond}, status))


def outside_small_rotation(status, amplitude_mm, scenes):
    """(`beyond_small_rotation`'s status, the platforms' largest rotation amplitude (mrad)) of
    peaks (m, n_f) at tip amplitudes amplitude_mm on the engine orders' scenes: the rotation is
    amplitude_mm times each scene's `rotation_mrad_per_mm`."""
    per_mm = np.array([s.rotation_mrad_per_mm for s in scenes])[:, None]
    rotation = per_mm * np.asarray(amplitude_mm)
    return beyond_small_rotation(status, rotation), rotation


def flexible_row(residual):
    """The residual flexibilities (m,) a row program takes, or None where all are zero (a family
    without platform_residual runs the program without them)."""
    return residual if np.any(residual != 0) else None


def check_engine_orders(engine_orders) -> list[int]:
    """Engine orders as a list of integers >= 0 (one, or a 1-D sequence): ValueError in one line
    for anything else (text such as 'all' is `engine_orders_of`'s, a fraction is no order)."""
    hint = ("engine_orders must be one or more integers >= 0 (for 'a:b', 'a,b' or 'all' use "
            "jaxdamp.engine_orders_of(text, n_blades))")
    if engine_orders is None or isinstance(engine_orders, (str, bytes)):
        raise ValueError(f"{hint}; got {engine_orders!r}")
    try:
        raw = np.asarray(engine_orders, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{hint}; got {engine_orders!r}") from None
    flat = raw.reshape(-1)
    if flat.size == 0:
        raise ValueError("engine_orders must hold at least one integer >= 0; got none")
    if raw.ndim > 1 or not np.all(np.isfinite(flat)) \
            or np.any(flat != np.round(flat)) or np.any(flat < 0):
        raise ValueError(f"{hint}; got {engine_orders!r}")
    return [int(e) for e in flat]


def prepare_row(shape, mu, contacts, load, modes: ModalFamily, engine_orders, force_n, h_l_mm):
    """Every check of a row's inputs, before any work: ((shape, mu, contacts, load) prepared,
    forces (n_f,), engine orders (list), their NodalScenes, tip forces (m, n_f), residual
    flexibilities (m,)). ValueError naming the parameter and its range."""
    shape, mu, contacts, load, _ = prepare_scene(shape, mu, contacts, load, BladeMode())
    forces = np.atleast_1d(check_values("force_n", force_n))
    h_l_mm = float(check_values("h_l", h_l_mm, max_ndim=0))
    orders = check_engine_orders(engine_orders)
    scenes = nodal_scenes(modes, orders, float(load.q_star), float(h_l_mm))
    for s in scenes:  # a zero modal force has no peak to find (it gave NaN peaks marked ok)
        if not s.force_per_unit > 0.0:
            raise ValueError(f"modal_force is zero at nodal diameter {s.nodal_diameter}: engine "
                             f"order {s.engine_order} does not excite the family; leave it out")
    tip = np.array([s.force_per_unit for s in scenes])[:, None] * forces[None, :]
    residual = np.array([s.residual_mrad_per_nmm for s in scenes])
    return (shape, mu, contacts, load), forces, orders, scenes, tip, residual


def row_response(shape, mu=None, contacts=None, load=None, *, modes: ModalFamily, engine_orders,
                 force_n=(1.0,), h_l_mm: float, initial: str = "assembly",
                 runner=None) -> RowResponse:
    """Peak tip response (mm) of a tuned bladed disk with one damper between each pair of blades,
    at each engine order and excitation force (N per blade, the modal file's force pattern).

    modes: a ModalFamily (`jaxdamp.modal_file.load_modal_family` reads one); engine_orders: a
    list of integers >= 0 (each must excite a nodal diameter the family has); h_l_mm: the damper's
    size (its left flank's length, mm; the platforms turn relative to each other at every nodal
    diameter but 0). initial: the contact history, "assembly" or "gross_slip" (on an ellipse: a
    straight move along its tau = 0 direction to gross slip, `jaxdamp.ellipse`). Inputs are
    checked here (ValueError naming the parameter and its range) before anything is compiled. Engine orders (per path kind) and forces are padded to
    bucket sizes, so that one compiled program serves rows of similar size. runner(program,
    args): how to call a compiled program (default program(*args); the CLI passes one that
    saves it traced, `cli.exported`)."""
    check_history(initial)
    return row_of_prepared(prepare_row(shape, mu, contacts, load, modes, engine_orders, force_n,
                                       h_l_mm), initial, runner)


def row_of_prepared(prepared, initial: str, runner=None) -> RowResponse:
    """`row_response` on inputs `prepare_row` returned (checked already) and a checked history:
    for a caller that needs the prepared row again (`row_gradient`)."""
    (shape, mu, contacts, load), forces, orders, scenes, tip, residual = prepared
    elliptic = np.array([not s.straight for s in scenes])
    flexible = flexible_row(residual)
    program = row_program(initial, flexible is not None)
    design = (shape, mu, contacts, load)
    rows = [jax.tree_util.tree_map(lambda v: v[:forces.size], r) for r in run_by_path_kind(
        program, design, scenes, tip, flexible, extra=(np.zeros((), np.int32), np.zeros(())),
        runner=runner, extra_later=lambda: run_program(base_scale, design, runner)[::2])]
    peaks = jax.tree_util.tree_map(lambda *v: np.stack(v), *rows)
    status, rotation = outside_small_rotation(peaks.status, peaks.peak_amplitude_mm, scenes)
    peaks = peaks._replace(status=status)
    eta_kb = np.array([s.mode.eta * s.mode.k_b for s in scenes])[:, None]
    free = np.where(eta_kb > 0, tip / np.where(eta_kb > 0, eta_kb, 1.0), np.inf)
    valid = np.asarray(RESULTS.valid(peaks.status))
    amp = np.where(valid, peaks.peak_amplitude_mm, -np.inf)
    worst = np.where(valid.any(axis=0), np.argmax(amp, axis=0), -1)
    return RowResponse(np.array(orders), np.array([s.nodal_diameter for s in scenes]),
                       np.array([s.ibpa_deg for s in scenes]),
                       np.array([s.mode.f0_hz for s in scenes]), forces, tip, peaks, free, worst,
                       elliptic, initial, status, residual, rotation)

