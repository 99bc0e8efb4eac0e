"""Synthetic loops from the model, for tests and examples: a moment loop and a per-contact loop
sampled at given times of psi = psi_a cos(2 pi t), exact (add noise and offsets yourself)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from .._validate import check_range
from ..amplitude import amplitude_cycle
from ..conventions import travel_mm
from ..geometry import DamperShape
from ..params import Contacts, LoadCase
from .loops import COMPONENTS
from .model import loop_model_moment

__all__ = ["sample_loop", "sample_contact_loop"]


def sample_loop(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                load: LoadCase = LoadCase(), *, t, initial: str = "gross_slip"):
    """(psi, M) of the model's exact steady loop sampled at times t (periods) of psi = psi_a cos(2 pi
    t): psi in mrad, M in N mm (numpy). A test loop for `fit_loops` (add noise and offsets)."""
    t = _times(t)
    ac = amplitude_cycle(shape, mu, psi_a_mrad, contacts, load, initial=initial)
    phase = np.mod(t, 1.0)
    forward = phase < 0.5  # psi decreasing from the top
    x = np.cos(2.0 * np.pi * t)
    u = np.where(forward, 0.5 * (1.0 - x), 0.5 * (1.0 + x))
    m = loop_model_moment(ac, jnp.asarray(forward), jnp.asarray(u))
    return float(psi_a_mrad) * x, np.asarray(m)


def sample_contact_loop(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                        load: LoadCase = LoadCase(), *, contact, component: str, t,
                        initial: str = "gross_slip"):
    """(disp in mm, force in N) of contact `contact` (0-2) of the model's exact steady loop at
    platform amplitude psi_a_mrad, sampled at times t (periods) of psi = psi_a cos(2 pi t): a test
    loop for `fit_loops` (add noise and offsets; centre: disp at the forward extreme is the model's
    d there, forward half first). Evaluated along the travel, tract by tract (numpy), not through
    the displacement inversion the fit uses."""
    if component not in COMPONENTS:
        raise ValueError(f"component must be tangential or normal; got {component!r}")
    t = _times(t)
    ac = amplitude_cycle(shape, mu, psi_a_mrad, contacts, load, initial=initial)
    F_D = float(load.F_D)
    kt = float(np.broadcast_to(np.asarray(contacts.kt, float), (3,))[contact]) / F_D
    kn = float(np.broadcast_to(np.asarray(contacts.kn, float), (3,))[contact]) / F_D
    travel = 2.0 * float(travel_mm(psi_a_mrad, load.q_star))
    phase = np.mod(t, 1.0)
    forward = phase < 0.5
    x = np.cos(2.0 * np.pi * t)
    u = np.where(forward, 0.5 * (1.0 - x), 0.5 * (1.0 + x))

    def along(half, s0, tv):
        h = {k: np.asarray(getattr(half, k)) for k in ("dv", "N0", "T0", "dN", "dT", "dslip", "active")}
        out_T, out_N, out_S = np.zeros_like(tv), np.zeros_like(tv), np.zeros_like(tv)
        pos, s = 0.0, s0
        for j in np.nonzero(h["active"])[0]:
            L = h["dv"][j]
            sel = (tv >= pos) & ((tv <= pos + L) | (j == np.nonzero(h["active"])[0][-1]))
            dt = tv[sel] - pos
            out_T[sel] = h["T0"][j, contact] + h["dT"][j, contact] * dt
            out_N[sel] = h["N0"][j, contact] + h["dN"][j, contact] * dt
            out_S[sel] = s + h["dslip"][j, contact] * dt
            pos, s = pos + L, s + h["dslip"][j, contact] * L
        return out_T, out_N, out_S, s

    Tf, Nf, Sf, s_end = along(ac.forward, 0.0, u * travel)
    Tb, Nb, Sb, _ = along(ac.backward, s_end, u * travel)
    T, N, S = np.where(forward, Tf, Tb), np.where(forward, Nf, Nb), np.where(forward, Sf, Sb)
    if component == "tangential":
        return T / kt - S, T * F_D
    return N / kn, N * F_D


def _times(t) -> np.ndarray:
    """The sample times t (periods) as floats, checked: finite numbers (one line naming t)."""
    check_range("t", t, -np.inf, np.inf, lo_open=True, hi_open=True, unit="periods")
    return np.asarray(t, float)
