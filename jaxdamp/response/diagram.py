"""The designer's diagram: peak amplitude against excitation force and against F_D, over a range of
mu, with the free and stuck limits."""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_values
from ..runtime import batch_jit, run_program
from ..status import number_repr, status_repr
from .peaks import peak_frequency_hz, peak_response
from .scene import BladeMode, Scene, prepare_scene
from .stiffness import damper_stiffness_kernel, scaled_stiffness, stuck_damper

__all__ = ["DesignerDiagram", "DIAGRAM_MUS", "designer_diagram", "diagram_program"]


class DesignerDiagram(NamedTuple):
    """Peak response against force and against F_D, over a friction range (numpy arrays).

    peak_vs_force_mm: (n_mu, n_force) at the design's F_D; peak_vs_fd_mm: (n_mu, n_fd) at
    force_at_fd_n. band_*: min and max over mu. stuck_*: the damper stuck (k_Re,fs, k_Im = 0);
    free_*: no damper. In the loss-factor model both limits have the peak F / (eta k_b): they
    coincide in amplitude and differ in frequency (stuck_frequency_hz, per mu, against f0).
    status: (n_mu,) damper status per mu.
    """

    mu: np.ndarray
    force_n: np.ndarray
    fd_n: np.ndarray
    force_at_fd_n: float
    peak_vs_force_mm: np.ndarray
    peak_vs_fd_mm: np.ndarray
    band_force_mm: np.ndarray  # (2, n_force): min, max over mu
    band_fd_mm: np.ndarray  # (2, n_fd)
    free_vs_force_mm: np.ndarray
    stuck_vs_force_mm: np.ndarray
    free_vs_fd_mm: np.ndarray
    stuck_vs_fd_mm: np.ndarray
    stuck_frequency_hz: np.ndarray  # (n_mu,)
    status: np.ndarray

    def __repr__(self):
        return (f"DesignerDiagram(mu {number_repr(self.mu, '')}, F {number_repr(self.force_n, 'N')}, "
                f"F_D {number_repr(self.fd_n, 'N')}, A* {number_repr(self.peak_vs_force_mm, 'mm')}, "
                f"status {status_repr(self.status)})")


DIAGRAM_MUS = (0.3, 0.4, 0.5, 0.6, 0.7)


def designer_diagram(shape, mode: BladeMode | None = None, contacts=None, load=None, *,
                     force_n=None, fd_n=None, force_at_fd_n=None, mu=DIAGRAM_MUS,
                     method: str = "exact", runner=None, **options) -> DesignerDiagram:
    """The designer's diagram of one shape: peak A* against F (log-log) and against F_D at fixed
    F, for each mu (the band is their envelope), with the stuck and free limits.

    The F_D sweep uses `scaled_stiffness`: one damper curve per mu for every F_D. One compiled
    program (`diagram_program`), vmapped over mu; runner(program, args) -> outputs runs it
    (default program(*args); the CLI passes one that reuses a saved export of the program).

    shape may be a Scene (`prepare_scene`, checked already: mode, contacts and load are then its
    own, and its mu is not used: the diagram runs over `mu`). The friction range mu is checked
    unless it is DIAGRAM_MUS.
    """
    # A Scene marks a caller that has checked its inputs (the CLI): its grids are taken as given.
    checked = isinstance(shape, Scene)
    if checked:
        scene = prepare_scene(shape, None, contacts, load, mode)
        mus = np.atleast_1d(np.asarray(mu, float) if mu is DIAGRAM_MUS else check_values("mu", mu))
    else:
        mus = np.atleast_1d(check_values("mu", mu))
        scene = prepare_scene(shape, float(mus[0]), contacts, load, mode)
    shape, _, contacts, load, mode = scene
    fd0 = float(load.F_D)
    if not float(mode.eta) > 0.0:  # the free blade's peak F / (eta k_b) is the diagram's limit
        raise ValueError(f"mode.eta must be in (0, 1] for the designer's diagram (its free-blade "
                         f"limit F / (eta k_b)); got {float(mode.eta):g}")
    def given(value, name, label, max_ndim=1):
        return np.asarray(value, float) if checked else check_values(name, value, label,
                                                                      max_ndim=max_ndim)

    force = (np.geomspace(0.05, 100.0, 41) if force_n is None
             else np.atleast_1d(given(force_n, "force_n", "force_n")))
    fds = (np.geomspace(fd0 / 30.0, fd0 * 30.0, 41) if fd_n is None
           else np.atleast_1d(given(fd_n, "F_D", "fd_n")))
    f_fd = float(np.median(force) if force_at_fd_n is None
                 else given(force_at_fd_n, "force_n", "force_at_fd_n", max_ndim=0))
    program = diagram_program(method, tuple(sorted(options.items())))
    args = (shape, jnp.asarray(mus), contacts, load, mode, jnp.asarray(force), jnp.asarray(fds),
            jnp.asarray(fd0), jnp.asarray(f_fd))
    outs = run_program(program, args, runner)
    by_force, by_fd, stuck_f, status = (np.asarray(v) for v in outs)
    free_f = force / (float(mode.eta) * float(mode.k_b))
    free_d = np.full(fds.shape, f_fd / (float(mode.eta) * float(mode.k_b)))
    return DesignerDiagram(
        mus, force, fds, f_fd, by_force, by_fd, np.stack([by_force.min(0), by_force.max(0)]),
        np.stack([by_fd.min(0), by_fd.max(0)]), free_f, free_f.copy(), free_d, free_d.copy(),
        stuck_f, status.astype(int))


@functools.cache
def diagram_program(method: str, options: tuple = ()):
    """The designer's diagram as one compiled program per method and options, vmapped over mu:
    (shape, mus, contacts, load, mode, forces, fds, fd0, force_at_fd) -> (peak against force
    (n_mu, n_force), against F_D (n_mu, n_fd), stuck frequency (n_mu,), status (n_mu,))."""
    def per_mu(shape, m, contacts, load, mode, forces, fds, fd0, f_fd):
        d = damper_stiffness_kernel(shape, m, contacts, load, method, **dict(options))
        by_force = peak_response(d, mode, forces).peak_amplitude_mm  # one shared grid
        by_fd = jax.vmap(lambda fd: peak_response(scaled_stiffness(d, fd0, fd), mode,
                                                  f_fd).peak_amplitude_mm)(fds)
        stuck_f = peak_frequency_hz(stuck_damper(d.k_re_stuck), mode, 1.0)
        return by_force, by_fd, stuck_f, d.status

    return batch_jit(jax.vmap(per_mu, in_axes=(None, 0, None, None, None, None, None, None, None)))
