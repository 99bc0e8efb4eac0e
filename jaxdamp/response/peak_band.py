"""The band of peaks over every admissible contact history: the response of the band's lower and
upper k_Im curves (`jaxdamp.band`), tabulated and run through one compiled peak program."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from ..band import amplitude_bands_unchecked, check_band_amplitudes, compile_bands_ahead
from .._validate import check_values
from ..runtime import batch_jit, compile_ahead, run_program
from ..status import RESULTS
from .peaks import peak_response
from .scene import BladeMode, Scene, prepare_scene
from .stiffness import DamperStiffness, base_scale, tabulated_stiffness

__all__ = ["peak_band", "peak_band_unchecked", "GRID_POINTS"]

# The band's default amplitude grid: this many points from 0.05 psi_BC to 3 psi_BC.
GRID_POINTS = 24


def peak_band(shape, mu=None, contacts=None, load=None, mode: BladeMode | None = None, force_n=1.0,
              psi_grid_mrad=None, n_samples: int = 64, steps: int = 6, runner=None):
    """Bounds of the peak amplitude A* (mm) over every admissible contact history.

    At each amplitude every history's steady cycle has k_Im inside the band
    (`jaxdamp.band.amplitude_band`), and the peak equation A (eta k_b + 1e-3 r^2 k_Im(r A)) = F
    gives a smaller A for a larger k_Im: the peaks of the band's lower and upper k_Im curves bracket
    the peak of every history. The band is tabulated on psi_grid_mrad (default: 24 amplitudes from
    0.05 psi_BC to 3 psi_BC, through one program: `band.amplitude_bands`; runner as there) and
    interpolated linearly between them. Returns (Peaks with the band's
    lowest k_Im: the highest A*, Peaks with its highest k_Im: the lowest A*, the grid and the
    bound curves). shape may be a Scene (`prepare_scene`): the mark of a caller that has checked
    its inputs (the CLI), whose forces are then taken as given too; otherwise force_n is checked."""
    checked = isinstance(shape, Scene)
    scene = prepare_scene(shape, mu, contacts, load, mode)
    force = jnp.asarray(force_n if checked else check_values("force_n", force_n), float)
    return peak_band_unchecked(scene, force, psi_grid_mrad, n_samples, steps, runner)


def peak_band_unchecked(scene: Scene, force_n, psi_grid_mrad=None, n_samples: int = 64,
                     steps: int = 6, runner=None):
    """`peak_band` of a Scene (`prepare_scene`) at forces checked already: neither is checked
    here (the amplitude grid and the counts are)."""
    shape, mu, contacts, load, mode = scene
    # checked before anything compiles ahead (the band's call checks them again)
    n_grid = GRID_POINTS if psi_grid_mrad is None else check_band_amplitudes(psi_grid_mrad).size
    # The grid waits on psi_BC, its program's shape does not: the band's program (the longest to
    # compile) compiles while the Base-Cycle's does and runs.
    compile_bands_ahead(shape, mu, contacts, load, n_grid, n_samples=n_samples, steps=steps,
                        runner=runner)
    status, k_re_stuck, psi_ref = run_program(base_scale, (shape, mu, contacts, load), runner)
    force = jnp.asarray(force_n, float)
    tail = (status, k_re_stuck, psi_ref, mode, force.reshape(-1))
    placeholder = np.zeros(n_grid)
    compile_ahead(_band_peaks, (placeholder,) * 4 + tail, runner)  # while the band runs
    if psi_grid_mrad is None:
        psi_ref = float(psi_ref)
        psi_grid_mrad = np.geomspace(0.05 * psi_ref, 3.0 * psi_ref, GRID_POINTS)
    grid = np.asarray(psi_grid_mrad, float)
    # every amplitude's band through one program (sampling plus the trust-region refinement)
    bands = amplitude_bands_unchecked(shape, mu, contacts, load, grid, n_samples=n_samples,
                                   steps=steps, runner=runner)
    # (n, 4): k_re_min, k_re_max, k_im_min, k_im_max; zero where no history gives a valid cycle
    k = np.array([b.bounds if b.status == RESULTS.ok else np.zeros(4) for b in bands])
    # The frequency uses k_Re; at the bound of k_Im take the k_Re of the same band (its middle).
    k_re_mid = 0.5 * (k[:, 0] + k[:, 1])
    highest, lowest = run_program(_band_peaks, (
        jnp.asarray(grid), jnp.asarray(k_re_mid), jnp.asarray(k[:, 2]), jnp.asarray(k[:, 3]))
        + tail, runner)
    pick = (lambda x: x[0]) if force.ndim == 0 else (lambda x: x)  # noqa: E731
    return jax.tree_util.tree_map(pick, highest), jax.tree_util.tree_map(pick, lowest), grid, k


@batch_jit
def _band_peaks(grid, k_re, k_im_low, k_im_high, status, k_re_stuck, psi_ref, mode, forces):
    """Peaks at each force of the band's lowest k_Im curve (its lower envelope: the highest peaks)
    and of its highest (upper envelope: the lowest peaks), tabulated on grid
    (`tabulated_stiffness`): one module-level program, the curves its arguments."""
    base = DamperStiffness(None, status, k_re_stuck, psi_ref)

    def peaks(k_im, envelope):
        damper = tabulated_stiffness(grid, k_re, k_im, base, envelope=envelope)
        return jax.vmap(lambda f: peak_response(damper, mode, f))(forces)

    return peaks(k_im_low, "lower"), peaks(k_im_high, "upper")
