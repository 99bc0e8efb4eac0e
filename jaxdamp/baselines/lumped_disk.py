"""A lumped-parameter tuned bladed disk: the example mode family, and the ring for the full check.

Each of the N blades has two degrees of freedom (mm, N, s, tonne units throughout):

- theta_j (rad): the rigid rotation of blade j's root and platforms about its centre C (the
  paper's Fig. 4: C lies h_C below the damper point D and q*/2 to the side), clockwise positive
  as in `jaxdamp.conventions.interblade_direction`. Per rad of theta_j the blade's left-hand
  platform moves at D by (h_C, q*/2, -1) and its right-hand platform by (h_C, -q*/2, -1)
  ((u mm, v mm, theta rad), theta counter-clockwise), so that at nodal diameter 0 the damper
  sees the paper's in-phase path (0, q* theta, 0);
- x_j (mm): the tangential displacement of the blade's tip (the response point).

Springs: the root and disk hold the platform (k_root, N mm/rad, to ground); the airfoil is a
cantilever on the root, a spring k_blade (N/mm) on the tip's motion relative to the root's rigid
rotation, x_j - L theta_j (L = lever_mm, the tip's distance from C); the disk couples neighbouring
roots, k_disk (N mm/rad) on theta_{j+1} - theta_j. Masses: the tip's modal mass m_tip (tonne) and
the root and platform's inertia about C, j_root (tonne mm^2). Damping: a loss factor eta on the
whole stiffness (K (1 + i eta) at the forcing frequency), so that every mode has loss factor eta.

A travelling wave theta_j = Theta e^{i j phi}, x_j = X e^{i j phi} leaves a 2x2 eigenproblem per
interblade phase angle phi, K(phi) = [[k_root + k_blade L^2 + 2 k_disk (1 - cos phi),
-k_blade L], [-k_blade L, k_blade]], M = diag(j_root, m_tip) (`sector_matrices`); the whole ring's
2N x 2N matrices (`full_matrices`) have the union of its eigenvalues over phi = 2 pi n / N.

The defaults (`LumpedDisk()`) make a small stage's first bending family for the paper's reference
damper (60sym, mu = 0.5, F_D = 1000 N, q* = 100 mm, default contacts: stuck, it resists the
in-phase platform rotation with k_Re,fs = 28 744 N mm/mrad): 506 Hz at nodal diameter 0 rising to
528 Hz and levelling off from about nodal diameter 8; a tip modal mass of 50 g (k_b = 509 N/mm at
nodal diameter 0); root rotation per tip motion r = theta / x 1.04 mrad/mm at nodal diameter 0
(`BladeMode`'s r = 1 mrad/mm) down to 0.54 mrad/mm at the highest, as the disk stiffens the
roots; loss factor 1e-3; the second (root-rocking) family at 3.4-4.6 kHz. The disk coupling is
weak enough that the roots keep turning at every nodal diameter: with the example's 24 blades,
h_C = 20 mm and h_L = 10 mm the damper microslips at a tip force of 2 N up to nodal diameter 10
(5 N at 11 and 12, where neighbouring platforms move nearly together radially and the damper
slips only on their relative rotation). A frequency rise with nodal diameter made by the root's
compliance comes with the root rotation it loses: (f_high / f_0)^2 ~ (1 - r_high L) / (1 - r_0 L).
The stuck damper raises the nodal-diameter-0 frequency by 3.0 % in the one-mode reduction
(sqrt(1 + 1e-3 r^2 k_Re,fs / k_b)) and by 2.3 % in the 2x2 sector problem with the damper's
stiffness on theta (the few per cent of rigs).

The one-mode reduction's error at nodal diameter 0 is set by the same parameters: the damper's
stiffness k_d on theta against the root's K_tt = k_root + k_blade L^2 (delta = k_d / K_tt, 0.33
stuck here), while the stiffening it gives the first mode is epsilon = k_d r^2 / k_b =
delta gamma / (1 - gamma), gamma ~ r L the first mode's share of the platform's static compliance
(0.16 here). A few per cent of stiffening with r L ~ 0.15 (a blade 150 mm long whose root turns
1 mrad per mm of tip) therefore means a damper a third as stiff as the root: the stuck damper
changes the mode shape at the platform, and the free-platform one-mode reduction overestimates
its damping there (docs/blade_example.md). At higher nodal diameters the disk stiffens the roots
(K_tt + 2 k_disk (1 - cos phi)) and delta falls (to 0.17 at the highest).

`modal_family` returns the first family as a `jaxdamp.response.modes.ModalFamily`, modes
mass-normalised per sector (Phi^T M_sector Phi = 1: the one-blade normalisation
`family_from_blade_mode` uses), the tip force F_j = e^{i j phi} projected on the mode (Phi_tip)
as its modal force. `write_example_family` writes the example file (N = 24) with numpy.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np

from .._validate import check_int, check_range
from ..conventions import platform_directions
from ..modal_file import EXAMPLE_PATH, save_modal_family
from ..response.modes import ModalFamily

__all__ = ["LumpedDisk", "sector_matrices", "full_matrices", "sector_modes", "modal_family",
           "example_family", "write_example_family", "EXAMPLE_GEOMETRY"]

# The damper geometry the example file (`modal_file.EXAMPLE_PATH`) is written for (that of
# benchmarks/ibpa_sweep.py).
EXAMPLE_GEOMETRY = {"n_blades": 24, "q_star_mm": 100.0, "h_c_mm": 20.0}


class LumpedDisk(NamedTuple):
    """The physical parameters of the lumped disk (module docstring), mm, N, s, tonne units.

    Illustrative values for a small turbine stage, chosen so that the first family has the shape
    of a bladed disk's first bending family; they are not any particular stage's.
    """

    n_blades: int = 24
    m_tip: float = 5.0e-5  # tip modal mass, tonne (50 g)
    k_blade: float = 600.0  # airfoil cantilever stiffness at the tip, N/mm (551 Hz clamped)
    lever_mm: float = 150.0  # tip's distance from the rotation centre C, mm
    j_root: float = 0.2  # root and platform inertia about C, tonne mm^2 (100 g at 45 mm)
    k_root: float = 7.5e7  # root / disk stiffness to ground, N mm/rad
    k_disk: float = 2.0e7  # disk coupling of neighbouring roots, N mm/rad
    eta: float = 1e-3  # loss factor of the whole stiffness


def _checked(disk: LumpedDisk) -> LumpedDisk:
    if not isinstance(disk, LumpedDisk):
        raise ValueError(f"disk must be a LumpedDisk; got {type(disk).__name__}")
    check_int("n_blades", disk.n_blades, 2)
    for name in ("m_tip", "k_blade", "lever_mm", "j_root", "k_root"):
        check_range(name, getattr(disk, name), 0.0, np.inf, lo_open=True, hi_open=True)
    check_range("k_disk", disk.k_disk, 0.0, np.inf, hi_open=True)
    check_range("eta", disk.eta, 0.0, 1.0)
    return disk


def sector_matrices(disk: LumpedDisk, phi_rad) -> tuple[np.ndarray, np.ndarray]:
    """(M, K) of one sector for the travelling wave of interblade phase angle phi (rad): 2x2 over
    (theta rad, x mm), M in (tonne mm^2, tonne), K in (N mm/rad, N, N/mm); both real symmetric
    (the disk couples only theta, and |e^{i phi} - 1|^2 = 2 (1 - cos phi))."""
    d = _checked(disk)
    ktl = d.k_blade * d.lever_mm
    k_tt = d.k_root + d.k_blade * d.lever_mm ** 2 + 2.0 * d.k_disk * (1.0 - np.cos(float(phi_rad)))
    return (np.diag([float(d.j_root), float(d.m_tip)]),
            np.array([[k_tt, -ktl], [-ktl, float(d.k_blade)]]))


def full_matrices(disk: LumpedDisk) -> tuple[np.ndarray, np.ndarray]:
    """(M, K) of the whole ring, 2N x 2N over (theta_0, x_0, theta_1, x_1, ...) (the units of
    `sector_matrices`); the disk spring k_disk between theta_j and theta_{j+1 mod N}."""
    d = _checked(disk)
    n = int(d.n_blades)
    m_sec, k_sec = sector_matrices(d, 0.0)
    M = np.kron(np.eye(n), m_sec)
    K = np.kron(np.eye(n), k_sec)
    for j in range(n):
        a, b = 2 * j, 2 * ((j + 1) % n)
        K[a, a] += d.k_disk
        K[b, b] += d.k_disk
        K[a, b] -= d.k_disk
        K[b, a] -= d.k_disk
    return M, K


def sector_modes(disk: LumpedDisk, phi_rad) -> tuple[np.ndarray, np.ndarray]:
    """(omega^2 (2,) in (rad/s)^2 ascending, modes (2, 2) as columns over (theta rad, x mm)) of
    the sector eigenproblem, mass-normalised (Phi^T M Phi = 1), each with its tip motion x >= 0."""
    M, K = sector_matrices(disk, phi_rad)
    scale = 1.0 / np.sqrt(np.diag(M))  # M is diagonal: M^{-1/2}
    lam, v = np.linalg.eigh(scale[:, None] * K * scale[None, :])
    modes = scale[:, None] * v
    modes = modes * np.where(modes[1] < 0.0, -1.0, 1.0)[None, :]
    return lam, modes


def modal_family(disk: LumpedDisk, q_star_mm: float, h_c_mm: float, name: str = "",
                 residual: bool = False) -> ModalFamily:
    """The first (blade bending) family of the disk at nodal diameters 0 ... N // 2, per the
    cyclic-symmetry sector eigenproblem (module docstring), as a ModalFamily: modes mass-
    normalised per sector, response point the tip, the modal force of a unit engine-order tip
    force Phi_tip, platforms per the Fig. 4 kinematics with the damper's q* and h_C (mm).

    residual: also the platforms' residual flexibility (`ModalFamily.platform_residual`) from the
    second family at the first one's frequency, theta_2^2 / (omega_2^2 - omega_1^2) on the root
    rotation (rad per N mm), mapped to the platforms at D as d d^T with d = (left; right) per rad
    of theta: exact for this disk, whose only other mode per nodal diameter is the second (and
    whose platforms move only with theta)."""
    d = _checked(disk)
    check_range("q_star_mm", q_star_mm, 0.0, np.inf, lo_open=True, hi_open=True, unit="mm")
    check_range("h_c_mm", h_c_mm, -np.inf, np.inf, hi_open=True, lo_open=True, unit="mm")
    n = int(d.n_blades)
    nds = np.arange(n // 2 + 1)
    left, right = platform_directions(q_star_mm, h_c_mm)
    freq, theta, tip, flex = [], [], [], []
    for nd in nds:
        lam, modes = sector_modes(d, 2.0 * np.pi * nd / n)
        freq.append(np.sqrt(lam[0]) / (2.0 * np.pi))
        theta.append(modes[0, 0])
        tip.append(modes[1, 0])
        flex.append(modes[0, 1] ** 2 / (lam[1] - lam[0]))
    theta, tip = np.array(theta), np.array(tip)
    both = np.concatenate([left, right])
    platform_residual = (np.array(flex)[:, None, None] * np.outer(both, both)[None]).astype(complex)
    return ModalFamily(n, nds, np.array(freq), np.full(nds.size, float(d.eta)),
                       tip.astype(complex), tip.astype(complex),
                       (theta[:, None] * left[None, :]).astype(complex),
                       (theta[:, None] * right[None, :]).astype(complex),
                       name or f"lumped disk, {n} blades, first family",
                       platform_residual if residual else None)


def example_family(residual: bool = True) -> ModalFamily:
    """The example disk's first family: `LumpedDisk()` with N = 24 at q* = 100 mm, h_C = 20 mm,
    with the platforms' residual flexibility from the second family (`modal_family(residual=
    True)`; the shipped file, `--modes example`): without it the one-mode reduction overestimates
    the damping at nodal diameter 0 by up to 25 % against the whole ring
    (benchmarks/ring_check.py). residual=False: the free-platform reduction, for comparison."""
    g = EXAMPLE_GEOMETRY
    name = "example disk (jaxdamp.baselines.lumped_disk), 24 blades, first family"
    return modal_family(LumpedDisk(n_blades=g["n_blades"]), g["q_star_mm"], g["h_c_mm"],
                        name=name + (", platform residual flexibility" if residual else ""),
                        residual=residual)


def write_example_family(path=EXAMPLE_PATH) -> Path:
    """Write `example_family()` as a modal file (`modal_file.save_modal_family`). Returns the
    path."""
    return save_modal_family(example_family(), path)
