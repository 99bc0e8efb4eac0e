"""A bladed disk's mode family from modal data, reduced per engine order to the one-mode blade and
the damper's platform path (the Platform Centred Reduction at every interblade phase angle).

A tuned disk of N blades vibrates in one mode family (e.g. the first bending) with one mode per
nodal diameter n = 0 ... N/2. Engine order e excites nodal diameter n = e mod N folded into
0 ... N/2 (n and N - n are the same standing shape, travelling the other way), as a travelling
wave in which blade j moves as Re(Phi e^{i j phi} e^{i omega t}) with the interblade phase angle
phi = 2 pi e / N. A damper sits between blade j's right-hand platform and blade j+1's left-hand
platform: the right platform of the damper is blade j+1's left-hand platform, so the damper sees

    X_hat = e^{i phi} Phi_left - Phi_right       (u, v at D in mm, theta in mrad per unit q)

per unit modal coordinate q. Reduced to the tip (response point) displacement A = Phi_tip q, mm:
the modal stiffness is k_b = omega_n^2 / |Phi_tip|^2 (N/mm, mass-normalised modes in mm, N, s,
tonne), the tip force per unit excitation is |f| / |Phi_tip|, and the path per mm of A is
X_hat / Phi_tip = r X_unit: r (mrad/mm) and X_unit (per mrad of psi = r A, `jaxdamp.Motion`'s
convention) are scaled so that the paper's in-phase path is X_unit = (0, q*/1e3, 0) exactly (any
other scale gives the same response: r^2 k(r A) does not depend on it). The path's phase is chosen
so that dv is real and positive (dv peaks at tau = 0; a phase of the mode is a shift in time).

The forced response per engine order is then `jaxdamp.response`'s, with the damper's k(psi) on
that path (`stiffness.path_damper`): |D(omega, A)| A = F with D as in the package docstring.

Residual flexibility (optional): where the damper is stiff against the platform's own support, it
changes the mode shape there, and a reduction on the free-platform mode alone overestimates the
damping it adds (docs/blade_example.md). The family may carry `platform_residual`, per nodal
diameter the 6x6 flexibility of the two platforms at D (left u, v, theta, then right) from every
mode the family leaves out (the static residual, K^-1 minus the family's own Phi Phi^H /
omega^2, or better that of the left-out modes at the family's frequency). The damper's
first-harmonic load on a blade is e^{-i phi} F on its left platform and -F on its right (F on
blade j+1's left platform, its reaction on blade j's right), so the relative motion it adds is
C_rel F with C_rel = [e^{i phi} I, -I] C [e^{-i phi} I; -I]. Its component along the path, per
generalized force of the damper (M = k psi, N mm), is c = 1e3 X^H C_rel X / |X|^4 (mrad per N mm;
X the path per rad of psi in (mm, mm, rad)): exact where the left-out modes move the platforms
along the path (the lumped disk's, whose platforms only turn), a projection otherwise. The damper
then sits in series with c: at the free-platform path amplitude psi = r A the damper's own
amplitude is psi_d = psi / |1 + c k(psi_d)| and the mode sees k(psi_d) / (1 + c k(psi_d))
(`stiffness.through_residual`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._validate import check_int, check_param, check_range, check_values
from ..conventions import MRAD_PER_RAD, platform_directions
from ..motion import Motion, general_motion
from .scene import BladeMode

__all__ = ["ModalFamily", "NodalScene", "validate_family", "excited_nodal_diameter", "nodal_scene",
           "nodal_scenes", "family_from_blade_mode", "FAMILY_FIELDS", "OPTIONAL_FIELDS"]

# The modal file's fields: name -> (shape after the nodal-diameter axis, complex allowed, unit).
FAMILY_FIELDS = {
    "nodal_diameter": ((), False, ""),
    "frequency_hz": ((), False, "Hz"),
    "loss_factor": ((), False, ""),
    "modal_force": ((), True, "N per N of excitation"),
    "response_displacement": ((), True, "mm per unit modal coordinate"),
    "left_platform": ((3,), True, "(mm, mm, rad) per unit modal coordinate"),
    "right_platform": ((3,), True, "(mm, mm, rad) per unit modal coordinate"),
}
# Optional fields: name -> (shape after the nodal-diameter axis, unit); zeros where absent.
OPTIONAL_FIELDS = {
    "platform_residual": ((6, 6), "(mm, mm, rad) per (N, N, N mm)"),
}


class ModalFamily(NamedTuple):
    """One mode family of a tuned bladed disk, per nodal diameter (host arrays, leading axis n).

    n_blades: N, the number of blades (>= 2).
    nodal_diameter: (n,) distinct integers in [0, N // 2].
    frequency_hz: (n,) natural frequency with the platforms free (no damper), Hz.
    loss_factor: (n,) modal loss factor eta (structural and root damping), in [0, 1].
    modal_force: (n,) complex modal force of a unit engine-order excitation (the excitation's
        pattern projected on the mode: Phi^H F for a unit force amplitude), per N of excitation.
    response_displacement: (n,) complex displacement of the response point (e.g. the tip), mm per
        unit modal coordinate; modes mass-normalised in mm, N, s, tonne (Phi^T M Phi = 1).
    left_platform, right_platform: (n, 3) complex rigid motion (u mm right, v mm up, theta rad
        counter-clockwise) at the damper's point D of the blade's left-hand and right-hand
        platform, per unit modal coordinate of blade 0 (blade j: times e^{i j phi}).
    name: a label for tables and figures.
    platform_residual: (n, 6, 6) complex Hermitian, positive semi-definite, or None (zeros): the
        residual flexibility of the platforms at D, (left u, v, theta, right u, v, theta) in
        (mm, mm, rad) per (N, N, N mm), from the modes the family leaves out (module docstring),
        for the travelling wave of blade 0 (blade j: times e^{i j phi}).
    """

    n_blades: int
    nodal_diameter: np.ndarray
    frequency_hz: np.ndarray
    loss_factor: np.ndarray
    modal_force: np.ndarray
    response_displacement: np.ndarray
    left_platform: np.ndarray
    right_platform: np.ndarray
    name: str = ""
    platform_residual: np.ndarray | None = None

    def __repr__(self):
        nd = np.asarray(self.nodal_diameter)
        f = np.asarray(self.frequency_hz)
        return (f"ModalFamily({self.name or 'unnamed'}: {self.n_blades} blades, nodal diameters "
                f"{nd.min()}..{nd.max()} ({nd.size}), {f.min():.4g}..{f.max():.4g} Hz)")


def validate_family(family: ModalFamily) -> ModalFamily:
    """The family's fields checked and converted (numpy: ints, floats, complex): ValueError in one
    line naming the field and what it must be."""
    if not isinstance(family, ModalFamily):
        raise ValueError(f"modes must be a jaxdamp.ModalFamily; got {type(family).__name__}")
    n_blades = check_int("n_blades", family.n_blades, 2)
    nd_raw = np.asarray(family.nodal_diameter)
    if nd_raw.ndim != 1 or nd_raw.size == 0:
        raise ValueError(f"nodal_diameter must be a 1-D array of one or more integers in "
                         f"[0, {n_blades // 2}]; got shape {nd_raw.shape}")
    n = nd_raw.size
    out = {}
    for name, (tail, complex_ok, unit) in FAMILY_FIELDS.items():
        value = np.asarray(getattr(family, name))
        if value.shape != (n,) + tail:
            raise ValueError(f"{name} must have shape {(n,) + tail} (one row per nodal diameter); "
                             f"got {value.shape}")
        if not complex_ok and np.iscomplexobj(value) and np.any(np.imag(value) != 0):
            raise ValueError(f"{name} must be real; got complex values")
        value = value.astype(complex if complex_ok else float)
        if not np.all(np.isfinite(value)):
            raise ValueError(f"{name} must be finite{f' ({unit})' if unit else ''}; got {value!r}")
        out[name] = value
    nd = out["nodal_diameter"]
    if np.any(nd != np.round(nd)) or np.any(nd < 0) or np.any(nd > n_blades // 2):
        raise ValueError(f"nodal_diameter must hold integers in [0, {n_blades // 2}] (n_blades = "
                         f"{n_blades}); got {nd_raw.tolist()}")
    if np.unique(nd).size != n:
        raise ValueError(f"nodal_diameter must not repeat; got {nd_raw.tolist()}")
    check_range("frequency_hz", out["frequency_hz"], 0.0, np.inf, lo_open=True, hi_open=True,
                unit="Hz")
    check_param("eta", out["loss_factor"], "loss_factor")
    if np.any(out["response_displacement"] == 0):
        raise ValueError("response_displacement must be non-zero at every nodal diameter (mm per "
                         "unit modal coordinate): the response is reduced to that point")
    out["nodal_diameter"] = nd.astype(int)
    out["platform_residual"] = _residual(family.platform_residual, n)
    return ModalFamily(n_blades=n_blades, name=str(family.name), **out)


RESIDUAL_RTOL = 1e-9  # of the largest entry: how far from Hermitian and PSD a residual may be


def _residual(value, n) -> np.ndarray:
    """platform_residual checked: zeros where None; shape (n, 6, 6), finite, Hermitian and
    positive semi-definite (a flexibility stores energy, it makes none) to RESIDUAL_RTOL."""
    tail, unit = OPTIONAL_FIELDS["platform_residual"]
    if value is None:
        return np.zeros((n,) + tail, complex)
    c = np.asarray(value)
    if c.shape != (n,) + tail:
        raise ValueError(f"platform_residual must have shape {(n,) + tail} (one 6x6 per nodal "
                         f"diameter); got {c.shape}")
    c = c.astype(complex)
    if not np.all(np.isfinite(c)):
        raise ValueError(f"platform_residual must be finite ({unit})")
    scale = max(float(np.max(np.abs(c))), np.finfo(float).tiny)
    if np.max(np.abs(c - np.conj(np.swapaxes(c, 1, 2)))) > RESIDUAL_RTOL * scale:
        raise ValueError("platform_residual must be Hermitian (C = C^H at every nodal diameter)")
    if np.min(np.linalg.eigvalsh(c)) < -RESIDUAL_RTOL * scale:
        raise ValueError("platform_residual must be positive semi-definite (a flexibility: no "
                         "negative eigenvalue)")
    return c


def excited_nodal_diameter(engine_order: int, n_blades: int) -> tuple[int, bool]:
    """(n, backward): the nodal diameter n in [0, N/2] that engine order e excites, and whether
    its travelling wave is the backward one (e mod N > N/2: the family's data are conjugated)."""
    e = int(engine_order) % n_blades
    return (n_blades - e, True) if 2 * e > n_blades else (e, False)


class NodalScene(NamedTuple):
    """One engine order's reduced scene: the one-mode blade at the tip and the damper's path.

    mode: BladeMode (f0_hz, k_b N/mm, eta, r mrad/mm) in tip coordinates.
    motion: the damper's path per mrad of psi = r A (a straight or elliptic `jaxdamp.Motion`).
    force_per_unit: tip force amplitude (N) per N of the engine-order excitation.
    residual_mrad_per_nmm: c, the path's residual flexibility (module docstring; 0 without
        platform_residual): the damper's amplitude is psi_d = r A / |1 + c k(psi_d)|.
    rotation_mrad_per_mm: the platforms' largest rotation amplitude (either platform's own, or
        the one relative to the other) per mm of tip amplitude, mrad/mm: what the small-rotation
        model limits (`SMALL_ROTATION_MRAD`). It is not r: psi is a scale of the whole path
        (|X_hat| = q*/1000 per mrad), which where the platforms turn relative to each other is
        about ten times their rotation (100 mm of q* against a rotation in mrad); in phase the
        two agree (psi is the platforms' common rotation).
    """

    engine_order: int
    nodal_diameter: int
    ibpa_deg: float
    mode: BladeMode
    motion: Motion
    force_per_unit: float
    residual_mrad_per_nmm: float = 0.0
    rotation_mrad_per_mm: float = 0.0

    @property
    def straight(self) -> bool:
        return self.motion.quadrature is None


def nodal_scene(family: ModalFamily, engine_order: int, q_star_mm: float, h_l_mm: float) -> NodalScene:
    """The reduction of the module docstring for engine order e (an integer >= 0), with the
    damper's q* (mm) and size h_L (its left flank's length, mm). The family is checked
    (`validate_family`); ValueError also where e excites a nodal diameter the family lacks, or
    where the damper sees no relative platform motion.

    r is a scale of the path, not the platforms' rotation per mm of tip: where the platforms turn
    relative to each other, the relative rotation (mrad) dominates |X_hat| and r is larger than
    the blade's own platform rotation per tip mm (only r^2 k(r A) enters the response)."""
    return nodal_scenes(family, [engine_order], q_star_mm, h_l_mm)[0]


def nodal_scenes(family: ModalFamily, engine_orders, q_star_mm: float,
                 h_l_mm: float) -> list[NodalScene]:
    """`nodal_scene` of each engine order, the family and the damper checked once."""
    family = validate_family(family)
    q_star_mm = float(check_values("q_star", q_star_mm, max_ndim=0))
    h_l_mm = float(check_values("h_l", h_l_mm, max_ndim=0))
    return [_reduced(family, e, q_star_mm, h_l_mm) for e in engine_orders]


def _reduced(family: ModalFamily, engine_order, q_star_mm, h_l_mm) -> NodalScene:
    """One engine order's reduction (module docstring) on a checked family."""
    e = check_int("engine_order", engine_order, 0)
    n_blades = family.n_blades
    nd, backward = excited_nodal_diameter(e, n_blades)
    rows = np.flatnonzero(np.asarray(family.nodal_diameter) == nd)
    if rows.size == 0:
        raise ValueError(f"engine_order {e} excites nodal diameter {nd} (n_blades {n_blades}), "
                         f"which the modal family lacks (it has "
                         f"{np.asarray(family.nodal_diameter).tolist()})")
    i = int(rows[0])
    pick = (lambda v: np.conj(v)) if backward else (lambda v: v)  # noqa: E731
    phi = 2.0 * np.pi * (e % n_blades) / n_blades
    shift = np.exp(1j * phi) if (2 * (e % n_blades)) % n_blades else complex(np.cos(phi))
    left, right = pick(family.left_platform[i]), pick(family.right_platform[i])
    per_q = shift * left - right
    per_q = per_q * np.array([1.0, 1.0, MRAD_PER_RAD])  # theta: rad -> mrad
    tip = complex(pick(family.response_displacement[i]))
    per_tip = per_q / tip
    size = float(np.linalg.norm(per_tip))
    if size == 0.0:
        raise ValueError(f"the damper sees no relative platform motion at nodal diameter {nd} "
                         f"(engine order {e}): left_platform and right_platform cancel")
    r = MRAD_PER_RAD * size / float(q_star_mm)
    unit = per_tip / r
    # Phase: dv real and positive (or the largest component real, where dv is zero).
    k = 1 if abs(unit[1]) > 1e-12 * np.max(np.abs(unit)) else int(np.argmax(np.abs(unit)))
    unit = unit * np.exp(-1j * np.angle(unit[k]))
    unit[k] = abs(unit[k])
    motion = general_motion(unit, h_l_mm)
    omega = 2.0 * np.pi * float(family.frequency_hz[i])
    mode = BladeMode(float(family.frequency_hz[i]), omega ** 2 / abs(tip) ** 2,
                     float(family.loss_factor[i]), r)
    force = abs(complex(family.modal_force[i])) / abs(tip)
    residual = _path_residual(pick(family.platform_residual[i]), shift, unit)
    turns = (left[2], right[2], shift * left[2] - right[2])  # rad per unit of the mode
    rotation = MRAD_PER_RAD * max(abs(t) for t in turns) / abs(tip)
    return NodalScene(e, nd, float(np.rad2deg(phi)), mode, motion, force, residual, rotation)


def _path_residual(c6, shift, unit) -> float:
    """c (mrad per N mm): the platforms' residual flexibility c6 (6x6) seen by the damper along
    its path, unit (mm, mm, mrad) per mrad of psi (module docstring)."""
    d = np.concatenate([np.conj(shift) * np.eye(3), -np.eye(3)])  # (6, 3): the damper's load
    c_rel = d.conj().T @ c6 @ d
    x = np.asarray(unit) * np.array([MRAD_PER_RAD, MRAD_PER_RAD, 1.0])  # per rad, (mm, mm, rad)
    return float(MRAD_PER_RAD * np.real(x.conj() @ c_rel @ x) / np.real(x.conj() @ x) ** 2)


def family_from_blade_mode(mode: BladeMode, q_star_mm: float, h_c_mm: float = 0.0,
                           n_blades: int = 2, name: str = "in-phase") -> ModalFamily:
    """The one-mode family whose nodal diameter 0 is `mode` on the paper's in-phase motion: each
    blade's platforms turn rigidly about its centre C (h_c_mm below D, q*/2 to the side) by
    r A / 1e3 rad (clockwise, so that dv = q* psi is positive), the tip moves omega0 / sqrt(k_b) mm
    per unit modal coordinate (k_b = omega0^2 / Phi_tip^2), and the modal force is Phi_tip (a unit
    tip force). `nodal_scene(family, 0, q*, h_L)` gives `mode` back (r, f0, k_b,
    eta) with the in-phase path: the reduction's check against the one-mode blade."""
    theta = float(mode.r) / MRAD_PER_RAD  # rad per mm of tip
    left, right = (theta * d for d in platform_directions(q_star_mm, h_c_mm))
    scale = 2.0 * np.pi * float(mode.f0_hz) / np.sqrt(float(mode.k_b))  # tip mm per unit q
    return ModalFamily(n_blades, np.array([0]), np.array([float(mode.f0_hz)]),
                       np.array([float(mode.eta)]), np.array([scale + 0j]),
                       np.array([scale + 0j]), (scale * left)[None].astype(complex),
                       (scale * right)[None].astype(complex), name)
