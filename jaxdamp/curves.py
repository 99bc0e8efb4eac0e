"""k(psi_a) for many designs at once: `amplitude_curves` (concrete inputs, host-driven: the stretched
Base-Cycle above psi_BC, then the other (design, amplitude) pairs in two stages) and
`curves_kernel` (its pure-JAX form for jit / vmap / grad), with the batched pieces that
`jaxdamp.sequence.sequence_curves` reuses."""

from __future__ import annotations

import functools

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_range, is_concrete, require_x64
from .amplitude import INITIAL_STATES, MAX_PAIRS, MAX_TRACTS, amplitude_kernel
from .conventions import warn_small_rotation
from .cycle import base_cycle_kernel
from .geometry import DamperShape, validate_shape
from .params import Contacts, LoadCase, check_types, validate_contacts, validate_load, validate_mu
from .runtime import batch_jit, map_in_parts, padded_size, run_program
from .status import RESULTS, number_repr, status_repr
from .stretch import base_cycle_amplitude, gross_slip_stiffness

__all__ = ["StiffnessCurves", "cycle_curves", "curves_kernel", "prepare_curves_inputs",
           "check_curve_request",
           "batch_size", "broadcast_designs", "flat_cycles", "stretched_curves", "padded_index",
           "STRETCH_MARGIN", "FLAT_CPU_CHUNK"]


class StiffnessCurves(NamedTuple):
    """k(psi_a) of a batch of designs: arrays (designs, amplitudes)."""

    psi_a: jnp.ndarray  # mrad
    k_re: jnp.ndarray  # N mm/mrad (zero where status is not ok / shakedown)
    k_im: jnp.ndarray
    status: jnp.ndarray  # RESULTS codes (int32)
    cycles: jnp.ndarray  # pairs of halves run (of the Base-Cycle where its stretch is the cycle)

    def __repr__(self) -> str:
        return (f"StiffnessCurves(status={status_repr(self.status)}, "
                f"psi_a={number_repr(self.psi_a, 'mrad')}, k_re={number_repr(self.k_re, 'N mm/mrad')}, "
                f"k_im={number_repr(self.k_im, 'N mm/mrad')})")


def batch_size(args):
    """The number of designs of a batch: the longest leading axis of its leaves (1 if none)."""
    sizes = [int(np.shape(x)[0]) for x in jax.tree_util.tree_leaves(args) if np.ndim(x) > 0]
    return max(sizes) if sizes else 1


def broadcast_designs(args, size, xp=jnp):
    """Every leaf with a leading design axis of `size` (a leaf without it is shared); xp: jnp
    (traceable) or np (concrete inputs, host-side indexing without a dispatch per operation)."""
    def one(x):
        x = xp.asarray(x, float)
        lead = x.ndim > 0 and x.shape[0] == size
        return x if lead else xp.broadcast_to(x, (size,) + x.shape)
    return jax.tree_util.tree_map(one, args)


def curves_kernel(shapes: DamperShape, mu, contacts: Contacts, load: LoadCase, psi_a_mrad, *,
                  initial="gross_slip", max_tracts: int = MAX_TRACTS,
                  max_pairs: int = MAX_PAIRS) -> StiffnessCurves:
    """`amplitude_curves` as a pure JAX function (jit / vmap / grad / jacfwd): every input leaf has
    a leading design axis or is shared; psi_a_mrad is (amplitudes,) shared or (designs, amplitudes).
    Differentiable forward and reverse w.r.t. every input, NaN-free (the tracts' lengths are minima
    of closed-form events, so a reversal falling on a transition only switches which one is taken)."""
    args = (shapes, mu, contacts, load)
    size = max(batch_size(args), int(np.shape(psi_a_mrad)[0]) if np.ndim(psi_a_mrad) == 2 else 1)
    shapes, mu, contacts, load = broadcast_designs(args, size)
    psi = jnp.asarray(psi_a_mrad, float)
    psi = jnp.broadcast_to(psi, (size,) + psi.shape[-1:])

    def design(s, m, c, ld, p):
        run = lambda a: amplitude_kernel(s, m, c, ld, a, initial=initial,  # noqa: E731
                                         max_tracts=max_tracts, max_pairs=max_pairs)
        ac = jax.vmap(run)(p)
        return StiffnessCurves(p, ac.k_re, ac.k_im, ac.status, ac.cycles)

    return jax.vmap(design)(shapes, mu, contacts, load, psi)


_curves_jit = batch_jit(curves_kernel, static_argnames=("initial", "max_tracts", "max_pairs"))


def flat_cycles(shapes, mu, contacts, load, psi, initial, max_tracts, max_pairs):
    """The exact steady cycle of each (design, amplitude) pair (every leaf with one leading pair
    axis): StiffnessCurves of 1-D arrays; one compiled program per option set."""
    return _flat_program(initial, max_tracts, max_pairs)(
        shapes, mu, contacts, load, psi, _budget(max_pairs))


def _budget(max_pairs: int, pair_budget=None) -> np.ndarray:
    """A flat-cycle program's pair budget input (None: max_pairs)."""
    return np.int32(max_pairs if pair_budget is None else pair_budget)


@functools.cache
def _flat_program(initial: str, max_tracts: int, max_pairs: int):
    """`flat_cycles`' program with its static options bound: a program of arrays only, which a
    runner can save (the options are its closure's constants). Its pair budget is an input: the
    two stages of `amplitude_curves` (one pair, then up to max_pairs) are one compiled program
    (two before: the study compiled each of its curves' cycle programs twice, ~5 s each)."""
    def program(shapes, mu, contacts, load, psi, pair_budget):
        run = lambda s, m, c, ld, a: amplitude_kernel(  # noqa: E731
            s, m, c, ld, a, initial=initial, max_tracts=max_tracts, max_pairs=max_pairs,
            pair_budget=pair_budget)
        ac = jax.vmap(run)(shapes, mu, contacts, load, psi)
        return StiffnessCurves(psi, ac.k_re, ac.k_im, ac.status, ac.cycles)

    return batch_jit(program)


# Pairs per call of a flat-cycle program on the CPU (as the band's CPU_CHUNK): one compiled
# program serves every batch and both of `amplitude_curves`' stages (the study compiled two per
# initial state, ~5 s each), and chunks on the cores' threads wait less on a vmapped while loop's
# slowest lane (4096 cycles from assembly, 2-core VM: 0.08-0.09 s in one batch, 0.04-0.06 s in
# chunks of 256 on two threads). An accelerator runs the pairs in one padded batch.
FLAT_CPU_CHUNK = 256
_CYCLE_FIELDS = ("k_re", "k_im", "status", "cycles")


def _cycles_at(program, designs, n_amp: int, flat_psi, index, pair_budget, runner) -> dict:
    """{field: numpy array} of program (a `_flat_program`) at the pairs `index` of the flattened
    (design, amplitude) grid. Gathers and merges in numpy: as eager JAX operations they cost a
    dispatch each, more than half of a 128-design x 64-amplitude curve job."""
    def run(idx):
        sub = jax.tree_util.tree_map(lambda x: x[idx // n_amp], designs)
        out = run_program(program, (*sub, flat_psi[idx], pair_budget), runner)
        return {f: getattr(out, f) for f in _CYCLE_FIELDS}

    # np.array: writable copies, the second stage's values are written into the first's
    return {f: np.array(v) for f, v in map_in_parts(run, index, FLAT_CPU_CHUNK, 16).items()}


# Above psi_BC (by this relative margin) the steady cycle from a gross-slip history is the
# Base-Cycle stretched by full slip at both ends, whose k is closed-form.
STRETCH_MARGIN = 1e-9


@batch_jit
def stretched_curves(shapes, mu, contacts, load, psi):
    """Per (design, amplitude): k of the stretched Base-Cycle, whether it is the steady cycle from
    gross slip there (Base-Cycle ok and psi >= psi_BC (1 + STRETCH_MARGIN)), and the Base-Cycle's
    pairs of halves."""

    def one(s, m, c, ld, p):
        bc = base_cycle_kernel(s, m, c, ld)
        k_re, k_im, _ = jax.vmap(lambda a: gross_slip_stiffness(bc, a))(p)
        use = (bc.status == RESULTS.ok) & (p >= base_cycle_amplitude(bc) * (1 + STRETCH_MARGIN))
        return k_re, k_im, use, jnp.broadcast_to(bc.half_cycles // 2, p.shape)

    return jax.vmap(one)(shapes, mu, contacts, load, psi)


def padded_index(index: np.ndarray) -> np.ndarray:
    """index padded by repeating its first entry (0 if empty) to `runtime.padded_size` (eight steps
    per octave, at least 16): a new count rarely compiles a new program, and at most ~1/8 of the
    work is padding."""
    size = padded_size(index.size, 16, 8)
    first = index[0] if index.size else 0
    return np.concatenate([index, np.full(size - index.size, first, dtype=index.dtype)])


def prepare_curves_inputs(shapes, mu, contacts, load, psi_a_mrad, initial, stacklevel=4):
    """A batch of curves checked (ValueError naming the parameter and its range; the
    small-rotation warning; Float64Required in float32) and broadcast: (the designs (shapes, mu,
    contacts, load) with a leading axis of the batch's size, numpy, and the amplitudes (designs,
    amplitudes))."""
    require_x64()
    if initial not in INITIAL_STATES:
        raise ValueError(f"initial must be one of {', '.join(INITIAL_STATES)}; got {initial!r}")
    check_types(shape=shapes, contacts=contacts, load=load)
    validate_shape(shapes)
    validate_mu(mu)
    validate_contacts(contacts)
    validate_load(load)
    check_range("psi_a_mrad", psi_a_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    warn_small_rotation(psi_a_mrad, "psi_a", stacklevel=stacklevel)
    psi = np.asarray(psi_a_mrad, float)
    if psi.ndim not in (1, 2) or psi.size == 0:
        raise ValueError("psi_a_mrad must be a non-empty (amplitudes,) or (designs, amplitudes) "
                         "array in (0, 10000] mrad")
    # Every leaf an array (a list of mu is one leaf, not a pytree of numbers), then one batch
    # length: each leaf a scalar or (designs,); kn, kt also (3,) shared per pad or (designs, 3).
    args = jax.tree_util.tree_map(lambda v: np.asarray(v, float),
                                  (shapes, np.asarray(mu, float), contacts, load))
    size = max(batch_size(args), psi.shape[0] if psi.ndim == 2 else 1)
    named = [*zip(DamperShape._fields, args[0]), ("mu", args[1]), *zip(Contacts._fields, args[2]),
             *zip(LoadCase._fields, args[3])]
    for name, v in named:
        per_pad = name in Contacts._fields
        shape = np.shape(v)
        if not (shape in ((), (size,)) or (per_pad and shape in ((3,), (size, 3)))):
            raise ValueError(f"{name}: a scalar or one per design ({size},)"
                             f"{f' or per pad (3,) / ({size}, 3)' if per_pad else ''}; got shape "
                             f"{shape}")
    if psi.ndim == 2 and psi.shape[0] != size:
        raise ValueError(f"psi_a_mrad: (amplitudes,) or ({size}, amplitudes); got {psi.shape}")
    return broadcast_designs(args, size, np), np.broadcast_to(psi, (size, psi.shape[-1]))


def cycle_curves(shapes: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                 load: LoadCase = LoadCase(), *, initial="gross_slip",
                 max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS,
                 runner=None) -> StiffnessCurves:
    """`jaxdamp.amplitude_curves` by one steady cycle per (design, amplitude) (method "cycles"):
    k_Re, k_Im (N mm/mrad) of the steady cycles of many designs over an amplitude grid, in one
    batched call. shapes / mu / contacts / load: every leaf with a leading design axis or a scalar
    shared by all (as `cycle.base_cycles`; a per-contact (3,) stiffness of a batch of 3 designs is
    read as one value per design). psi_a_mrad: (amplitudes,) shared or (designs, amplitudes), > 0.
    initial: "gross_slip" or "assembly". Returns StiffnessCurves with (designs, amplitudes) arrays.

    Concrete inputs: from a gross-slip history, amplitudes at or above a design's psi_BC take the
    Base-Cycle stretched by full slip at both ends, which is the steady cycle there (closed-form k;
    the same numbers as the cycle to ~1e-11, tests/test_amplitude.py); the other (design,
    amplitude) pairs run in two stages: one pair of halves each, then the full iteration only where
    the cycle did not close in one pair. Traced inputs (inside jit / grad) run `curves_kernel`,
    every cycle by the direct method. runner(program, args) -> outputs runs each stage's program
    instead of a plain call (the CLI passes its saved-program cache).
    """

    leaves = jax.tree_util.tree_leaves((shapes, mu, contacts, load, psi_a_mrad))
    if not all(is_concrete(x) for x in leaves):
        return curves_kernel(shapes, mu, contacts, load, psi_a_mrad, initial=initial,
                             max_tracts=max_tracts, max_pairs=max_pairs)
    designs, psi = prepare_curves_inputs(shapes, mu, contacts, load, psi_a_mrad, initial)
    size, n_amp = psi.shape
    flat_psi = psi.reshape(-1)
    if initial == "gross_slip":
        k_re, k_im, use, pairs = (np.array(x).reshape(-1) for x in run_program(
            stretched_curves, (*designs, jnp.asarray(psi)), runner))
    else:
        k_re, k_im, pairs = (np.zeros(flat_psi.size) for _ in range(3))
        use = np.zeros(flat_psi.size, bool)
    out = StiffnessCurves(flat_psi, k_re, k_im, np.where(use, RESULTS.ok, 0).astype(np.int32),
                          pairs.astype(np.int32))
    todo = np.nonzero(~use)[0]
    if todo.size:
        # The remaining (design, amplitude) pairs, flattened, so that the second stage re-runs
        # only the pairs that need it; both stages through one program (its pair budget is an
        # input), which on the CPU also has one shape (`FLAT_CPU_CHUNK`).
        program = _flat_program(initial, max_tracts, max_pairs)
        cyc = _cycles_at(program, designs, n_amp, flat_psi, todo, _budget(max_pairs, 1), runner)
        again = np.nonzero(cyc["status"] == RESULTS.not_converged)[0]
        if max_pairs > 1 and again.size:
            rerun = _cycles_at(program, designs, n_amp, flat_psi, todo[again], _budget(max_pairs),
                               runner)
            for f, v in cyc.items():
                v[again] = rerun[f]
        for f, v in cyc.items():
            getattr(out, f)[todo] = v
    return jax.tree_util.tree_map(lambda x: jnp.asarray(x).reshape(size, n_amp), out)


def check_curve_request(designs, psi_lo, psi_hi, grid, initial, N_init, T_init) -> None:
    """`sequence.stiffness_curve`'s designs, amplitudes (psi_lo to psi_hi, or an ascending grid,
    mrad) and start (a named history, or initial="explicit" with N_init, T_init), checked:
    ValueError in one line naming the parameter and what it takes."""
    if initial not in INITIAL_STATES + ("explicit",):
        raise ValueError(f"initial must be one of {', '.join(INITIAL_STATES)}, explicit; "
                         f"got {initial!r}")
    if not isinstance(designs, tuple) or len(designs) != 4:
        raise ValueError(f"designs must be a batch of designs (shapes, mu, contacts, load), e.g. "
                         f"jaxdamp.stack_designs(...); got {type(designs).__name__}")
    shapes, mu, contacts, load = designs
    validate_shape(shapes)
    validate_mu(mu)
    validate_contacts(contacts)
    validate_load(load)
    if grid is None:
        if psi_lo is None or psi_hi is None:
            raise ValueError("give psi_lo and psi_hi (mrad), or grid")
        check_range("psi_lo", psi_lo, 0.0, 1e4, lo_open=True, unit="mrad")
        check_range("psi_hi", psi_hi, 0.0, 1e4, lo_open=True, unit="mrad")
        if np.any(np.asarray(psi_hi, float) < np.asarray(psi_lo, float)):
            raise ValueError(f"psi_hi must be >= psi_lo (mrad); got psi_lo {psi_lo!r:.40}, "
                             f"psi_hi {psi_hi!r:.40}")
    else:
        check_range("grid", grid, 0.0, 1e4, lo_open=True, unit="mrad")
        if np.any(np.diff(np.asarray(grid, float), axis=-1) < 0.0):
            raise ValueError("grid must be ascending along its last axis (mrad)")
    if initial == "explicit" and (N_init is None or T_init is None):
        raise ValueError('initial="explicit" needs N_init and T_init, (designs, 3) each')
    if initial != "explicit" and (N_init is not None or T_init is not None):  # were ignored
        raise ValueError(f'N_init and T_init are for initial="explicit"; got initial={initial!r}')
