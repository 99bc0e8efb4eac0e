"""The blade mode (one blade-dominated mode at one interblade phase angle, reduced to the tip
displacement) and the scene every compiled response entry point takes: the design and the mode,
checked once and as float arrays."""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..geometry import DamperShape
from ..params import Contacts, LoadCase, check_param, prepare_inputs

__all__ = ["BladeMode", "Scene", "validate_mode", "prepare_scene"]


class BladeMode(NamedTuple):
    """One blade mode with the platforms free (a pytree: every field may be traced).

    ILLUSTRATIVE defaults, chosen to be realistic rather than flattering (they are not the paper's:
    the paper gives no blade). With the paper's reference damper (60sym, mu = 0.5, F_D = 1000 N,
    q* = 100 mm, the reference contact pair), k_Re,fs = 28 744 N mm/mrad and k_Im,BC = 4 927
    N mm/mrad at psi_BC = 2.18 mrad. With the defaults:

    - f0 = 500 Hz and k_b = 500 N/mm: a tip-normalised modal mass k_b / omega0^2 = 51 g, the order
      of a small turbine blade's first bending mode;
    - r = 1 mrad/mm: 0.1 mm of relative radial platform motion per mm of tip motion at q* = 100 mm
      (platforms near the root move a tenth of the tip);
    - eta = 1e-3: the upper end of a blade's material + root-joint loss factor (1e-4 ... 1e-3);
      a larger eta makes the damper look less effective, which is the non-flattering side.

    Then the stuck damper raises the frequency by sqrt(1 + 1e-3 r^2 k_Re,fs / k_b) - 1 = 2.8 %
    (a few per cent, as measured on rigs with stuck underplatform dampers), and at the Base-Cycle
    the damper's modal loss term 1e-3 r^2 k_Im,BC = 4.9 N/mm is ten times eta k_b = 0.5 N/mm.
    """

    f0_hz: jnp.ndarray | float = 500.0
    k_b: jnp.ndarray | float = 500.0  # modal stiffness, N/mm
    eta: jnp.ndarray | float = 1e-3  # structural loss factor
    r: jnp.ndarray | float = 1.0  # platform rotation per tip displacement, mrad/mm


def validate_mode(mode: BladeMode) -> BladeMode:
    """ValueError naming the parameter and its range (concrete values only; `params.RANGES`);
    TypeError for anything that is not a BladeMode."""
    if not isinstance(mode, BladeMode):
        raise TypeError(f"mode must be a jaxdamp.BladeMode (f0_hz, k_b, eta, r); got "
                        f"{type(mode).__name__}")
    for name in BladeMode._fields:
        check_param(name, getattr(mode, name))
        if not isinstance(getattr(mode, name), jax.core.Tracer) and np.ndim(getattr(mode, name)):
            raise ValueError(f"mode.{name} must be one number; got shape "
                             f"{np.shape(getattr(mode, name))}")
    return mode


class Scene(NamedTuple):
    """One design and blade mode, checked once and converted to float64 arrays (kn, kt per
    contact): what `prepare_scene` returns. `peak_band`, `designer_diagram`, `response_curves`,
    `design_peaks`, `uncertainty.peak_distribution` and `fit.fit_loops` take it in place of their
    shape argument and check it no more; `peak_response` takes its mode. A pytree (unpack it into
    the compiled programs: `program(*scene, forces)`). Build it with `prepare_scene`: a Scene made
    by hand is taken as checked."""

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase
    mode: BladeMode


def prepare_scene(shape, mu=None, contacts=None, load=None, mode: BladeMode | None = None, *,
                  wedge_ok: bool = False) -> Scene:
    """The Scene of a design (`params.prepare_inputs`) and blade mode (`validate_mode`): every
    input checked once here (ValueError naming the parameter and its range), as float arrays; what
    every compiled response, HBM and time-integration entry point takes. A Scene given as shape
    (with nothing else) is returned as it is. mode: default BladeMode(). wedge_ok: the caller
    computes a wedge (`path_response_curves`); the others refuse one."""
    if isinstance(shape, Scene):
        if mu is not None or contacts is not None or load is not None or mode is not None:
            raise ValueError("give a Scene alone, or shape, mu, contacts, load and mode; not both")
        return shape
    if mu is None:
        raise ValueError("mu is required (the friction coefficient, in (0, 5]) unless shape is a "
                         "Scene")
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    mode = BladeMode() if mode is None else mode
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load, wedge_ok=wedge_ok)
    validate_mode(mode)
    return Scene(shape, mu, contacts, load, BladeMode(*(jnp.asarray(v, float) for v in mode)))
