"""The blade mode (one blade-dominated mode at one interblade phase angle, reduced to the tip
displacement) and the scene every compiled response entry point takes: the design and the mode,
checked once and as float arrays."""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp

from .._validate import check_positive, check_range
from ..params import Contacts, LoadCase, prepare_inputs

__all__ = ["BladeMode", "validate_mode", "prepare_scene"]


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
    """ValueError naming the parameter and its range (concrete values only)."""
    check_positive("f0_hz", mode.f0_hz, unit="Hz")
    check_positive("k_b", mode.k_b, unit="N/mm")
    check_range("eta", mode.eta, 0.0, 1.0)
    check_range("r", mode.r, 0.0, 1e6, lo_open=True, unit="mrad/mm")
    return mode



def prepare_scene(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode()):
    """Validated design (`params.prepare_inputs`) and blade mode (`validate_mode`) as float arrays:
    what every compiled response, HBM and time-integration entry point takes."""
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    validate_mode(mode)
    return shape, mu, contacts, load, BladeMode(*(jnp.asarray(v, float) for v in mode))
