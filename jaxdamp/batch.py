"""Many designs at once: batched pytrees, device-sharded evaluation, and design-space sweeps.

`jaxdamp.base_cycle` works under `jax.vmap` over any pytree of designs (e.g. the output of
`stack_designs`). `evaluate_designs` runs a batch sharded over the available devices with
`jax.sharding` (one CPU device by default; several GPUs/TPUs, hosts, or
XLA_FLAGS=--xla_force_host_platform_device_count=N): the batch is padded to a multiple of the
device count, split along its leading axis by a `NamedSharding`, and each device runs its share.
`sweep` evaluates a theta_L x theta_R grid at several mu, with b_R fixed or chosen by the paper's
centring rule, and flags liftoff and non-converged points (`jaxdamp sweep`, in jaxdamp.cli.sweep,
writes heatmaps and data).
"""

from __future__ import annotations

import functools
from typing import NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np
from jax.experimental import multihost_utils
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from ._validate import check_values, require_x64
from .cycle import MAX_PAIRS, MAX_TRACTS, BaseCycle, base_cycle_kernel
from .design import Design, check_batch
from .energy import work_shape_factors
from .geometry import WEDGE_REFUSED, DamperShape, validate_shape
from .harmonics import five_numbers
from .params import (Contacts, LoadCase, check_param, check_types, validate_contacts, validate_load,
                     validate_mu)
from .runtime import batch_jit, padded_size
from .statics import design_br_kernel
from .status import RESULTS, number_repr, status_repr

AXIS = "designs"
MIN_BATCH = 16  # smallest compiled batch: small batches are padded up to it


class DesignSummary(NamedTuple):
    """Per-design results (numpy arrays with the batch shape). psi in mrad, k in N mm/mrad, w_*
    dimensionless (Appendix C). Values of designs whose status is not ok are not a damper's."""

    psi_fs: np.ndarray
    k_re_fs: np.ndarray
    psi_bc: np.ndarray
    k_re_bc: np.ndarray
    k_im_bc: np.ndarray
    w_R1: np.ndarray
    w_L1: np.ndarray
    w_L2: np.ndarray
    w_M: np.ndarray
    half_cycles: np.ndarray
    status: np.ndarray  # jaxdamp.RESULTS codes

    def __repr__(self) -> str:
        return (f"DesignSummary(status={status_repr(self.status)}, "
                f"psi_bc={number_repr(self.psi_bc, 'mrad')}, k_im_bc={number_repr(self.k_im_bc, 'N mm/mrad')}, "
                f"w_M={number_repr(self.w_M)})")


def _rows(name, value, n, per_contact):
    """Broadcast a shared value to the batch: (n,) or, for per-contact stiffness (3,), (n, 3)."""
    a = np.asarray(value, dtype=float)
    target = (n, 3) if per_contact else (n,)
    try:
        return np.broadcast_to(a, target).copy()
    except ValueError:
        raise ValueError(f"{name} must be a scalar or have {n} entries (one per design); "
                         f"got shape {a.shape}") from None


def _batch_len(name, value, sizes):
    if value is not None and np.ndim(value) > 0:
        sizes[name] = np.shape(value)[0]


def stack_designs(shapes, mu, contacts: Contacts | Sequence[Contacts] = Contacts(),
                  load: LoadCase | Sequence[LoadCase] = LoadCase()) -> Design:
    """Turn designs into one batched pytree.

    shapes: a sequence of DamperShape, or one DamperShape whose fields are arrays (n,) or scalars.
    mu: a scalar (shared) or one value per design.
    contacts: one Contacts shared by every design (kn, kt scalars or (3,) per contact, as in
        `Contacts`), or a sequence of Contacts, one per design.
    load: one LoadCase (fields scalars or (n,) arrays) or a sequence of LoadCase, one per design.
    Raises ValueError naming the parameter for out-of-range values or mismatched lengths.
    """
    sizes: dict = {}
    if not isinstance(contacts, Contacts) and not (
            isinstance(contacts, (list, tuple)) and all(isinstance(c, Contacts) for c in contacts)):
        raise TypeError(f"contacts must be a jaxdamp.Contacts or a sequence of them; got "
                        f"{type(contacts).__name__}")
    if not isinstance(load, LoadCase) and not (
            isinstance(load, (list, tuple)) and all(isinstance(ld, LoadCase) for ld in load)):
        raise TypeError(f"load must be a jaxdamp.LoadCase or a sequence of them; got "
                        f"{type(load).__name__}")
    named = [("mu", mu)]
    if isinstance(shapes, DamperShape):
        named += list(zip(DamperShape._fields, shapes))
    if isinstance(contacts, Contacts):
        named += list(zip(Contacts._fields, contacts))
    for name, v in named:  # text and None are no numbers (numpy would read "0.5" as one)
        if isinstance(v, (str, bytes)) or (v is None and name not in ("x_d", "br2_over_hr")):
            raise ValueError(f"{name} must be numbers (a scalar or one per design); got {v!r}")
    if isinstance(shapes, DamperShape):
        shape = shapes
    else:
        if not isinstance(shapes, (list, tuple)):
            raise ValueError("shapes must be a DamperShape or a non-empty sequence of DamperShape; "
                             f"got {type(shapes).__name__}")
        shapes = list(shapes)
        if not shapes or not all(isinstance(s, DamperShape) for s in shapes):
            raise ValueError("shapes must be a DamperShape or a non-empty sequence of DamperShape")
        if any(s.br2_over_hr is not None for s in shapes):  # stacking the fields would drop it
            raise ValueError(WEDGE_REFUSED)
        with_xd = [s.x_d is not None for s in shapes]
        if any(with_xd) and not all(with_xd):
            raise ValueError("x_d must be given for every shape or for none")
        fields = [[getattr(s, f) for s in shapes] for f in DamperShape._fields]
        shape = DamperShape(*fields[:4], fields[4] if all(with_xd) else None)
        sizes["shapes"] = len(shapes)
    for name, v in zip(DamperShape._fields, shape):
        _batch_len(name, v, sizes)
    _batch_len("mu", mu, sizes)
    if isinstance(contacts, Contacts):
        per_design_k = False
        kn, kt = np.asarray(contacts.kn, float), np.asarray(contacts.kt, float)
    else:
        contacts = list(contacts)
        per_design_k = True
        kn = np.asarray([c.kn for c in contacts], float)
        kt = np.asarray([c.kt for c in contacts], float)
        sizes["contacts"] = len(contacts)
    if not isinstance(load, LoadCase):
        load = list(load)
        sizes["load"] = len(load)
        load = LoadCase(*(np.asarray(v, float) for v in zip(*load)))
    for name, v in zip(LoadCase._fields, load):
        _batch_len(name, v, sizes)
    lengths = set(sizes.values())
    if len(lengths) > 1:
        raise ValueError("batch lengths differ: " + ", ".join(f"{k}={v}" for k, v in sizes.items()))
    n = lengths.pop() if lengths else 1
    if n < 1:
        raise ValueError("a batch needs at least one design")
    shape = DamperShape(*(None if v is None else _rows(f, v, n, False)
                          for f, v in zip(DamperShape._fields, shape)))
    per_contact = lambda k: k.ndim == (2 if per_design_k else 1)  # noqa: E731
    contacts = Contacts(_rows("kn", kn, n, per_contact(kn)), _rows("kt", kt, n, per_contact(kt)))
    designs = Design(shape, _rows("mu", mu, n, False), contacts,
                      LoadCase(*(_rows(f, v, n, False) for f, v in zip(LoadCase._fields, load))))
    validate_shape(designs.shape)
    validate_mu(designs.mu)
    validate_contacts(designs.contacts)
    validate_load(designs.load)
    return designs


def take(tree, idx):
    """Rows idx of every leaf of a batched pytree (numpy; None leaves stay None)."""
    return jax.tree_util.tree_map(lambda x: None if x is None else np.asarray(x)[idx], tree)


def device_mesh(devices=None) -> Mesh:
    """A 1-D mesh over `devices` (default: all of `jax.devices()`, every process's under
    `jax.distributed`) with the batch axis "designs"."""
    devices = jax.devices() if devices is None else list(devices)
    return Mesh(np.array(devices), (AXIS,))


def shard(batched, mesh: Mesh):
    """Place a batched pytree on the mesh, split along its leading axis (a multiple of the mesh
    size) by a NamedSharding: what `map_batched` does with every chunk.

    Under `jax.distributed` the mesh spans every process's devices: each process holds the whole
    (host) batch and hands each of its own devices that device's rows."""
    sharding = NamedSharding(mesh, PartitionSpec(AXIS))
    if mesh.is_multi_process:
        return jax.tree_util.tree_map(
            lambda x: jax.make_array_from_callback(np.shape(x), sharding,
                                                   lambda idx, x=np.asarray(x): x[idx]), batched)
    return jax.device_put(batched, sharding)


def gather(out) -> object:
    """A sharded result as numpy on this host; under `jax.distributed`, every process gets the
    whole result (an all-gather over processes)."""
    leaves = jax.tree_util.tree_leaves(out)
    if leaves and not all(getattr(x, "is_fully_addressable", True) for x in leaves):
        out = multihost_utils.process_allgather(out, tiled=True)
    return jax.tree_util.tree_map(np.asarray, out)


# ---------------------------------------------------------------- the one batching path
# Designs per device per compiled call, by platform. CPU: the fastest of the committed chunk sweep
# on 2 host devices (benchmarks/results/batch.json, "chunk_sweep"); larger chunks only add memory.
# GPU: a GPU idles between small calls; 131072 per device measured 26x the throughput of 1024 on
# one H100 (issue 18), and the chunk is further bounded by free device memory (`default_chunk`).
CHUNK_BY_PLATFORM = {"cpu": 1024, "gpu": 131072, "cuda": 131072, "rocm": 131072, "tpu": 65536}
# Device memory one design may use while a chunk runs (inputs, the scan carries of both stages and
# the outputs are a few kB; 64 kB leaves room for XLA's temporaries), and the share of free memory a
# chunk may take.
BYTES_PER_DESIGN = 64 * 1024
MEMORY_SHARE = 0.5


def default_chunk(platform: str, free_bytes: int | None = None) -> int:
    """Designs per device per call for a platform ("cpu", "gpu", ...), bounded by free memory (bytes)
    when it is known: at most MEMORY_SHARE of it at BYTES_PER_DESIGN each, rounded down to a power of
    two, and never below MIN_BATCH."""
    chunk = CHUNK_BY_PLATFORM.get(platform, CHUNK_BY_PLATFORM["cpu"])
    if free_bytes is not None:
        fit = int(free_bytes * MEMORY_SHARE // BYTES_PER_DESIGN)
        if fit < chunk:
            chunk = 1 << max(int(np.log2(max(fit, 1))), 0)
    return max(chunk, MIN_BATCH)


def _free_bytes(device) -> int | None:
    try:
        stats = device.memory_stats()
    except Exception:  # noqa: BLE001 - CPU clients raise or return None: memory is not the bound
        return None
    if not stats or "bytes_limit" not in stats:
        return None
    return int(stats["bytes_limit"] - stats.get("bytes_in_use", 0))


# Values-only programs (`evaluate_designs`, `base_cycles`) hold a few kB per design, so on a CPU a
# larger chunk amortises XLA's fixed cost per kernel: with the compiler options of
# `jaxdamp.runtime`, 8192 ran ~1.4x the designs/s of 1024 and 16384 less again
# (benchmarks/results/cpu_runtime_options.json, the "default" worker's chunk_* sweep).
# Programs with derivatives keep CHUNK_BY_PLATFORM: reverse mode at 8192 took 3.5 GB.
VALUES_CHUNK_BY_PLATFORM = {"cpu": 8192}


def values_chunk(devices=None) -> int | None:
    """The chunk of values-only batches on `devices` (default: all), or None for the platform's
    default (`default_chunk`)."""
    return VALUES_CHUNK_BY_PLATFORM.get(device_mesh(devices).devices.flat[0].platform)


def device_chunk(mesh: Mesh) -> int:
    """`default_chunk` for the mesh's first device (all devices of a mesh are alike)."""
    dev = mesh.devices.flat[0]
    return default_chunk(dev.platform, _free_bytes(dev))


def bucket_size(n: int, ndev: int, chunk: int) -> int:
    """Batch size actually compiled: chunk designs per device for large batches; for small ones the
    next power of two, at least MIN_BATCH, so that many batch sizes share a few compiled programs;
    always a multiple of ndev."""
    size = min(chunk * ndev, padded_size(n, MIN_BATCH))
    return -(-size // ndev) * ndev


@functools.cache
def _compiled(fn, in_axes):
    """One compiled, vmapped program per kernel and in_axes, for the life of the process."""
    return batch_jit(jax.vmap(fn, in_axes=in_axes))


def batch_length(batched) -> int:
    """The leading (batch) axis shared by every leaf of a batched pytree: ValueError in one line
    where a leaf has none or the lengths differ (map_batched never cuts an axis)."""
    leaves = jax.tree_util.tree_leaves(batched)
    if not leaves:
        raise ValueError("batched: a pytree with at least one array leaf (n, ...)")
    lengths = {np.shape(x)[0] if np.ndim(x) else None for x in leaves}
    if None in lengths:
        raise ValueError("batched: every leaf needs a leading batch axis (n, ...); a scalar leaf "
                         "goes in as a shared argument, or broadcast it (jaxdamp.stack_designs)")
    if len(lengths) > 1:
        raise ValueError(f"batched: the leaves' leading axes differ ({sorted(lengths)}); every "
                         "leaf must have the same batch length (no axis is cut)")
    n = lengths.pop()
    if n < 1:
        raise ValueError("batched: a batch needs at least one item")
    return int(n)


def map_batched(fn, batched, *shared, devices=None, chunk_size: int | None = None,
                progress=None):
    """fn(item, *shared) over the leading axis of the pytree `batched`: numpy pytree out.

    The one batching path of jaxdamp (Base-Cycles, summaries, sweeps, Jacobians, the optimiser):
    the batch is cut into chunks of chunk_size designs per device (default: `default_chunk` for the
    platform and its free memory), each padded with copies of its first item to a bucket size
    (`bucket_size`) so that jit does not recompile per batch size, and sharded along its leading
    axis over the devices of `device_mesh(devices)` with a NamedSharding. All chunks are dispatched
    before any result is read, so host and devices overlap. `fn` must be a stable (module-level)
    function: its jit(vmap) is cached by identity. progress(k) is called after each chunk is read.
    """
    if chunk_size is not None and (isinstance(chunk_size, bool)  # text or NaN: int()'s errors
                                   or not isinstance(chunk_size, (int, np.integer)) or chunk_size < 1):
        raise ValueError(f"chunk_size must be an integer >= 1; got {chunk_size!r}")
    if not callable(fn):
        raise ValueError(f"fn must be a function; got {type(fn).__name__}")
    if progress is not None and not callable(progress):  # it failed after the first chunk ran
        raise ValueError(f"progress must be a function; got {type(progress).__name__}")
    n = batch_length(batched)
    mesh = device_mesh(devices)
    ndev = mesh.devices.size
    chunk = device_chunk(mesh) if chunk_size is None else int(chunk_size)
    size = bucket_size(n, ndev, chunk)
    run = _compiled(fn, (0,) + (None,) * len(shared))
    pending = []
    for start in range(0, n, size):
        idx = np.arange(start, min(start + size, n))
        count = idx.size
        idx = np.concatenate([idx, np.full(size - count, idx[0])])
        pending.append((count, run(shard(take(batched, idx), mesh), *shared)))
    parts = []
    for count, out in pending:
        parts.append(jax.tree_util.tree_map(lambda x, k=count: x[:k], gather(out)))
        if progress is not None:
            progress(count)
    return jax.tree_util.tree_map(lambda *xs: np.concatenate(xs, 0), *parts)


def two_stage(fast, full, batched, *shared, unfinished, **kwargs):
    """map_batched(fast) for every item, then map_batched(full) only where unfinished(result) is
    True. Under vmap every design pays for the slowest: a frozen mechanism needs several pairs of
    half-cycles, almost every other design one, so the second stage runs the long iteration only
    for the few that need it."""
    out = map_batched(fast, batched, *shared, **kwargs)
    again = np.nonzero(unfinished(out))[0]
    if again.size == 0:
        return out
    rerun = map_batched(full, take(batched, again), *shared, **kwargs)
    out = jax.tree_util.tree_map(np.array, out)
    for a, b in zip(jax.tree_util.tree_leaves(out), jax.tree_util.tree_leaves(rerun)):
        a[again] = b
    return out


# How a batch runs its tract and pair loops (base_cycle_kernel's loop). Under vmap a while loop runs
# until the batch's slowest design is done: the first stage's short loops are full for almost every
# design, so it scans; the second stage's designs need few of its many slots, so it stops when done
# (the same numbers; 2.4 ms instead of 3.9 ms for the 233 designs of 16384 random ones it reran).
BATCH_LOOP = "scan"
SECOND_STAGE_LOOP = "while"


def _not_closed(r) -> np.ndarray:
    """Rerun in the second stage: the Base-Cycle did not close within one pair of half-cycles
    (ill-conditioned ones too: their rerun gives the same numbers, and the status cannot say
    whether they closed)."""
    return np.isin(np.asarray(r.status), (RESULTS.not_converged, RESULTS.ill_conditioned))


def _cycle_one_pair(design: Design):
    return base_cycle_kernel(*design, max_pairs=1, loop=BATCH_LOOP)


def _cycle_full(design: Design):
    return base_cycle_kernel(*design, loop=SECOND_STAGE_LOOP)


def base_cycles(shapes, mu=None, contacts: Contacts = Contacts(), load: LoadCase = LoadCase(), *,
                devices=None, chunk_size: int | None = None) -> BaseCycle:
    """Base-Cycles of a batch of designs (a batched Design, or shapes/mu/contacts/load whose leaves
    have a leading batch axis or are shared scalars). The same numbers as calling `base_cycle`
    design by design; numpy leaves. Float64Required in float32; shapes/mu/contacts/load are
    checked by `stack_designs`, a batched Design by `jaxdamp.design.check_batch` (the batched
    entry points' one input boundary)."""
    require_x64()
    if not isinstance(shapes, Design) and mu is None:
        raise ValueError("mu is required with shapes (a scalar or one per design in (0, 5]), or "
                         "give a batched Design")
    designs = (check_batch(shapes) if isinstance(shapes, Design)
               else stack_designs(shapes, mu, contacts, load))
    chunk = values_chunk(devices) if chunk_size is None else chunk_size
    return two_stage(_cycle_one_pair, _cycle_full, designs, unfinished=_not_closed,
                     devices=devices, chunk_size=chunk)


# Tracts per half-cycle in the first stage of `evaluate_designs`: a half-cycle of random designs
# needs at most 3 tracts plus the step that finds gross slip in ~99 % of cases (4096 random designs:
# 1.1 % need more and are rerun by the second stage at MAX_TRACTS); 4 instead of 6 measured 1.4x.
FIRST_STAGE_TRACTS = 4


def summary_kernel(design: Design, max_pairs: int = MAX_PAIRS,
                   max_tracts: int = MAX_TRACTS, loop: str = BATCH_LOOP) -> DesignSummary:
    """Five numbers, work shape factors and status of one prepared Design (traceable)."""
    bc = base_cycle_kernel(*design, max_pairs=max_pairs, max_tracts=max_tracts, loop=loop)
    nums = five_numbers(bc)
    w = work_shape_factors(bc)
    return DesignSummary(*nums.numbers(), *w, bc.half_cycles, bc.status)


def first_stage_summary(design: Design) -> DesignSummary:
    """`summary_kernel` of the first stage: one pair of half-cycles of FIRST_STAGE_TRACTS tracts."""
    return summary_kernel(design, 1, FIRST_STAGE_TRACTS)


def needs_second_stage(r) -> np.ndarray:
    """Rerun in the second stage: not closed, or failed (`singular`, which includes half-cycles
    that ran out of the first stage's FIRST_STAGE_TRACTS; a half that continues from such an
    unfinished one may even lift off spuriously, which is why the Base-Cycle reports `singular`
    before `liftoff`), or ill-conditioned (the status cannot say whether it closed; a rerun gives
    the same numbers). Finished: ok and liftoff. A design that fails for good fails again there."""
    return ~np.isin(np.asarray(r.status), (RESULTS.ok, RESULTS.liftoff))


def _summary_full(design: Design) -> DesignSummary:
    return summary_kernel(design, MAX_PAIRS, loop=SECOND_STAGE_LOOP)


def evaluate_designs(designs: Design, *, devices=None, chunk_size: int | None = None,
                     progress=None) -> DesignSummary:
    """Five numbers, work shape factors and status of every design in the batch (numpy arrays).

    Sharded over `devices` (default: all, every process's under jax.distributed), chunk_size
    designs per device per call (default: `values_chunk` on a CPU, else `default_chunk`), in two
    stages (`two_stage`: one pair of half-cycles of at most FIRST_STAGE_TRACTS tracts, then the
    full iteration for the designs that did not finish). The results equal `base_cycle` design by
    design (see tests/test_batch.py for the one known exception at rounding level, k_Re,BC).
    """
    designs = check_batch(designs)
    chunk = values_chunk(devices) if chunk_size is None else chunk_size
    return two_stage(first_stage_summary, _summary_full, designs, unfinished=needs_second_stage,
                     devices=devices, chunk_size=chunk, progress=progress)


# ---------------------------------------------------------------- sweep
class SweepResult(NamedTuple):
    """A theta_L x theta_R x mu grid. Per-point arrays have shape (n_mu, n_theta_l, n_theta_r)."""

    theta_l: np.ndarray  # deg, (n_l,)
    theta_r: np.ndarray  # deg, (n_r,)
    mu: np.ndarray  # (n_mu,)
    br_over_hr: np.ndarray  # (n_l, n_r): fixed, or the centring rule's value at mu_max
    # Masks of the grid (docs/api.md, "Statuses and masks"): where the centring rule found b_R
    # (else the points' `status` is no_root) and where a b_R keeps the resultant inside L1-L2
    br_found: np.ndarray  # (n_l, n_r) False where the centring rule has no root (b_R meaningless)
    br_inside: np.ndarray  # (n_l, n_r) False where no b_R keeps the resultant inside L1-L2 at mu_max
    mu_max: float | None  # None when b_R is fixed
    bl2_over_hl: float
    kn: float
    kt: float
    summary: DesignSummary

    def __repr__(self) -> str:
        """One line: the grid, the shared contact pair and its designs' statuses by name (a sweep
        has no status of its own: each point's is in summary.status)."""
        return (f"SweepResult(theta_l={number_repr(self.theta_l, 'deg')}, "
                f"theta_r={number_repr(self.theta_r, 'deg')}, mu={number_repr(self.mu)}, "
                f"kn={number_repr(self.kn, 'N/mm')}, kt={number_repr(self.kt, 'N/mm')}, "
                f"status={status_repr(self.status)})")

    @property
    def status(self) -> np.ndarray:
        """(n_mu, n_l, n_r) RESULTS codes of the points: no_root where the centring rule has no
        b_R (br_found, a mask of the grid), else the design's own (summary.status); a working
        damper is `status == RESULTS.ok`."""
        found = np.broadcast_to(np.asarray(self.br_found)[None], np.shape(self.summary.status))
        return np.asarray(RESULTS.first({RESULTS.no_root: ~found}, self.summary.status))


@jax.jit
def _centring(theta_l, theta_r, bl2_over_hl, mu_max):
    def one(tl, tr):
        return design_br_kernel(DamperShape(tl, tr, 0.0, bl2_over_hl), mu_max, -0.45, 0.45)

    return jax.vmap(one)(theta_l, theta_r)


def centred_br(theta_l, theta_r, mu_max=0.7, bl2_over_hl=0.8):
    """The paper's centring rule (jaxdamp.design_br) for arrays of angles: (br, found, inside).
    Checked (ValueError naming the parameter and its range; Float64Required in float32)."""
    require_x64()
    check_param("theta_l", theta_l)  # numbers in range: None, text or NaN refused in one line
    check_param("theta_r", theta_r)
    check_values("mu", mu_max, "mu_max", max_ndim=0)
    try:
        tl, tr = np.broadcast_arrays(np.asarray(theta_l, float), np.asarray(theta_r, float))
    except ValueError:
        raise ValueError(f"theta_l and theta_r must broadcast to one grid; got shapes "
                         f"{np.shape(theta_l)} and {np.shape(theta_r)}") from None
    validate_shape(DamperShape(tl, tr, 0.0, bl2_over_hl))
    validate_mu(mu_max, "mu_max")
    res = _centring(jnp.asarray(tl.ravel()), jnp.asarray(tr.ravel()), jnp.asarray(bl2_over_hl, float),
                    jnp.asarray(mu_max, float))
    return tuple(np.asarray(a).reshape(tl.shape) for a in (res.br_over_hr, res.found, res.inside))


def check_sweep_inputs(theta_l, theta_r, mu, br_over_hr="centred", *, mu_max=None,
                       bl2_over_hl=0.8, contacts: Contacts = Contacts(),
                       load: LoadCase = LoadCase()):
    """Validate a sweep's inputs without computing anything (ValueError naming the parameter and
    its range; Float64Required in float32); returns (theta_l, theta_r, mu) as 1-D float arrays.
    `sweep` calls it first."""
    require_x64()
    tl, tr, mus = (np.atleast_1d(check_values(name, v))
                   for name, v in (("theta_l", theta_l), ("theta_r", theta_r), ("mu", mu)))
    check_types(contacts=contacts, load=load)
    for name, v in (("theta_l", tl), ("theta_r", tr), ("mu", mus)):
        if v.ndim != 1 or v.size == 0:
            raise ValueError(f"{name} must be a non-empty 1-D sequence")
    validate_mu(mus)
    if isinstance(br_over_hr, str):
        if br_over_hr not in ("centred", "centered"):
            raise ValueError(f"br_over_hr must be a number in [-0.5, 0.5] or 'centred'; "
                             f"got {br_over_hr!r}")
        br = 0.0
        if mu_max is not None:
            validate_mu(mu_max, "mu_max")
    else:
        br = br_over_hr  # a fixed b_R is checked, never clipped into range
    validate_shape(DamperShape(tl[:, None], tr[None, :], br, bl2_over_hl))
    if np.ndim(contacts.kn) or np.ndim(contacts.kt):
        raise ValueError("sweep takes scalar kn, kt (shared by R1, L1, L2)")
    validate_contacts(contacts)
    validate_load(load)
    return tl, tr, mus


def sweep(theta_l, theta_r, mu, br_over_hr="centred", *, mu_max=None, bl2_over_hl=0.8,
          contacts: Contacts = Contacts(), load: LoadCase = LoadCase(), devices=None,
          chunk_size: int | None = None, progress=None) -> SweepResult:
    """Evaluate every (mu, theta_l, theta_r) of a grid.

    br_over_hr: a number (fixed b_R/h_R, in [-0.5, 0.5]) or "centred": the paper's rule, which puts
    the left resultant equidistant from L1 and L2 at mu_max (default: the largest mu of the sweep).
    Every input is validated (`check_sweep_inputs`) before anything is computed.
    progress: passed to `evaluate_designs`.
    """
    tl, tr, mus = check_sweep_inputs(theta_l, theta_r, mu, br_over_hr, mu_max=mu_max,
                                     bl2_over_hl=bl2_over_hl, contacts=contacts, load=load)
    L, R = np.meshgrid(tl, tr, indexing="ij")
    if isinstance(br_over_hr, str):
        mu_max = float(mus.max()) if mu_max is None else float(mu_max)
        br, found, inside = centred_br(L, R, mu_max, bl2_over_hl)
    else:
        mu_max = None
        br = np.full(L.shape, float(br_over_hr))
        found = inside = np.ones(L.shape, bool)
    # Points without a centring root still run (with the bisection's end value) and are masked.
    grid = lambda a: np.broadcast_to(a, (mus.size,) + L.shape).ravel()  # noqa: E731
    shape = DamperShape(grid(L), grid(R), grid(np.clip(br, -0.5, 0.5)), bl2_over_hl)
    designs = stack_designs(shape, grid(mus[:, None, None]), contacts, load)
    out = evaluate_designs(designs, devices=devices, chunk_size=chunk_size, progress=progress)
    out = DesignSummary(*(a.reshape((mus.size,) + L.shape) for a in out))
    return SweepResult(tl, tr, mus, br, found, inside, mu_max, float(bl2_over_hl),
                       float(contacts.kn), float(contacts.kt), out)


__all__ = ["AXIS", "MIN_BATCH", "DesignSummary", "stack_designs", "take", "device_mesh", "shard",
           "gather", "CHUNK_BY_PLATFORM", "BYTES_PER_DESIGN", "MEMORY_SHARE", "default_chunk",
           "VALUES_CHUNK_BY_PLATFORM", "values_chunk", "device_chunk", "bucket_size",
           "batch_length", "map_batched", "two_stage", "BATCH_LOOP", "SECOND_STAGE_LOOP", "base_cycles",
           "FIRST_STAGE_TRACTS", "summary_kernel", "first_stage_summary", "needs_second_stage",
           "evaluate_designs", "SweepResult", "centred_br", "check_sweep_inputs", "sweep"]
