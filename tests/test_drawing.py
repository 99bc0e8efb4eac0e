"""Figures drawn as jobs (`jaxdamp.plotting.drawing`): a worker process saves the same PNG as the
calling process, in the order submitted, at a lower priority, and a job's error reaches the
caller."""

import functools
import os

import pytest

import jaxdamp as jd
from jaxdamp import plotting as P
from jaxdamp.plotting.drawing import FIGURE_NICENESS, FigureJob, FigureSaver, default_processes


class _Count:
    """A tqdm-like bar that counts its updates."""

    def __init__(self):
        self.n = 0

    def update(self, k):
        self.n += k


def _jobs():
    import jax

    # the cycle's arrays as NumPy, as the study hands them to its jobs
    bcs = [jax.device_get(jd.base_cycle(jd.family_shape("60sym"), 0.5))]
    return [FigureJob("section.png", "the section", "Sections", P.plot_section,
                      (jd.family_shape("60sym"), 0.5)),
            FigureJob("moment.png", "the moment cycle", "Moments", P.plot_moment_cycles, (bcs,)),
            FigureJob("stiffness.png", "k", "Stiffness",
                      functools.partial(P.plot_complex_stiffness, psi_max=10.0), (bcs,))]


def test_a_worker_process_saves_the_same_pngs_as_this_process(tmp_path):
    jobs = _jobs()
    here, there = _Count(), _Count()
    with FigureSaver(tmp_path / "here", 0, here) as saver:
        saver.submit(jobs)
        paths_here = saver.results()
    with FigureSaver(tmp_path / "there", 1, there) as saver:
        saver.submit(jobs)
        paths_there = saver.results()
        if hasattr(os, "getpriority"):  # the worker draws below the caller's priority
            theirs = saver._pool.submit(os.getpriority, os.PRIO_PROCESS, 0).result()
            assert theirs == min(os.getpriority(os.PRIO_PROCESS, 0) + FIGURE_NICENESS, 19)
    assert [p.name for p in paths_here] == [p.name for p in paths_there] == [j.name for j in jobs]
    for a, b in zip(paths_here, paths_there):
        assert a.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert a.read_bytes() == b.read_bytes(), a.name  # Agg draws the same pixels anywhere
    assert here.n == there.n == len(jobs)


def test_a_job_error_in_a_worker_is_raised_by_results(tmp_path):
    bad = FigureJob("bad.png", "", "", jd.family_shape, ("no such shape",))
    with FigureSaver(tmp_path, 1) as saver:
        saver.submit([bad])
        with pytest.raises(ValueError, match="shape must be one of"):
            saver.results()
    assert not (tmp_path / "bad.png").exists()


def test_default_processes_is_one_per_core_within_the_cap():
    n = default_processes()
    assert 1 <= n <= 8
