"""Per-cycle summaries for the study and the figures: one jit-compiled function, reused.

`analyse_cycle` is compiled once for a given amplitude grid length and reused for every shape and
friction coefficient (all BaseCycles have the same pytree structure and array shapes). The numpy
helpers turn a cycle into the polylines the figures draw (exact: the cycle is piecewise linear).
"""

from __future__ import annotations

import string
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .energy import contact_energies, work_shape_factors
from .geometry import DamperShape, section_geometry, validate_shape
from .params import validate_mu
from .harmonics import complex_stiffness, five_numbers, moment_half
from .statics import statics_kernel
from .status import RESULTS

PSI_GRID_POINTS = 401
PSI_MAX_MRAD = 20.0


def psi_grid(psi_max=PSI_MAX_MRAD, points=PSI_GRID_POINTS) -> np.ndarray:
    """Amplitudes 0..psi_max (mrad) for the complex-stiffness curves (fixed length: one compile)."""
    return np.linspace(0.0, psi_max, points)


@jax.jit
def _analyse(bc, psi):
    nums = five_numbers(bc)
    w = work_shape_factors(bc)
    e = contact_energies(bc)
    k_re, k_im = complex_stiffness(bc, psi, method="interpolated")
    return dict(psi_fs_mrad=nums.psi_fs, k_re_fs=nums.k_re_fs, psi_bc_mrad=nums.psi_bc,
                k_re_bc=nums.k_re_bc, k_im_bc=nums.k_im_bc, w_R1=w.w_R1, w_L1=w.w_L1, w_L2=w.w_L2,
                w_M=w.w_M, energy_contacts=e.contacts, energy_moment=e.moment, k_re=k_re, k_im=k_im)


_moment_half = jax.jit(moment_half)
STIFFNESS_SLOTS = 8  # amplitudes per call of stiffness_at (padded: one compile)


def stiffness_at(bc, psi_a_mrad):
    """(k_Re, k_Im) numpy arrays at a few amplitudes (mrad), jit-compiled once for any count <= 8."""
    psi = np.atleast_1d(np.asarray(psi_a_mrad, float))
    out_re, out_im = [], []
    for i in range(0, len(psi), STIFFNESS_SLOTS):
        chunk = psi[i:i + STIFFNESS_SLOTS]
        padded = np.pad(chunk, (0, STIFFNESS_SLOTS - len(chunk)), constant_values=1.0)
        k_re, k_im = jax.device_get(complex_stiffness(bc, jnp.asarray(padded), method="interpolated"))
        out_re.append(np.asarray(k_re)[: len(chunk)])
        out_im.append(np.asarray(k_im)[: len(chunk)])
    return np.concatenate(out_re), np.concatenate(out_im)


@jax.jit
def _section_data(shape, mu):
    return section_geometry(shape), statics_kernel(shape, mu)


def section_data(shape, mu):
    """(SectionGeometry, FullSlipStatics) as numpy pytrees, jit-compiled once for every shape."""
    validate_shape(shape)
    validate_mu(mu)
    shape = DamperShape(*(None if v is None else jnp.asarray(v, float) for v in shape))
    return jax.device_get(_section_data(shape, jnp.asarray(mu, float)))


class CycleSummary(NamedTuple):
    """Numbers of one Base-Cycle as numpy / python values (psi in mrad, k in N mm/mrad, W in N mm)."""

    numbers: dict  # the five numbers and the work shape factors, floats
    energy_Nmm: dict  # R1, L1, L2, M: energy dissipated per Base-Cycle
    psi: np.ndarray  # amplitude grid of the stiffness curves, mrad
    k_re: np.ndarray
    k_im: np.ndarray
    status: RESULTS  # the Base-Cycle's status (numbers exist where it is not liftoff)


def analyse_cycle(bc, psi=None) -> CycleSummary:
    """Five numbers, work shape factors, energies and k(psi_a) curves of one BaseCycle."""
    psi = psi_grid() if psi is None else np.asarray(psi, float)
    out = jax.device_get(_analyse(bc, jnp.asarray(psi)))
    keys = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc", "w_R1", "w_L1", "w_L2", "w_M")
    numbers = {k: float(out[k]) for k in keys}
    ec = np.asarray(out["energy_contacts"])
    energy = {"R1": float(ec[0]), "L1": float(ec[1]), "L2": float(ec[2]), "M": float(out["energy_moment"])}
    return CycleSummary(numbers, energy, psi, np.asarray(out["k_re"]), np.asarray(out["k_im"]),
                        RESULTS(int(np.asarray(bc.status))))


# ---------------------------------------------------------------- polylines (numpy, exact vertices)
def point_names(n: int) -> list[str]:
    """Point names along a cycle: 0, A, B, ... (the paper's labels)."""
    letters = string.ascii_uppercase
    return ["0"] + [letters[i % 26] + ("'" * (i // 26)) for i in range(n - 1)]


def force_points(bc):
    """Contact forces (N, T), units of F_D, at every tract end of the cycle: 0, A, B, ... back to 0.

    Returns (N, T) arrays of shape (n_points, 3); zero-length tracts repeat a point (as in the paper).
    """
    Ns, Ts = [], []
    for half in (bc.forward, bc.backward):
        active = np.asarray(half.active)
        for i in np.nonzero(active)[0]:
            Ns.append(np.asarray(half.N0[i]))
            Ts.append(np.asarray(half.T0[i]))
    Ns.append(np.asarray(bc.backward.N_end))
    Ts.append(np.asarray(bc.backward.T_end))
    return np.array(Ns), np.array(Ts)


def moment_polyline(bc, psi_a_mrad=None):
    """Vertices of the moment cycle at amplitude psi_a >= psi_BC (default: the Base-Cycle).

    Returns (psi, M, labels): psi - psi_c in mrad, M in N mm, and the paper's point names. The loop
    starts at point 0 (psi = +psi_a), runs the forward half (psi decreasing) and then the backward
    half; a half shorter than the longest ends with a constant-moment full-slip stretch (C-C′ at
    mid-cycle, F-0 at the end), and at psi_a > psi_BC both halves end with one. The last vertex
    closes the loop (psi = +psi_a).
    """
    q = float(bc.load.q_star)
    span = max(float(bc.forward.span), float(bc.backward.span))
    psi_bc = span / (2.0 * q) * 1e3
    psi_a = psi_bc if psi_a_mrad is None else max(float(psi_a_mrad), psi_bc)
    total = 2.0 * psi_a * q / 1e3
    psi, M, kinds = [], [], []
    x = psi_a
    for branch, half in ((-1.0, bc.forward), (1.0, bc.backward)):
        seg = jax.device_get(_moment_half(bc, half, total))
        for i in np.nonzero(np.asarray(half.active))[0]:
            psi.append(x)
            M.append(float(seg.M0[i]))
            kinds.append("tract")
            x = x + branch * float(seg.dv[i]) / q * 1e3
        psi.append(x)
        M.append(float(seg.M0[-1]))
        kinds.append("half-end")
        stretch = float(seg.dv[-1])
        if stretch > 1e-12 * total:
            x = x + branch * stretch / q * 1e3
            psi.append(x)
            M.append(float(seg.M0[-1]))
            kinds.append("stretch-end")
    # A half starts where the previous one (or its stretch) ended: drop the repeated vertex.
    keep = [0] + [k for k in range(1, len(psi)) if (psi[k], M[k]) != (psi[k - 1], M[k - 1])]
    psi, M, kinds = [psi[k] for k in keep], [M[k] for k in keep], [kinds[k] for k in keep]
    names, labels, letter = iter(point_names(64)), [], "0"
    for k, kind in enumerate(kinds):
        if kind == "stretch-end":
            labels.append("0" if k == len(kinds) - 1 else f"{letter}\u2032")  # the paper's C′
        else:
            letter = next(names)
            labels.append(letter)
    if labels[-1] != "0":
        labels[-1] = f"{labels[-1]}\u22610"  # F = 0: the cycle closes exactly at the last tract end
    return np.array(psi), np.array(M), labels


def sample_cycle(psi_v, M_v, psi_a, n=4096):
    """Sample a closed moment polyline at psi = psi_a cos(tau), tau uniform in [0, 2 pi).

    The forward half (psi decreasing) covers tau in [0, pi], the backward half tau in [pi, 2 pi].
    Returns (tau, M(tau)).
    """
    psi_v, M_v = np.asarray(psi_v), np.asarray(M_v)
    k_min = int(np.argmin(psi_v))
    tau = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    x = psi_a * np.cos(tau)
    fwd_psi, fwd_M = psi_v[: k_min + 1][::-1], M_v[: k_min + 1][::-1]
    bwd_psi, bwd_M = psi_v[k_min:], M_v[k_min:]
    m = np.where(tau <= np.pi, np.interp(x, fwd_psi, fwd_M), np.interp(x, bwd_psi, bwd_M))
    return tau, m


def numeric_first_harmonic(psi_v, M_v, psi_a, n=4096):
    """(M_0, k_Re, k_Im) of a closed moment polyline by numerical Fourier sums (independent check).

    M(tau) ~ M_0 + psi_a (k_Re cos tau - k_Im sin tau).
    """
    tau, m = sample_cycle(psi_v, M_v, psi_a, n)
    m0 = float(np.mean(m))
    k_re = float(2.0 * np.mean(m * np.cos(tau)) / psi_a)
    k_im = float(-2.0 * np.mean(m * np.sin(tau)) / psi_a)
    return m0, k_re, k_im


__all__ = ["PSI_GRID_POINTS", "PSI_MAX_MRAD", "psi_grid", "STIFFNESS_SLOTS", "stiffness_at",
           "section_data", "CycleSummary", "analyse_cycle", "point_names", "force_points",
           "moment_polyline", "sample_cycle", "numeric_first_harmonic"]
