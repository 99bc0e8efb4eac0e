"""The study's figures and the whole study run: every figure the study writes (`study_figures`),
the README's key figure, and `run_study`, which computes the study (`jaxdamp.paper.study`) and
writes its data, report and figures. It sits in the plotting layer because it draws."""

from __future__ import annotations

import contextlib
import functools
import time
from pathlib import Path

from ..paper.claim import PLATFORM_CLAIM_SECTION
from ..paper.report import KEY_FIGURE_SECTION
from .._validate import check_int
from .drawing import FigureJob, FigureSaver, default_processes, draw_job
from ..paper.study import (DEFAULT_MU, DEFAULT_SHAPES, check_study_inputs, compute_study, mu_key,
                           paper_values, write_study)


PSI_C_NOTE = ("ψ_c is the centre of the rotation cycle: ψ_P oscillates between ψ_c − ψ_a and "
              "ψ_c + ψ_a, so the axis shows the rotation about the centre.")


def study_figures(cycles, summaries, summary):
    """Every figure of the study, one at a time: yields (Figure, file name, caption, section).

    A curve that lies on another one in any panel is brought to the front with distinct markers and
    a note (`mark_coincident_lines`). The caller saves and closes each figure or inspects it (the
    layout test); `run_study` draws the same jobs (`study_figure_jobs`), in processes of its own."""
    for job in study_figure_jobs(cycles, summaries, summary):
        yield draw_job(job), job.name, job.caption, job.section


def study_figure_jobs(cycles, summaries, summary) -> list[FigureJob]:
    """Every figure of the study as a `FigureJob`: those of the Base-Cycles, then those of the
    summary (bands, energies, the family, the claim, the key figure)."""
    return (cycle_figure_jobs(cycles, summaries, summary["meta"]["mus"], summary["load"]["q_star"])
            + summary_figure_jobs(cycles, summaries, summary))


def _as_numpy(tree):
    """The cycles' and summaries' arrays as NumPy: a job's data pickles without JAX's arrays."""
    import jax

    return jax.device_get(tree)


def stretched_figure(bcs):
    """The Base-Cycle and stretched cycles of each mu side by side (Fig. 14)."""
    import matplotlib.pyplot as plt

    from .figures import plot_stretched_cycles

    fig, axes = plt.subplots(1, len(bcs), figsize=(7.0 * len(bcs), 7.4), squeeze=False,
                             layout="constrained")
    for ax, bc in zip(axes[0], bcs):
        plot_stretched_cycles(bc, ax=ax)
    return fig


def cycle_figure_jobs(cycles, summaries, mus, q_star) -> list[FigureJob]:
    """The study's figures of each shape's Base-Cycles (section, tracks, moment, stretched cycles,
    complex stiffness), which need nothing but the cycles: the first of `study_figure_jobs`. mus:
    the study's mu keys; q_star in mm."""
    from .. import plotting as P
    from ..geometry import family_shape

    mu_max = max(mus, key=float)
    psi_c = PSI_C_NOTE
    jobs = []
    for s, per in cycles.items():
        bcs = _as_numpy(list(per.values()))
        jobs += [
            FigureJob(f"section_{s}.png",
                      f"{s}, μ = {mu_max}: section with pads, D, R, L, full-slip forces, friction "
                      "angles (dashed) and lines of action (dotted), at cycle start and mid-cycle "
                      "(cf. Fig. 7).", "Sections and lines of action (Fig. 7)",
                      P.plot_section, (family_shape(s), float(mu_max))),
            FigureJob(f"tracks_{s}.png",
                      f"{s}: equilibrium tracks (force Base-Cycles, F_D = 1) with secondary loops "
                      "(cf. Fig. 10b).", "Equilibrium tracks (Fig. 10b)",
                      P.plot_equilibrium_tracks, (bcs,)),
            FigureJob(f"moment_{s}.png",
                      f"{s}: moment Base-Cycles for q* = {q_star:g} mm (cf. Fig. 13). " + psi_c,
                      "Moment Base-Cycles (Fig. 13)", P.plot_moment_cycles, (bcs,)),
            FigureJob(f"stretched_{s}.png",
                      f"{s}: Base-Cycle and stretched cycles (solid) with their first-harmonic "
                      "ellipses (dotted) (cf. Fig. 14); C–C′ and F–0 are the full-slip stretches. "
                      + psi_c, "Stretched cycles and first harmonics (Fig. 14)",
                      stretched_figure, (bcs,)),
            FigureJob(f"stiffness_{s}.png",
                      f"{s}: k_Re and k_Im versus ψ_P,a with ψ_fs (circles) and ψ_BC (squares) "
                      "marked; linear interpolation in the microslip range between them (cf. Fig. "
                      "15, Appendix B). Right: the same curves zoomed on the microslip range.",
                      "Complex stiffness (Fig. 15, Appendix B)",
                      functools.partial(P.plot_complex_stiffness,
                                        summaries=_as_numpy(list(summaries[s].values()))), (bcs,)),
        ]
    return jobs


def summary_figure_jobs(cycles, summaries, summary) -> list[FigureJob]:
    """The study's figures that need its summary (bands, energies, the family, the claim) and the
    key figure."""
    from .. import plotting as P

    psi_c = PSI_C_NOTE
    jobs = [FigureJob(f"amplitude_stiffness_{s}.png",
                      f"{s}: k_Re (top) and k_Im (bottom) against ψ_a, one column per μ: the exact "
                      "steady cycles at each amplitude from the gross-slip (solid) and the assembly "
                      "(dash-dot) initial state, the band over all admissible initial states "
                      f"(shaded; {_band_words(per)}), the paper's linear interpolation (dashed); "
                      "ψ_fs and ψ_BC dotted. The interpolation's largest gap to the band is in the "
                      "report's table.", "k(ψ_a): exact, band and the paper's interpolation",
                      amplitude_stiffness_figure, (s, per))
            for s, per in summary.get("stiffness_band", {}).items()
            if any("curve" in e for e in per.values())]
    jobs.append(FigureJob(
        "energy.png",
        "Work shape factors (top) and energy dissipated per Base-Cycle (bottom) per contact; "
        "each shape's energy is that of its own Base-Cycle, so at its own amplitude ψ_BC (they "
        "differ by shape and μ); a bar labelled 0 dissipates (next to) nothing (90R: the mechanism "
        "freezes); black diamonds: w_M and ∮M dψ (cf. Appendix B/C).", "Dissipated energy per contact",
        P.plot_energy, (summary["results"], _as_numpy(summary["energies"]))))
    jobs.append(FigureJob(
        "family.png",
        "The family side by side: the five numbers and w_M for each μ; black ticks: the paper's "
        "Tables B3.1-B5.1.", "Family comparison (Table 11)",
        P.plot_family_comparison, (summary["results"], paper_values())))
    claim = summary.get("platform_claim")
    if claim:
        jobs.append(FigureJob(
            "platform_claim.png",
            "The curved-flat damper (60sym) and the wedge of the same base angles against the "
            "interblade phase angle (the paper's Fig. 4 kinematics): damping per mrad of blade "
            "rotation relative to in-phase (top) and the fraction of the period each pad is "
            "open (bottom).", PLATFORM_CLAIM_SECTION,
            functools.partial(P.plot_ibpa_claim, title=(
                "60sym (curved-flat, solid) and the 60/60 wedge (dashed) against the interblade "
                f"phase angle: h_C = {claim['h_c_mm']:g} mm, h_L = {claim['h_l_mm']:g} mm, from "
                "assembly (x: no valid cycle)")), (claim["curves"],)))
    if "60sym" in cycles and mu_key(0.7) in cycles["60sym"]:
        jobs.append(FigureJob(
            "key_figure.png",
            "60sym, μ = 0.7: stretched moment cycles with their first harmonics (left) and the "
            "complex stiffness they give (right). " + psi_c, KEY_FIGURE_SECTION,
            key_figure, _as_numpy((cycles["60sym"][mu_key(0.7)], summaries["60sym"][mu_key(0.7)]))))
    return jobs


def amplitude_data(entry) -> dict:
    """The study's stiffness_band entry of one design as `plot_amplitude_stiffness` data (NaN for
    null)."""
    import numpy as np

    def arr(v):
        return np.array([np.nan if x is None else x for x in v], float)

    c, b = entry["curve"], entry["band"]
    return {"psi_a_mrad": arr(c["psi_a_mrad"]), "psi_fs": entry["psi_fs_mrad"],
            "psi_bc": entry["psi_bc_mrad"],
            **{k: (arr(c[k]["k_re"]), arr(c[k]["k_im"])) for k in ("gross_slip", "assembly",
                                                                    "interpolated")},
            "band": (arr(b["psi_a_mrad"]), np.stack([arr(b[k]) for k in
                                                     ("k_re_min", "k_re_max", "k_im_min", "k_im_max")],
                                                    axis=1))}


def _band_words(per) -> str:
    b = next((e["band"] for e in per.values() if "band" in e), None)
    if b is None:
        return "none"
    return (f"{len(b['psi_a_mrad'])} amplitudes, drawn linear between them, {b['n_samples']} sampled states each plus the "
            "polytope's vertices, widened to hold both named states")


def amplitude_stiffness_figure(shape, per):
    """One figure per shape: columns per mu, rows k_Re and k_Im (`plot_amplitude_stiffness` on the
    study's data); a mu that lifts off gets an empty panel saying so. None if every mu lifts off."""
    import matplotlib.pyplot as plt

    from .amplitude import plot_amplitude_stiffness

    if not any("curve" in e for e in per.values()):
        return None
    fig, axes = plt.subplots(2, len(per), figsize=(5.2 * len(per), 7.6), squeeze=False,
                             layout="constrained")
    for j, (m, e) in enumerate(per.items()):
        col = axes[:, j]
        if "curve" not in e:
            for a in col:
                a.text(0.5, 0.5, f"μ = {m}: {e['status'].upper()}\n(no cycle)", ha="center",
                       va="center", transform=a.transAxes)
                a.set_xticks([])
                a.set_yticks([])
            continue
        plot_amplitude_stiffness(None, None, ax=col, data=amplitude_data(e))
        col[0].set_title(f"μ = {m}")
        if j != len(per) - 1 and col[-1].get_legend() is not None:
            col[-1].get_legend().remove()
    fig.suptitle(f"{shape}: complex stiffness against amplitude")
    return fig


def make_figures(out: Path, cycles, summaries, summary, progress=None, processes: int = 0) -> list[dict]:
    """Every figure of the study as PNG in out; returns [{file, caption, section, shape}] (paths
    relative to out/..). processes: 0 draws here, n > 0 in n worker processes (`FigureSaver`)."""
    jobs = study_figure_jobs(cycles, summaries, summary)
    with FigureSaver(out, processes, progress) as saver:
        saver.submit(jobs)
        saver.results()
    return figure_entries(out, cycles, jobs)


def figure_entries(out: Path, cycles, jobs) -> list[dict]:
    """The report's [{file, caption, section, shape}] of the jobs saved in out."""
    def shape_of(name):
        last = name[:-4].rsplit("_", 1)[-1]
        return last if last in cycles else None

    return [{"file": f"{Path(out).name}/{j.name}", "caption": j.caption, "section": j.section,
             "shape": shape_of(j.name)} for j in jobs]


def key_figure(bc, summary):
    """The README's figure: Fig. 14 and Fig. 15 of the paper side by side for one cycle."""
    import matplotlib.pyplot as plt

    from .. import plotting as P

    from ..summary import stiffness_at

    fig, (a, b) = plt.subplots(1, 2, figsize=(15, 6.6), layout="constrained")
    P.plot_stretched_cycles(bc, ax=a)
    P.plot_complex_stiffness([bc], ax=b, summaries=[summary])
    amps = P.default_amplitudes(bc)
    k_re, k_im = stiffness_at(bc, amps)
    colors = [line.get_color() for line in a.get_lines() if line.get_linestyle() == "-"][: len(amps)]
    # The first amplitude is psi_BC itself: its point is the psi_BC square already drawn (a diamond
    # on top of it would hide it), so only the stretched cycles get diamonds.
    for psi, kr, ki, c in list(zip(amps, k_re, k_im, colors))[1:]:
        b.plot([psi, psi], [kr, ki], "D", color=c, mec="k", ms=7)
    b.plot([], [], "D", color="w", mec="k", label="the stretched cycles on the left")
    b.legend(loc="upper right", fontsize=8)
    return fig


# Matplotlib's backends that draw off screen: pyplot may make figures in another thread only with
# these (a GUI backend's windows belong to the main thread).
OFF_SCREEN_BACKENDS = frozenset({"agg", "cairo", "pdf", "pgf", "ps", "svg", "template"})


def draws_off_screen() -> bool:
    """Whether matplotlib's backend draws off screen (OFF_SCREEN_BACKENDS)."""
    import matplotlib

    return matplotlib.get_backend().lower() in OFF_SCREEN_BACKENDS


def run_study(out: Path, shapes=DEFAULT_SHAPES, mus=DEFAULT_MU, kn=None, kt=None, progress=True,
              figures=True, runner=None, figure_processes: int | None = 0) -> dict:
    """Compute every shape x mu Base-Cycle; write study.json, tables, figures and the report into out.

    Returns the summary dict (the content of study.json). Inputs are checked before any work.
    The figures of the Base-Cycles are drawn while the bands, peaks and claim are computed where
    matplotlib draws off screen (Agg, the CLI's backend; OFF_SCREEN_BACKENDS), else after them:
    figure_processes 0 draws them on a thread of this process (the computing is mostly XLA, which
    leaves Python free), n > 0 in n worker processes (drawing is Python, which a thread shares
    with the computing; the workers start while the Base-Cycles compute), None one per core
    (`drawing.default_processes`). runner: as `compute_study`'s.
    """
    from tqdm import tqdm

    t0 = time.perf_counter()
    check_study_inputs(shapes, mus, kn, kt)
    if figure_processes is not None:
        check_int("figure_processes", figure_processes, 0)
    out = Path(out)
    n_fig = (6 * len(shapes) + 3 + ("60sym" in shapes and 0.7 in [float(m) for m in mus])) if figures else 0
    bar = tqdm(total=3 * len(shapes) * len(mus) + 2 + n_fig, desc="Base-Cycles", disable=not progress, unit="step")
    early = figures and draws_off_screen()
    processes = 0 if not early else (default_processes() if figure_processes is None
                                     else figure_processes)
    with contextlib.ExitStack() as stack:
        saver = stack.enter_context(FigureSaver(out / "figures", processes, bar)) if figures else None
        first = []

        def draw_cycles(cycles, summaries, q_star):
            first.extend(cycle_figure_jobs(cycles, summaries, [mu_key(m) for m in mus], float(q_star)))
            saver.submit(first)

        summary, cycles, summaries = compute_study(
            shapes, mus, kn, kt, bar, runner=runner,
            beside=(lambda c, s, load: draw_cycles(c, s, load.q_star)) if early else None)
        if figures:
            bar.set_description("Figures")
            if not early:
                draw_cycles(cycles, summaries, summary["load"]["q_star"])
            rest = summary_figure_jobs(cycles, summaries, summary)
            saver.submit(rest)
            saver.results()
            summary["figures"] = figure_entries(out / "figures", cycles, first + rest)
    bar.close()
    summary["meta"]["runtime_s"] = time.perf_counter() - t0
    write_study(out, summary)
    return summary


__all__ = ["study_figures", "study_figure_jobs", "cycle_figure_jobs", "summary_figure_jobs",
           "stretched_figure", "amplitude_data", "amplitude_stiffness_figure", "make_figures",
           "figure_entries", "key_figure", "run_study", "PSI_C_NOTE",
           "OFF_SCREEN_BACKENDS", "draws_off_screen"]
