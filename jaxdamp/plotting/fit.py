"""Figures of `jaxdamp fit-loops`: per loop, the measured samples and the fitted exact steady loop
against psi, and the residual against the travel phase. matplotlib is imported here; no backend is
chosen."""

from __future__ import annotations

import numpy as np


def fitted_loop_curve(fit, i: int, shape, load, points: int = 400):
    """(psi in mrad, M in N mm) of loop i's fitted model loop on a fine travel-phase grid (the
    measured centre and the fitted offset included)."""
    import jax.numpy as jnp

    from jaxdamp.amplitude import amplitude_cycle
    from jaxdamp.fit import loop_model_moment
    from jaxdamp.params import Contacts

    lp = fit.loops[i]
    ac = amplitude_cycle(shape, fit.mu, lp.psi_a, Contacts(fit.kn, fit.kt), load, initial=fit.initial)
    u = np.linspace(0.0, 1.0, points)
    fwd = np.concatenate([np.ones(points, bool), np.zeros(points, bool)])
    uu = np.concatenate([u, u])
    m = np.asarray(loop_model_moment(ac, jnp.asarray(fwd), jnp.asarray(uu))) + fit.offsets[i]
    x = np.where(fwd, 1.0 - 2.0 * uu, -1.0 + 2.0 * uu)
    return lp.psi_c + lp.psi_a * x, m


def fitted_contact_curve(fit, i: int, shape, load):
    """(disp in mm, force in N) of contact loop i's fitted model loop: the exact vertices of both
    halves (forward then backward), placed at the measured centre, the fitted offset included."""
    import jax.numpy as jnp

    from jaxdamp.amplitude import amplitude_cycle
    from jaxdamp.fit import contact_path
    from jaxdamp.params import Contacts

    lp = fit.loops[i]
    ac = amplitude_cycle(shape, fit.mu, lp.psi_a, Contacts(fit.kn, fit.kt), load, initial=fit.initial)
    (df, ff), (db, fb), af, ab = contact_path(ac, lp.contact, jnp.asarray(lp.component == "normal"))
    keep = lambda v, a: np.asarray(v)[np.concatenate([[True], np.asarray(a)])]  # noqa: E731
    d = np.concatenate([keep(df, af), keep(db, ab)])
    f = np.concatenate([keep(ff, af), keep(fb, ab)]) * float(load.F_D)
    return d - 0.5 * (d.max() + d.min()) + lp.disp_c, f + fit.offsets[i]


def plot_loop_fit(fit, i: int, shape, load, title: str | None = None):
    """One loop: measured and fitted M(psi) (top), residual against the travel phase (bottom)."""
    import matplotlib.pyplot as plt

    lp = fit.loops[i]
    fig, (ax, ar) = plt.subplots(2, 1, figsize=(6.4, 6.4), height_ratios=(3, 1.3),
                                 constrained_layout=True)
    contact = hasattr(lp, "disp")
    ax.plot(lp.x, lp.y, ".", ms=2.5, color="0.55", label="measured")
    x, y = (fitted_contact_curve if contact else fitted_loop_curve)(fit, i, shape, load)
    ax.plot(x, y, "-", color="C3", lw=1.4, label="fitted exact steady loop")
    unit = "N" if contact else "N mm"
    if contact:
        ax.set_xlabel(f"{lp.component} relative displacement (mm)")
        ax.set_ylabel(f"{lp.component} force (N)")
    else:
        ax.set_xlabel("platform rotation psi (mrad)")
        ax.set_ylabel("moment M (N mm)")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or f"loop {i + 1}: psi_a = {lp.psi_a:.4g} mrad", fontsize=10)
    phase = np.where(lp.forward, lp.u, 1.0 + lp.u)
    res = lp.y - fit.fitted[i]
    ar.plot(phase, res, ".", ms=2.5, color="C0")
    ar.axhline(0.0, color="0.3", lw=0.8)
    ar.set_xlim(0.0, 2.0)
    ar.set_xlabel("displacement phase (0-1 half with disp decreasing; 1-2 increasing)" if contact
                  else "travel phase (0-1 forward half, psi decreasing; 1-2 backward)")
    ar.set_ylabel(f"residual ({unit})")
    ar.set_title(f"rms {fit.rms[i]:.3g} {unit}", fontsize=9)
    return fig


__all__ = ["fitted_loop_curve", "fitted_contact_curve", "plot_loop_fit"]
