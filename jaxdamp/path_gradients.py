"""Derivatives of one steady path cycle (`elliptic_cycle`) with respect to the design and the path.

k_Re, k_Im (N mm/mrad), the energy dissipated at each pad and the modal work per cycle (N mm), by
forward (`jax.jacfwd`) or reverse (`jax.jacrev`) mode through the elliptic kernel's replay of the
value pass's choices (`loops.values_by_replay`: the derivatives of the sequence of tracts the
cycle took; at a switch of that sequence, its one-sided derivatives). With respect to every leaf of
the Design (angles per degree, mu, kn and kt per pad per N/mm, the load) and of the Motion
(`direction` and `quadrature` per mm or mrad of X_hat, `h_l` per mm): a modal file's platform
motions are differentiable too. A straight motion runs as an ellipse of zero width (the path
engine, pads that may open).

One design's derivative program is compiled once per (initial, mode) and kept, with XLA's options
for a short compile (`runtime.LATENCY_OPTIONS`): measured on the 2-core VM (2026-11-30, a slow
hour: benchmarks/path_derivatives.py), 60sym at phi 90 deg, w.r.t. 8 variables, lowering +
compile 22.4 -> 12.6 s forward and 26.7 -> 14.5 s reverse, each call then 32 -> 86 ms and 24 ->
31 ms. Inside your own jit, vmap or grad use `path_outputs` (the pure function behind it).
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_int, check_scalar
from .design import Design, as_design, check_design
from .ellipse import MAX_PERIODS, MAX_TRACTS, elliptic_kernel
from .geometry import DamperShape
from .gradients import check_mode, collapse_shared_stiffness
from .motion import Motion, as_ellipse, validate_motion
from .params import Contacts, LoadCase
from .runtime import LATENCY_OPTIONS, batch_jit
from .status import number_repr, status_repr

INITIAL = ("assembly", "gross_slip")
# Units of PathOutputs' fields.
UNITS = ("N mm/mrad", "N mm/mrad", "N mm", "N mm")


class PathOutputs(NamedTuple):
    """The differentiated numbers of a path cycle (as `EllipticCycle`'s fields)."""

    k_re: jnp.ndarray  # N mm/mrad per mrad of the path's amplitude
    k_im: jnp.ndarray
    energy: jnp.ndarray  # (P,) N mm per cycle dissipated at each pad (`geometry.pad_names` order)
    work: jnp.ndarray  # N mm per cycle of the modal forces

    def __repr__(self) -> str:
        """The four numbers with units; a PathOutputs of derivatives (Designs or Motions) by its
        fields' types."""
        if all(isinstance(v, (jnp.ndarray, np.ndarray, np.generic, float)) for v in self):
            return "PathOutputs(" + ", ".join(f"{f}={number_repr(v, u)}" for f, v, u in
                                              zip(self._fields, self, UNITS)) + ")"
        return "PathOutputs(" + ", ".join(f"{f}=<{type(v).__name__}>" for f, v in
                                          zip(self._fields, self)) + ")"


class PathGradient(NamedTuple):
    """values: PathOutputs. d_design, d_motion: PathOutputs whose fields are a Design and a Motion
    of derivatives, e.g. d_design.k_im.mu = d k_Im / d mu (N mm/mrad), d_motion.k_im.h_l (N mm/mrad
    per mm); an energy's derivative has the pads' axis first. status: the cycle's RESULTS code
    (derivatives of a cycle whose status is not valid are not a damper's: check it)."""

    values: PathOutputs
    d_design: PathOutputs
    d_motion: PathOutputs
    status: jnp.ndarray

    def __repr__(self) -> str:
        """One line: status by name, k_Re and k_Im with units, and d k_Im by mu and by h_L."""
        try:
            k = ", ".join(f"{f}={number_repr(v, u)}" for f, v, u in
                          zip(("k_re", "k_im"), self.values[:2], UNITS))
            d = (f"d k_im/d mu={number_repr(self.d_design.k_im.mu, 'N mm/mrad')}, "
                 f"d k_im/d h_l={number_repr(self.d_motion.k_im.h_l, 'N mm/mrad per mm')}")
        except Exception:  # noqa: BLE001 - a repr must not raise
            k, d = "<unavailable>", ""
        return f"PathGradient(status={status_repr(self.status)}, {k}; {d})"


def path_outputs(design: Design, amplitude_mrad, motion: Motion, *, initial: str = "assembly",
                 max_tracts: int = MAX_TRACTS, max_periods: int = MAX_PERIODS):
    """(PathOutputs, status) of one prepared Design (kn, kt per pad) on an elliptic Motion (a
    quadrature part, zero for a straight path): pure, unchecked and traceable, the function that
    `path_gradient` differentiates (use it inside your own jit / vmap / grad)."""
    cycle = elliptic_kernel(*design, amplitude_mrad, motion, initial=initial,
                            max_tracts=max_tracts, max_periods=max_periods)
    return PathOutputs(cycle.k_re, cycle.k_im, cycle.energy, cycle.work), cycle.status


@functools.cache
def _program(initial: str, mode: str, max_tracts: int, max_periods: int):
    def with_values(design, amplitude, motion):
        out, status = path_outputs(design, amplitude, motion, initial=initial,
                                   max_tracts=max_tracts, max_periods=max_periods)
        return out, (out, status)

    jac = jax.jacfwd if mode == "fwd" else jax.jacrev
    # One design's derivative runs once or a few times: compiled for a short compile.
    return batch_jit(jac(with_values, argnums=(0, 2), has_aux=True), cpu_options=LATENCY_OPTIONS)


def path_gradient(shape: DamperShape | Design, mu=None, amplitude_mrad=None,
                  motion: Motion | None = None, contacts: Contacts = Contacts(),
                  load: LoadCase = LoadCase(), *, initial: str = "assembly", mode: str = "fwd",
                  max_tracts: int = MAX_TRACTS, max_periods: int = MAX_PERIODS) -> PathGradient:
    """k_Re, k_Im, the energy per pad and the work of the steady cycle on `motion`'s path at
    amplitude a (mrad), and their derivatives with respect to the design (shape, mu, kn and kt,
    the load) and the motion (X_hat's real and imaginary parts, h_L), by forward ("fwd") or
    reverse ("rev") mode. shape: a DamperShape (the curved-flat damper or a wedge) with mu,
    contacts and load, or a Design (mu None). initial: "assembly" or "gross_slip" (as
    `elliptic_cycle`'s). kn, kt given as one value come back as one derivative (the sum over the
    pads), per pad where given per pad. Checked (ValueError naming the parameter and its range,
    Float64Required in float32) before anything is compiled."""
    given = as_design(shape, mu, contacts, load)
    design = check_design(given, wedge_ok=True)
    if amplitude_mrad is None:
        raise ValueError("amplitude_mrad must be given: the path's amplitude in (0, 10000] mrad")
    amplitude_mrad = check_scalar("amplitude_mrad", amplitude_mrad, 0.0, 1e4, lo_open=True,
                                  unit="mrad")
    if motion is None:
        raise ValueError("motion must be given: a Motion (interblade_motion, general_motion, ...)")
    motion = as_ellipse(validate_motion(motion, design.load))
    if initial not in INITIAL:
        raise ValueError(f"initial must be one of {', '.join(INITIAL)}; got {initial!r}")
    check_mode(mode)
    check_int("max_tracts", max_tracts, 1)
    check_int("max_periods", max_periods, 1)
    motion = Motion(*(jnp.asarray(v, float) for v in motion))
    # Per output, (its Design of derivatives, its Motion of derivatives).
    jac, (values, status) = _program(initial, mode, max_tracts, max_periods)(
        design, jnp.asarray(float(amplitude_mrad)), motion)
    shared = (np.ndim(given.contacts.kn) == 0, np.ndim(given.contacts.kt) == 0)
    d_design = PathOutputs(*(collapse_shared_stiffness(d, *shared) for d, _ in jac))
    return PathGradient(values, d_design, PathOutputs(*(m for _, m in jac)), status)


__all__ = ["PathOutputs", "PathGradient", "path_outputs", "path_gradient"]
