"""Uncertainty propagation: the distribution of a design's resonant peak over what the designer
does not know (mu, contact stiffness per contact pair, F_D), by Monte Carlo over vmap.

Each sample is one *scenario* (mu, kn and kt of R1, L1, L2 in N/mm, F_D in N). Its damper curve is
the exact one (`response.damper_stiffness_kernel`, "exact": the steady cycle at each amplitude from
the named history), recomputed per sample: the paper's scaling law (`scaled_stiffness`) is exact
only for F_D and for kn, kt scaled together, and a per-pair kn, kt or a new mu changes the curve's
shape, so no sample is approximated. The result is the dynamic magnification A*/F (mm/N) of the
one-mode blade at each force of a force range.

    scen = sample_scenarios(key, 10_000, Uncertainty(), Contacts(), LoadCase())
    dist = peak_distribution(shape, scen, BladeMode(), forces_n, limit_mm_per_n=0.2)
    dist.quantiles, dist.exceedance   # per force

`magnification_kernel` is the pure, traceable core (vmap it, differentiate it: IFT through the
peak); `peak_distribution` batches it through `map_batched`.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .batch import map_batched
from ._validate import check_int, check_range, check_values, require_x64
from .params import (RANGES, Contacts, LoadCase, check_contacts_and_load, validate_contacts,
                     validate_load)
from .response import BladeMode, Scene, damper_stiffness_kernel, peak_response, prepare_scene
from .status import RESULTS, number_repr, status_repr

HISTORIES = ("gross_slip", "assembly")


class Uncertainty(NamedTuple):
    """What is not known, as distributions (all independent).

    mu: uniform on [mu_low, mu_high]. F_D: uniform on F_D0 (1 -/+ fd_spread). kn, kt: log-uniform
    on [k0 / k_factor, k0 k_factor], drawn independently for each contact pair R1, L1, L2
    (k_factor = 2: a factor of two each way, a rig calibration's spread)."""

    mu_low: float = 0.3
    mu_high: float = 0.7
    fd_spread: float = 0.2
    kn_factor: float = 2.0
    kt_factor: float = 2.0


class Scenarios(NamedTuple):
    """n scenarios: mu (n,), kn (n, 3) and kt (n, 3) in N/mm ordered (R1, L1, L2), fd_n (n,)."""

    mu: jnp.ndarray
    kn: jnp.ndarray
    kt: jnp.ndarray
    fd_n: jnp.ndarray


class PeakDistribution(NamedTuple):
    """A*/F over the scenarios, per force.

    magnification: (n, n_force) A*/F in mm/N (NaN where the sample's status is not ok); status:
    (n,) damper status per sample; levels: the quantile levels; quantiles: (n_levels, n_force) over
    the ok samples; worst: (n_force,) the largest sampled A*/F; exceedance: (n_force,) fraction of
    ok samples with A*/F above limit_mm_per_n (NaN when no limit); n_ok: ok samples."""

    force_n: np.ndarray
    magnification: np.ndarray
    status: np.ndarray
    levels: np.ndarray
    quantiles: np.ndarray
    worst: np.ndarray
    exceedance: np.ndarray
    n_ok: int

    def __repr__(self) -> str:
        """Two lines at most: the samples' statuses by name, the forces, the median and 95 %
        quantile and the worst A*/F (mm/N), and the exceedance where a limit was given."""
        def level(q):
            try:
                i = int(np.argmin(np.abs(np.asarray(self.levels, float) - q)))
                return number_repr(np.asarray(self.quantiles)[i], "mm/N")
            except Exception:  # noqa: BLE001 - a repr must not raise
                return "<unavailable>"

        try:
            limit = bool(np.any(np.isfinite(np.asarray(self.exceedance, float))))
        except Exception:  # noqa: BLE001
            limit = False
        return (f"PeakDistribution(status={status_repr(self.status)}, n_ok={number_repr(self.n_ok)}, "
                f"force_n={number_repr(self.force_n, 'N')}, median={level(0.5)}, q95={level(0.95)}, "
                f"worst={number_repr(self.worst, 'mm/N')}"
                + (f", exceedance={number_repr(self.exceedance)}" if limit else "") + ")")


def validate_uncertainty(u: Uncertainty) -> Uncertainty:
    """ValueError naming the field and its valid range."""
    if not isinstance(u, Uncertainty):  # its fields were read as attributes: an AttributeError
        raise ValueError(f"uncertainty must be a jaxdamp.Uncertainty; got {type(u).__name__}")
    mu_hi = RANGES["mu"][1]
    if not 0.0 < u.mu_low <= u.mu_high <= mu_hi:
        raise ValueError(f"mu range must satisfy 0 < mu_low <= mu_high <= {mu_hi:g}; got "
                         f"{u.mu_low}:{u.mu_high}")
    if not 0.0 <= u.fd_spread < 1.0:
        raise ValueError(f"fd_spread must be in [0, 1); got {u.fd_spread}")
    for name in ("kn_factor", "kt_factor"):
        f = getattr(u, name)
        if not 1.0 <= f <= 100.0:
            raise ValueError(f"{name} must be in [1, 100]; got {f}")
    return u


def sample_scenarios(key, n: int, uncertainty: Uncertainty = Uncertainty(),
                     contacts: Contacts = Contacts(), load: LoadCase = LoadCase()) -> Scenarios:
    """n independent scenarios drawn from `uncertainty` around the nominal contacts and load.

    Every input is checked before any sampling (ValueError naming the parameter and its range:
    the uncertainty, n, the nominal kn, kt and F_D, q*, r sin beta; Float64Required in float32)."""
    require_x64()
    u = validate_uncertainty(uncertainty)
    n = check_int("n", n, 1)  # 2.5, "3" or True are no count (int() took them)
    dtype = getattr(key, "dtype", None)  # a typed key, or the raw uint32 pair of PRNGKey
    if dtype is None or not (jax.dtypes.issubdtype(dtype, jax.dtypes.prng_key)
                             or (dtype == np.uint32 and np.shape(key) == (2,))):
        raise ValueError(f"key must be one JAX random key (jax.random.key(seed) or "
                         f"jax.random.PRNGKey(seed)); got {type(key).__name__}")
    check_contacts_and_load(contacts, load)
    validate_contacts(contacts)
    validate_load(load)
    kn0, kt0 = contacts.per_contact()
    k_mu, k_fd, k_kn, k_kt = jax.random.split(key, 4)
    mu = jax.random.uniform(k_mu, (n,), minval=u.mu_low, maxval=u.mu_high)
    fd = load.F_D * jax.random.uniform(k_fd, (n,), minval=1.0 - u.fd_spread,
                                       maxval=1.0 + u.fd_spread)

    def log_uniform(k, factor):
        return jnp.exp(jax.random.uniform(k, (n, 3), minval=-1.0, maxval=1.0) * jnp.log(factor))

    return Scenarios(mu, kn0[None, :] * log_uniform(k_kn, u.kn_factor),
                     kt0[None, :] * log_uniform(k_kt, u.kt_factor),
                     fd)


class Magnification(NamedTuple):
    """A*/F of one scenario per force, and its damper's status (a pytree; unpacks as a pair)."""

    mm_per_n: jnp.ndarray  # (n_force,) peak amplitude over force, mm/N
    status: jnp.ndarray  # the damper's RESULTS code

    def __repr__(self) -> str:
        return (f"Magnification(status={status_repr(self.status)}, "
                f"mm_per_n={number_repr(self.mm_per_n, 'mm/N')})")


def magnification_kernel(shape, scenario: Scenarios, load: LoadCase, mode: BladeMode, force_n,
                         initial: str = "gross_slip") -> Magnification:
    """`Magnification` (A*/F per force (n_force,) in mm/N, damper status) of one scenario (unbatched fields), on
    the exact curve from `initial`. Pure JAX: vmap over scenarios, differentiate in the shape."""
    load = LoadCase(scenario.fd_n, load.q_star, load.r_sin_beta)
    d = damper_stiffness_kernel(shape, scenario.mu, Contacts(scenario.kn, scenario.kt), load,
                                "exact", initial=initial)
    forces = jnp.asarray(force_n, float).reshape(-1)
    return Magnification(peak_response(d, mode, forces).peak_amplitude_mm / forces, d.status)


def _gross_slip(scenario, shape, load, mode, forces):
    return magnification_kernel(shape, scenario, load, mode, forces, "gross_slip")


def _assembly(scenario, shape, load, mode, forces):
    return magnification_kernel(shape, scenario, load, mode, forces, "assembly")


_BY_HISTORY = {"gross_slip": _gross_slip, "assembly": _assembly}


def peak_distribution(shape, scenarios: Scenarios, mode: BladeMode | None = None, force_n=5.0,
                      load: LoadCase | None = None, *, history: str = "gross_slip",
                      levels=(0.05, 0.5, 0.95), limit_mm_per_n=None,
                      progress=None) -> PeakDistribution:
    """The distribution of A*/F of one design over the scenarios (see module doc). history:
    "gross_slip", "assembly" or "band" (the larger A*/F of the two histories per sample, the cheap
    upper edge of the history band). shape may be a Scene (`prepare_scene`, checked already: its
    load and mode are used, its mu and contacts are not: every sample brings its own); mode and
    load default to BladeMode() and LoadCase()."""
    if history not in HISTORIES + ("band",):
        raise ValueError(f"history must be one of gross_slip, assembly, band; got {history!r}")
    if not isinstance(scenarios, Scenarios):
        raise ValueError(f"scenarios must be a jaxdamp.Scenarios (from sample_scenarios); got "
                         f"{type(scenarios).__name__}")
    forces = np.atleast_1d(check_values("force_n", force_n))
    # Checked here, before the scenarios run (they were read after).
    check_range("levels", levels, 0.0, 1.0)
    if np.ndim(levels) > 1 or np.size(levels) == 0:
        raise ValueError(f"levels must be one or more quantiles in [0, 1]; got {levels!r}")
    if limit_mm_per_n is not None:
        check_range("limit_mm_per_n", limit_mm_per_n, 0.0, np.inf, lo_open=True, hi_open=True,
                    unit="mm/N")
    if not isinstance(shape, Scene):
        # the nominal mu only validates the scene; every sample brings its own
        shape = prepare_scene(shape, 0.5, Contacts(), load, mode)
    else:
        shape = prepare_scene(shape, None, None, load, mode)  # a Scene alone: taken as it is
    shape, _, _, load, mode = shape
    runs = [_BY_HISTORY[h] for h in (HISTORIES if history == "band" else (history,))]
    mags, stats = zip(*(map_batched(fn, scenarios, shape, load, mode, jnp.asarray(forces),
                                    progress=progress) for fn in runs))
    mag = np.max(np.stack(mags), axis=0)
    status = np.max(np.stack(stats), axis=0)
    ok = status == RESULTS.ok
    mag = np.where(ok[:, None], mag, np.nan)
    lev = np.asarray(levels, float)
    n_ok = int(ok.sum())
    if n_ok:
        q = np.quantile(mag[ok], lev, axis=0)
        worst = np.max(mag[ok], axis=0)
        exc = (np.full(forces.shape, np.nan) if limit_mm_per_n is None
               else np.mean(mag[ok] > float(limit_mm_per_n), axis=0))
    else:
        q = np.full((lev.size, forces.size), np.nan)
        worst = exc = np.full(forces.shape, np.nan)
    return PeakDistribution(forces, mag, status, lev, q, worst, exc, n_ok)


__all__ = ["Uncertainty", "Scenarios", "PeakDistribution", "Magnification", "HISTORIES", "validate_uncertainty",
           "sample_scenarios", "magnification_kernel", "peak_distribution"]
