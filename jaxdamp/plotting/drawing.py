"""Figures described as jobs, and drawn and saved in processes of their own.

Drawing is matplotlib, which holds Python's lock: in one process the study's 34 figures cost about
a second of CPU each on the 2-core VM (text layout and the constrained layout, docs/performance.md)
and they compete with the computing's own Python. A `FigureJob` describes one figure without
drawing it (a module-level builder and its NumPy data, both of which pickle), so a pool of worker
processes (`FigureSaver`) can draw and save many at once while the calling process computes.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import NamedTuple

from ..paper.files import save_figure
from ..runtime import cpu_cores

FIGURE_DPI = 110  # the study's PNGs
MAX_FIGURE_PROCESSES = 8  # beyond this, starting processes (about 2 s each) outweighs drawing
# The workers' scheduling priority below the caller's (POSIX nice): on a study's first call the
# critical path is XLA compiling its programs, not the drawing, so the compiling takes the cores
# first and the figures fill the rest (2-core VM, 2026-11-27: first call 58.9 and 63.8 s against
# 74.1 and 79.8 s at equal priority, alternating; the repeat unchanged, 42-44 s against 42-46 s).
FIGURE_NICENESS = 10


class FigureJob(NamedTuple):
    """One figure: build(*args) -> Figure, saved as `name`, with its report caption and section.
    `build` is a module-level function (or a functools.partial of one) and args are NumPy data or
    plain Python, so that a job pickles to a worker process."""

    name: str
    caption: str
    section: str
    build: Callable
    args: tuple = ()


def draw_job(job: FigureJob):
    """The job's Figure, a curve that lies on another one in any panel brought to the front with
    distinct markers and a note (`labels.mark_coincident_lines`)."""
    from .labels import mark_coincident_lines

    fig = job.build(*job.args)
    for ax in fig.axes:
        mark_coincident_lines(ax)
    return fig


def save_job(job: FigureJob, folder) -> Path:
    """Draw the job, save it as PNG in folder, close it; returns the path."""
    import matplotlib.pyplot as plt

    fig = draw_job(job)
    try:
        return save_figure(fig, Path(folder) / job.name, dpi=FIGURE_DPI)
    finally:
        plt.close(fig)


def default_processes() -> int:
    """One drawing process per core the calling process may use, at most MAX_FIGURE_PROCESSES."""
    return max(1, min(cpu_cores(), MAX_FIGURE_PROCESSES))


def _start_drawing_process(x64: bool, cache_dir, cache_min_compile_s) -> None:
    """A worker's settings, made explicitly before it draws: a lower priority (FIGURE_NICENESS),
    the headless Agg backend, the calling process's float64 switch and compilation cache (the
    figures' few small programs: a repeat loads them), and JAX on the CPU (a GPU's memory stays
    the caller's)."""
    if hasattr(os, "nice"):  # POSIX
        os.nice(FIGURE_NICENESS)
    import matplotlib

    matplotlib.use("Agg")
    import jax

    jax.config.update("jax_platforms", "cpu")
    jax.config.update("jax_enable_x64", x64)
    if cache_dir:
        jax.config.update("jax_compilation_cache_dir", cache_dir)
        jax.config.update("jax_persistent_cache_min_compile_time_secs", cache_min_compile_s)


def _warm() -> None:
    """A task that only starts its worker (the pool starts processes as tasks arrive)."""


class FigureSaver:
    """Saves FigureJobs as PNG in `folder`: with processes=0 on the calling thread at `submit`,
    else in that many spawned worker processes while the caller goes on. `results()` waits for
    every job and returns the saved paths in the order submitted; a job's error is raised there
    (a crashed worker too: `BrokenProcessPool`). A context manager: leaving it stops the workers.
    progress: None or a tqdm-like bar, updated once per saved figure."""

    def __init__(self, folder, processes: int = 0, progress=None):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.progress = progress
        self._done: list = []
        self._pool = None
        if processes > 0:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            import jax

            # spawn, not fork: the caller runs JAX's threads, which a forked child would inherit
            # half-copied
            self._pool = ProcessPoolExecutor(
                max_workers=processes, mp_context=multiprocessing.get_context("spawn"),
                initializer=_start_drawing_process,
                initargs=(bool(jax.config.jax_enable_x64), jax.config.jax_compilation_cache_dir,
                          jax.config.jax_persistent_cache_min_compile_time_secs))
            for _ in range(processes):  # start them now, while the caller computes
                self._pool.submit(_warm)

    def submit(self, jobs: Iterable[FigureJob]) -> None:
        for job in jobs:
            if self._pool is None:
                self._done.append(save_job(job, self.folder))
                self._tick()
            else:
                future = self._pool.submit(save_job, job, self.folder)
                future.add_done_callback(lambda _: self._tick())
                self._done.append(future)

    def _tick(self) -> None:
        if self.progress is not None:
            self.progress.update(1)

    def results(self) -> list[Path]:
        return [d if isinstance(d, Path) else d.result() for d in self._done]

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


__all__ = ["FigureJob", "FigureSaver", "draw_job", "save_job", "default_processes", "FIGURE_DPI",
           "MAX_FIGURE_PROCESSES", "FIGURE_NICENESS"]
