"""`jaxdamp response`: blade forced response with the damper (amplitude-layered, first harmonic).

Peaks A* (every root, isolas included) at each force, the FRFs with the damper and of the free
and stuck blade (each across its own peak, with the peak reduction A*_free / A*), and with
--diagram the designer's diagram (peak against F and against F_D, mu band 0.3 ... 0.7). With
--modes FILE the blade row instead: the peak per engine order, each on its nodal diameter's mode
and platform path (docs/blade.md). With --ibpa / --motion (and --h-l) the one-mode blade's damper
runs on that platform path instead of the paper's in-phase motion (the curved-flat damper's exact
cycles on the path, docs/motions.md); --psi-per-mm is then the path parameter's mrad (for --ibpa
the left-hand blade's platform rotation) per mm of tip. --damper wedge computes a wedge (R1, R2 |
L1, L2; in-phase on the same path engine), its amplitude scale and status from the path's
gross-slip move. The
programs are saved as exports in the compilation cache folder (`cli.exported`): a second call
neither traces nor compiles them.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..params import check_param
from ..runtime import side_by_side
from ..response import (BladeMode, curves_program, designer_diagram, path_curves_program,
                        peak_band_unchecked, prepare_scene)
from ..status import RESULTS
from . import common as C
from . import motion_flags as M
from . import exported
from .response_row import add_row_args, check_row_args, run_row
from .uncertainty_report import add_uncertainty_args
from .uncertainty_report import report as uncertainty_report

STIFFNESS_NOTE = ("k(psi_a): with --stiffness exact (default) the steady travel-limited cycle at each "
                  "amplitude from the --initial history; with --stiffness interpolated the paper's "
                  "linear microslip interpolation between psi_fs and psi_BC (exact above psi_BC).")


def register(sub) -> None:
    m = BladeMode()
    p = sub.add_parser("response", help="blade forced response with the damper: peaks, FRFs, "
                       "designer's diagram", description=__doc__ + "\n" + STIFFNESS_NOTE)
    C.add_design_args(p, mu_default=0.5)
    C.add_damper_args(p)
    g = p.add_argument_group("blade mode (illustrative defaults, see jaxdamp.response.BladeMode)")
    g.add_argument("--f0-hz", type=float, default=m.f0_hz,
                   help=f"frequency with the platforms free, Hz, > 0 (default {m.f0_hz:g})")
    g.add_argument("--modal-stiffness-n-per-mm", type=float, default=m.k_b,
                   help=f"modal stiffness k_b, N/mm, > 0 (default {m.k_b:g})")
    g.add_argument("--loss-factor", type=float, default=m.eta,
                   help=f"structural loss factor eta, in [0, 1] (default {m.eta:g})")
    g.add_argument("--psi-per-mm", type=float, default=m.r,
                   help=f"platform rotation per tip displacement r, mrad/mm, > 0 (default {m.r:g})")
    p.add_argument("--force-n", default="5,20,50",
                   help="modal excitation forces F, N, comma-separated, each > 0 (default 5,20,50)")
    p.add_argument("--stiffness", default="exact", choices=("exact", "interpolated"),
                   help="damper curve k(psi_a): exact steady cycles (default) or the paper's "
                        "microslip interpolation")
    p.add_argument("--initial", default=None, choices=("gross_slip", "assembly"),
                   help="contact history of the exact curve (default gross_slip; with --modes, "
                        "--ibpa or --motion assembly)")
    p.add_argument("--band", action="store_true",
                   help="also the peak's bounds over every admissible contact history (in-phase: "
                        "the band of k(psi_a) tabulated on 24 amplitudes, about a minute; with "
                        "--modes: per engine order, each peak bracketed, minutes)")
    p.add_argument("--diagram", action="store_true",
                   help="also the designer's diagram (peak against F and F_D over mu 0.3 ... "
                        "0.7; with --modes the row's worst peak against F and F_D at --mu)")
    p.add_argument("--plot", metavar="DIR",
                   help="write frf.png (and designer_diagram.png with --diagram) to DIR")
    M.add_motion_args(p, parameter="psi_a (the path parameter, --psi-per-mm per mm of tip)",
                      h_l_extra="; with --modes at every nodal diameter but 0")
    add_row_args(p, with_h_l=False)
    add_uncertainty_args(p)
    C.add_progress_arg(p)
    C.add_json_arg(p)
    p.set_defaults(func=run)


def _forces(text):
    vals = list(C.float_list(str(text), "--force-n"))
    check_param("force_n", vals)
    return vals


_num = C.number
FORCE_BUCKET = 4  # forces are padded (runtime.padded_size) to a power of two, at least this


def _padded(forces):
    from ..runtime import padded_size

    n = padded_size(len(forces), FORCE_BUCKET)
    return jnp.asarray(forces + [forces[-1]] * (n - len(forces)), float)


def _branches(curve, i, valid=True):
    """One FRF's existing points as two branches (amplitude, frequency): no null where a number
    exists, and no point where none does."""
    a = np.asarray(curve.amplitude_mm[i])
    out = {}
    for name, f, has in (("low", curve.f_low_hz, curve.has_low), ("high", curve.f_high_hz,
                                                                    curve.has_high)):
        keep = np.asarray(has[i]) & valid
        out[name] = {"amplitude_mm": [_num(v) for v in a[keep]],
                     "frequency_hz": [_num(v) for v in np.asarray(f[i])[keep]]}
    return out


def _peak_entry(force, p, i):
    valid = bool(RESULTS.valid(p.status[i]))
    roots = [{"amplitude_mm": _num(a), "frequency_hz": _num(f)}
             for a, f, ok in zip(p.roots_mm[i], p.frequency_hz[i], p.found[i]) if bool(ok)]

    def value(v):
        return _num(v[i]) if valid else None

    return {"force_n": force, "peak_amplitude_mm": value(p.peak_amplitude_mm),
            "peak_frequency_hz": value(p.peak_frequency_hz), "psi_a_mrad": value(p.psi_a_mrad),
            "max_amplitude_mm": value(p.max_amplitude_mm), "status": RESULTS.name_of(p.status[i]),
            "roots": roots if valid else [], "isola": valid and len(roots) > 1}


def _diagram_json(dd):
    def rows(a):
        return [[_num(v) for v in row] for row in np.atleast_2d(a)]

    return {
        "mu": [float(m) for m in dd.mu], "status": [RESULTS.name_of(s) for s in dd.status],
        "force_n": [float(v) for v in dd.force_n], "peak_vs_force_mm": rows(dd.peak_vs_force_mm),
        "band_force_mm": rows(dd.band_force_mm), "free_vs_force_mm": rows(dd.free_vs_force_mm)[0],
        "stuck_vs_force_mm": rows(dd.stuck_vs_force_mm)[0],
        "fd_n": [float(v) for v in dd.fd_n], "force_at_fd_n": dd.force_at_fd_n,
        "peak_vs_fd_mm": rows(dd.peak_vs_fd_mm), "band_fd_mm": rows(dd.band_fd_mm),
        "free_vs_fd_mm": rows(dd.free_vs_fd_mm)[0], "stuck_vs_fd_mm": rows(dd.stuck_vs_fd_mm)[0],
        "stuck_frequency_hz": [_num(v) for v in dd.stuck_frequency_hz]}


class Computed(NamedTuple):
    """What `compute` returns: the curves (host numbers), the band's (highest, lowest) peaks or
    None, the designer's diagram or None, and the platform path (None: in-phase)."""

    curves: object
    band: tuple | None
    diagram: object
    motion: object = None


def prepare(args):
    """Every check before any work, once: (the Scene, the forces, the shape, contacts and load as
    the flags give them, for the echo, the platform path or None). The library checks each input
    once (`prepare_scene`); the compiled programs take the Scene as it is."""
    wedge = args.damper == "wedge"
    if wedge and args.modes is not None:
        raise C.CliError("--damper must be curved-flat with --modes (the row's damper); a wedge's "
                         "response on one path: --damper wedge with --ibpa / --motion, or in-phase")
    shape = C.shape_from_args(args, need_br=not wedge, check=False)
    shape = C.damper_from_args(args, shape)
    forces = _forces(args.force_n)
    mode = BladeMode(args.f0_hz, args.modal_stiffness_n_per_mm, args.loss_factor, args.psi_per_mm)
    contacts, load = C.contacts_from_args(args, check=False), C.load_from_args(args, check=False)
    motion = None if args.modes is not None else M.motion_from_args(args, load)
    if motion is not None or wedge:
        what = ("the paper's in-phase motion and curved-flat damper only; drop it, or --ibpa / "
                "--motion / --damper wedge")
        for flag, on in (("--band", args.band), ("--diagram", args.diagram),
                         ("--uncertainty", getattr(args, "uncertainty", False)),
                         ("--stiffness interpolated", args.stiffness != "exact")):
            if on:
                raise C.CliError(f"{flag} is computed for {what}")
    scene = prepare_scene(shape, args.mu, contacts, load, mode, wedge_ok=wedge)
    if wedge and motion is None:  # a wedge runs on the path engine, in-phase too
        from ..motion import in_phase_motion

        motion = in_phase_motion(float(load.q_star))
    return scene, forces, shape, contacts, load, motion


def compute(args, scene, forces, bar, motion=None) -> Computed:
    """The curves, and with --band and --diagram the band and the diagram, on the Scene; on a
    platform path (motion) the curves only."""
    if motion is not None:
        res = exported.call("response_path_curves", path_curves_program(args.initial),
                            (*scene, motion, _padded(forces)), repr(args.initial))
        bar.update(1)
        return Computed(jax.device_get(res), None, None, motion)
    options = {"initial": args.initial} if args.stiffness == "exact" else {}
    options_key = tuple(sorted(options.items()))
    variant = repr((args.stiffness, options_key))

    def curves():
        res = exported.call("response_curves", curves_program(args.stiffness, options_key),
                            (*scene, _padded(forces)), variant)
        # Numbers on the host once: indexing device arrays below would compile a small program
        # each.
        return jax.device_get(res)

    def peak_band():
        highest, lowest, _, _ = peak_band_unchecked(
            scene, jnp.asarray(forces), runner=exported.Runner("band_grid"))
        return highest, lowest

    # The band is independent of the curves and, on a first call, mostly XLA compiling its own
    # program: side by side, XLA compiles both on separate cores.
    if args.band:
        bar.set_description("peaks, FRFs and the band over histories")
    res, band = side_by_side(curves, peak_band) if args.band else (curves(), None)
    bar.update(2 if args.band else 1)
    dd = None
    if args.diagram and RESULTS.valid(res.status):
        bar.set_description("designer's diagram")
        # 21 levels per decade-spanning sweep: enough for a readable diagram at half the cost.
        dd = designer_diagram(scene, force_at_fd_n=float(np.median(forces)),
                              force_n=np.geomspace(0.05, 100.0, 21), fd_n=np.geomspace(
                                  float(args.fd) / 30.0, float(args.fd) * 30.0, 21),
                              method=args.stiffness, runner=exported.Runner(
                                  "designer_diagram", variant), **options)
        bar.update(1)
    return Computed(res, band, dd)


def _frf_json(res, forces, peaks):
    frf_json = {"forces": []}
    for i, force in enumerate(forces):
        valid = bool(RESULTS.valid(res.peaks.status[i]))
        # A*_free / A*: the free blade's peak F / (eta k_b) over the damped one.
        free_top, damped_top = np.max(res.free.amplitude_mm[i]), peaks[i]["peak_amplitude_mm"]
        frf_json["forces"].append({
            "force_n": force, "damper": _branches(res.damper, i, valid),
            "free": _branches(res.free, i), "stuck": _branches(res.stuck, i),
            "free_peak_amplitude_mm": _num(free_top),
            "peak_reduction": (_num(free_top / damped_top) if valid and damped_top else None)})
    return frf_json


def _band_json(peaks, band) -> None:
    highest, lowest = band
    for i, p in enumerate(peaks):
        ok = bool(RESULTS.valid(highest.status[i])) and bool(RESULTS.valid(lowest.status[i]))
        p["band"] = {"peak_amplitude_min_mm": _num(lowest.peak_amplitude_mm[i]) if ok else None,
                     "peak_amplitude_max_mm": _num(highest.peak_amplitude_mm[i]) if ok else None}


def _inputs_json(args, shape, forces, motion=None) -> dict:
    inputs = {"shape": shape._asdict(), "mu": args.mu, "kn": args.kn, "kt": args.kt,
              "fd": args.fd, "q": args.q, "r_sin_beta": args.r_sin_beta,
              "f0_hz": args.f0_hz, "modal_stiffness_n_per_mm": args.modal_stiffness_n_per_mm,
              "loss_factor": args.loss_factor, "psi_per_mm": args.psi_per_mm,
              "force_n": forces, "initial": args.initial, "band": bool(args.band),
              "diagram": bool(args.diagram),
              "stiffness_method": args.stiffness, "stiffness_note": STIFFNESS_NOTE,
              "motion": M.motion_echo(args, motion, "psi_a"), "damper": args.damper}
    inputs["shape"] = {k: (None if v is None else float(v)) for k, v in inputs["shape"].items()}
    return inputs


def to_json(args, out: Computed, forces, shape, contacts, load) -> dict:
    """The JSON document of a run (its "peaks" and "frf" are what `to_text` prints)."""
    res = out.curves
    peaks = [_peak_entry(f, res.peaks, i) for i, f in enumerate(forces)]
    frf_json = _frf_json(res, forces, peaks)
    if out.band is not None:
        _band_json(peaks, out.band)
    worst = max((RESULTS[p["status"]] for p in peaks), default=RESULTS.ok)
    status = RESULTS(int(worst)).name
    dd = out.diagram
    return C.document(status, {
        "inputs": _inputs_json(args, shape, forces, out.motion), "damper_status": RESULTS.name_of(res.status),
        "peaks": peaks, "frf": frf_json,
        "designer_diagram": None if dd is None else _diagram_json(dd)},
        reason=C.status_reason(status, contacts, load))


def write_plots(args, plot_dir, out: Computed, forces) -> None:
    """--plot: frf.png, and designer_diagram.png where the diagram was drawn."""
    from ..plotting.response import designer_diagram_figure, response_figure

    plot_dir.mkdir(parents=True, exist_ok=True)
    fig = response_figure(out.curves, forces)
    C.save_figure(fig, plot_dir / "frf.png", dpi=120)
    if out.diagram is not None:
        fig = designer_diagram_figure(out.diagram)
        C.save_figure(fig, plot_dir / "designer_diagram.png", dpi=120)


def to_text(args, doc: dict) -> str:
    """The text report of a run's document."""
    peaks, frf_json = doc["peaks"], doc["frf"]
    lines = [f"Blade response, mu = {args.mu:g}, F_D = {args.fd:g} N; f0 = {args.f0_hz:g} Hz, "
             f"k_b = {args.modal_stiffness_n_per_mm:g} N/mm, eta = {args.loss_factor:g}, "
             f"r = {args.psi_per_mm:g} mrad/mm",
             f"  platform motion: {M.motion_text(doc['inputs']['motion'])}",
             f"  damper stiffness: {args.stiffness}"
             + (f" (history: {args.initial})" if args.stiffness == "exact" else "")
             + f", status {doc['damper_status']}",
             f"  {'F, N':>8} {'A*, mm':>11} {'f*, Hz':>10} {'psi_a, mrad':>12} "
             f"{'A*_free/A*':>11}  status"]
    for p, e in zip(peaks, frf_json["forces"]):
        def fmt(v, spec):
            return format(v, spec) if v is not None else "-"
        lines.append(f"  {p['force_n']:8g} {fmt(p['peak_amplitude_mm'], '11.5g')} "
                     f"{fmt(p['peak_frequency_hz'], '10.4f')} {fmt(p['psi_a_mrad'], '12.5g')} "
                     f"{fmt(e['peak_reduction'], '11.4g')}  "
                     f"{p['status']}" + ("  (isola: roots " + ", ".join(
                         f"{r['amplitude_mm']:.4g}" for r in p["roots"]) + " mm)"
                         if p["isola"] else ""))
    if args.band:
        lines.append("  band over every admissible contact history (peak amplitude, mm):")
        for p in peaks:
            b = p.get("band") or {}
            lo, hi = b.get("peak_amplitude_min_mm"), b.get("peak_amplitude_max_mm")
            lines.append(f"  {p['force_n']:8g}  " + (f"{lo:.5g} .. {hi:.5g}" if lo is not None
                                                     and hi is not None else "- (no valid band)"))
    if args.plot:
        lines.append(f"  figures written to {args.plot}")
    return "\n".join(lines)


def run(args) -> int:
    check_row_args(args)
    if args.initial is None:
        on_path = args.modes is not None or args.ibpa is not None or args.motion is not None
        args.initial = "assembly" if on_path else "gross_slip"
    scene, forces, shape, contacts, load, motion = prepare(args)
    if args.modes is not None:
        return run_row(args, scene, forces, shape, contacts, load)
    plot_dir = None if args.plot is None else C.check_output_dir("--plot", args.plot)
    if args.uncertainty:  # the Monte Carlo peak distribution instead of one design's peaks
        return uncertainty_report(args, scene, forces)

    stages = 1 + bool(args.band) + bool(args.diagram)
    bar = C.progress_bar(args, total=stages, desc="peaks and FRFs", unit="stage")
    out = compute(args, scene, forces, bar, motion)
    bar.close()
    doc = to_json(args, out, forces, shape, contacts, load)
    if args.plot:
        write_plots(args, plot_dir, out, forces)
    C.emit(args, doc, to_text(args, doc))
    return 0


__all__ = ["STIFFNESS_NOTE", "register", "FORCE_BUCKET", "Computed", "prepare", "compute",
           "to_json", "write_plots", "to_text", "run"]
