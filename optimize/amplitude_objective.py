"""Objectives at a prescribed amplitude, from jaxdamp's exact steady cycles (issue 13), besides
k_Im,BC: the exact k_Im at a given psi_a from a named history, worst case over the mu set, and the
band's lower bound (the robust choice: the least damping any admissible history gives).

`k_im_at_amplitude` is a pure JAX function of the design (jit / grad / vmap); it is the metric an
optimiser step differentiates. `robust_k_im` runs the band (sampling plus constrained refinement)
and is for reporting and checking a design, not for differentiation.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from jaxdamp import RESULTS, Contacts, LoadCase, amplitude_band, amplitude_kernel, check_design
from jaxdamp.blocks import validate_mu


def k_im_at_amplitude(shape, mus, psi_a_mrad, contacts=Contacts(), load=LoadCase(), *,
                      initial="gross_slip"):
    """(k_Im per mu (n_mu,), worst = min over the mu set, valid per mu) at psi_a (mrad), in
    N mm/mrad, from the exact steady cycle started at `initial` ("gross_slip" or "assembly").
    An invalid cycle (liftoff, not periodic) counts as k_Im = 0 in the worst case. Concrete
    inputs are checked first (ValueError naming the parameter and its range); traced ones are the
    caller's (an optimiser checks its box once)."""
    if not any(isinstance(x, jax.core.Tracer)
               for x in jax.tree_util.tree_leaves((shape, mus, contacts, load, psi_a_mrad))):
        validate_mu(mus, "mus")  # numbers in range: None, text or NaN refused in one line
        mu_list = np.asarray(mus, float)
        if mu_list.ndim > 1 or mu_list.size == 0:
            raise ValueError(f"mus must be one or more friction coefficients in (0, 5]; got shape "
                             f"{mu_list.shape}")
        for m in np.atleast_1d(mu_list):
            check_design(shape, float(m), contacts, load)
        try:
            psi = float(psi_a_mrad) if not isinstance(psi_a_mrad, (str, bool)) else np.nan
        except (TypeError, ValueError):
            psi = np.nan
        if np.ndim(psi_a_mrad) != 0 or not 0.0 < psi <= 1e4:
            raise ValueError(f"psi_a_mrad must be one amplitude in (0, 10000] mrad; got {psi_a_mrad!r}")
        if initial not in ("gross_slip", "assembly"):
            raise ValueError(f"initial must be gross_slip or assembly; got {initial!r}")
    mus = jnp.atleast_1d(jnp.asarray(mus, float))
    contacts = Contacts(jnp.asarray(contacts.kn, float), jnp.asarray(contacts.kt, float))
    load = LoadCase(*(jnp.asarray(v, float) for v in load))
    psi = jnp.asarray(psi_a_mrad, float)
    k_im, valid = [], []
    for j in range(mus.shape[0]):
        ac = amplitude_kernel(shape, mus[j], contacts, load, psi, initial=initial)
        k_im.append(ac.k_im)
        valid.append(RESULTS.valid(ac.status))
    k_im, valid = jnp.stack(k_im), jnp.stack(valid)
    return k_im, jnp.min(jnp.where(valid, k_im, 0.0)), valid


def robust_k_im(shape, mus, psi_a_mrad, contacts=Contacts(), load=LoadCase(), **band_kwargs):
    """The band's lower bound of k_Im (N mm/mrad) at psi_a, worst over the mu set, with the per-mu
    bands (jaxdamp.band.Band). Not differentiable: for reporting and checking designs."""
    bands = [amplitude_band(shape, float(mu), psi_a_mrad, contacts, load, **band_kwargs)
             for mu in jnp.atleast_1d(jnp.asarray(mus, float))]
    lows = [b.bounds[2] if b.status == RESULTS.ok else 0.0 for b in bands]
    return min(lows), bands


__all__ = ["k_im_at_amplitude", "robust_k_im"]
