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

from functools import partial
from typing import NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from .cycle import MAX_PAIRS, MAX_TRACTS, _base_cycle
from .energy import work_shape_factors
from .geometry import DamperShape, validate_shape
from .harmonics import five_numbers
from .params import Contacts, LoadCase, validate_contacts, validate_load, validate_mu
from .statics import _design_br

AXIS = "designs"
DEFAULT_CHUNK = 1024  # designs per device per compiled call: the fastest measured on 2 host
# devices, within noise of the best on one (benchmarks/results/batch.json, "chunk_sweep")
MIN_BATCH = 16  # smallest compiled batch: small batches are padded up to it


class Designs(NamedTuple):
    """A batch of designs: every leaf has the batch as its leading axis (per-contact kn, kt: (n, 3)).

    `jax.vmap(jaxdamp.base_cycle)(*designs)` gives their Base-Cycles."""

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase

    @property
    def size(self) -> int:
        return int(np.shape(self.mu)[0])


class DesignSummary(NamedTuple):
    """Per-design results (numpy arrays with the batch shape). psi in mrad, k in N mm/mrad, w_*
    dimensionless (Appendix C). Values of liftoff / failed designs are not a damper's: check flags."""

    psi_fs: np.ndarray
    k_re_fs: np.ndarray
    psi_bc: np.ndarray
    k_re_bc: np.ndarray
    k_im_bc: np.ndarray
    w_R1: np.ndarray
    w_L1: np.ndarray
    w_L2: np.ndarray
    w_M: np.ndarray
    converged: np.ndarray
    liftoff: np.ndarray
    failed: np.ndarray
    half_cycles: np.ndarray


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
                  load: LoadCase | Sequence[LoadCase] = LoadCase()) -> Designs:
    """Turn designs into one batched pytree.

    shapes: a sequence of DamperShape, or one DamperShape whose fields are arrays (n,) or scalars.
    mu: a scalar (shared) or one value per design.
    contacts: one Contacts shared by every design (kn, kt scalars or (3,) per contact, as in
        `Contacts`), or a sequence of Contacts, one per design.
    load: one LoadCase (fields scalars or (n,) arrays) or a sequence of LoadCase, one per design.
    Raises ValueError naming the parameter for out-of-range values or mismatched lengths.
    """
    sizes: dict = {}
    if isinstance(shapes, DamperShape):
        shape = shapes
    else:
        shapes = list(shapes)
        if not shapes or not all(isinstance(s, DamperShape) for s in shapes):
            raise ValueError("shapes must be a DamperShape or a non-empty sequence of DamperShape")
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
    designs = Designs(shape, _rows("mu", mu, n, False), contacts,
                      LoadCase(*(_rows(f, v, n, False) for f, v in zip(LoadCase._fields, load))))
    validate_shape(designs.shape)
    validate_mu(designs.mu)
    validate_contacts(designs.contacts)
    validate_load(designs.load)
    return designs


def _take(tree, idx):
    return jax.tree_util.tree_map(lambda x: None if x is None else np.asarray(x)[idx], tree)


def device_mesh(devices=None) -> Mesh:
    """A 1-D mesh over `devices` (default: all of `jax.devices()`) with the batch axis "designs"."""
    devices = jax.devices() if devices is None else list(devices)
    return Mesh(np.array(devices), (AXIS,))


def _summary_one(shape, mu, contacts, load, max_pairs):
    bc = _base_cycle(shape, mu, contacts, load, max_tracts=MAX_TRACTS, max_pairs=max_pairs)
    nums = five_numbers(bc)
    w = work_shape_factors(bc)
    return DesignSummary(*nums, *w, bc.converged, bc.liftoff, bc.failed, bc.half_cycles)


@partial(jax.jit, static_argnames=("max_pairs",))
def _summaries(designs: Designs, max_pairs: int) -> DesignSummary:
    run = partial(_summary_one, max_pairs=max_pairs)
    return jax.vmap(run)(*designs)


def _padded_size(n, ndev, chunk):
    """Batch size actually compiled: chunk designs per device for large batches; for small ones the
    next power of two, at least MIN_BATCH (few programs for many sizes); a multiple of ndev."""
    small = max(MIN_BATCH, 1 << int(np.ceil(np.log2(max(n, 1)))))
    size = min(chunk * ndev, small)
    return -(-size // ndev) * ndev


def _run_sharded(designs: Designs, mesh: Mesh, chunk: int, max_pairs: int,
                 progress=None) -> DesignSummary:
    """Evaluate in chunks; each chunk is padded (with copies of its first design) and sharded over
    the mesh. All chunks are dispatched before any result is read, so host and devices overlap.
    progress(count) is called as each chunk's results arrive, with its number of designs."""
    n = designs.size
    size = _padded_size(n, mesh.devices.size, chunk)
    sharding = NamedSharding(mesh, PartitionSpec(AXIS))
    pending = []
    for start in range(0, n, size):
        idx = np.arange(start, min(start + size, n))
        count = idx.size
        idx = np.concatenate([idx, np.full(size - count, idx[0])])
        pending.append((count, _summaries(jax.device_put(_take(designs, idx), sharding), max_pairs)))
    parts = []
    for count, out in pending:
        parts.append(jax.tree_util.tree_map(lambda x, k=count: np.asarray(x)[:k], out))
        if progress is not None:
            progress(count)
    return DesignSummary(*(np.concatenate(xs) for xs in zip(*parts)))


def evaluate_designs(designs: Designs, *, devices=None, chunk_size: int = DEFAULT_CHUNK,
                     max_pairs: int = MAX_PAIRS, progress=None) -> DesignSummary:
    """Five numbers, work shape factors and flags of every design in the batch (numpy arrays).

    The batch is sharded over `devices` (default: all), chunk_size designs per device per call.
    Two stages, as `jaxdamp.base_cycles`: one forward/backward pair for every design, then the full
    iteration only for the designs whose cycle did not close in one pair (under vmap every design
    would otherwise pay for the longest iteration). The results equal `base_cycle` design by design
    (see tests/test_batch.py for the one known exception at rounding level, k_Re,BC).
    progress: None or a callable progress(count) told of every finished chunk of the first stage
    (count designs); the re-run of non-closed designs is not counted.
    """
    if not isinstance(designs, Designs):
        raise ValueError("designs must be a Designs batch (see jaxdamp.stack_designs)")
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be >= 1; got {chunk_size}")
    mesh = device_mesh(devices)
    out = _run_sharded(designs, mesh, chunk_size, 1, progress)
    again = np.nonzero(~(out.converged | out.liftoff | out.failed))[0]
    if max_pairs > 1 and again.size:
        rerun = _run_sharded(_take(designs, again), mesh, chunk_size, max_pairs)
        out = DesignSummary(*(np.array(a) for a in out))
        for a, b in zip(out, rerun):
            a[again] = b
    return out


# ---------------------------------------------------------------- sweep
class SweepResult(NamedTuple):
    """A theta_L x theta_R x mu grid. Per-point arrays have shape (n_mu, n_theta_l, n_theta_r)."""

    theta_l: np.ndarray  # deg, (n_l,)
    theta_r: np.ndarray  # deg, (n_r,)
    mu: np.ndarray  # (n_mu,)
    br_over_hr: np.ndarray  # (n_l, n_r): fixed, or the centring rule's value at mu_max
    br_found: np.ndarray  # (n_l, n_r) False where the centring rule has no root (b_R meaningless)
    br_inside: np.ndarray  # (n_l, n_r) False where no b_R keeps the resultant inside L1-L2 at mu_max
    mu_max: float | None  # None when b_R is fixed
    bl2_over_hl: float
    kn: float
    kt: float
    summary: DesignSummary

    @property
    def valid(self) -> np.ndarray:
        """Points that are a working damper: converged, no liftoff, b_R defined."""
        s = self.summary
        return s.converged & ~s.liftoff & ~s.failed & self.br_found[None]


@jax.jit
def _centring(theta_l, theta_r, bl2_over_hl, mu_max):
    def one(tl, tr):
        return _design_br(DamperShape(tl, tr, 0.0, bl2_over_hl), mu_max, -0.45, 0.45)

    return jax.vmap(one)(theta_l, theta_r)


def centred_br(theta_l, theta_r, mu_max=0.7, bl2_over_hl=0.8):
    """The paper's centring rule (jaxdamp.design_br) for arrays of angles: (br, found, inside)."""
    tl, tr = np.broadcast_arrays(np.asarray(theta_l, float), np.asarray(theta_r, float))
    validate_shape(DamperShape(tl, tr, 0.0, bl2_over_hl))
    validate_mu(mu_max, "mu_max")
    res = _centring(jnp.asarray(tl.ravel()), jnp.asarray(tr.ravel()), jnp.asarray(bl2_over_hl, float),
                    jnp.asarray(mu_max, float))
    return tuple(np.asarray(a).reshape(tl.shape) for a in (res.br_over_hr, res.found, res.inside))


def check_sweep_inputs(theta_l, theta_r, mu, br_over_hr="centred", *, mu_max=None,
                       bl2_over_hl=0.8, contacts: Contacts = Contacts(),
                       load: LoadCase = LoadCase()):
    """Validate a sweep's inputs without computing anything (ValueError naming the parameter and
    its range); returns (theta_l, theta_r, mu) as 1-D float arrays. `sweep` calls it first."""
    try:
        tl, tr, mus = (np.atleast_1d(np.asarray(v, float)) for v in (theta_l, theta_r, mu))
    except (TypeError, ValueError):
        raise ValueError("theta_l, theta_r and mu must be sequences of numbers") from None
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
          chunk_size: int = DEFAULT_CHUNK, progress=None) -> SweepResult:
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
