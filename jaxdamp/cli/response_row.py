"""`jaxdamp response --modes FILE`: the forced response across a blade row from modal data.

Per engine order, the nodal diameter it excites, that diameter's one-mode blade and the damper's
platform path (straight at nodal diameters 0 and N/2, an ellipse between), and the peak tip
response with and without the damper (`jaxdamp.row_response`). A table, the worst engine order
per force, JSON with --json and the figure row.png with --plot. With --diagram the row's
designer's diagram (`jaxdamp.row_diagram`): the worst peak over the row against the force
(DIAGRAM_FORCES_N) and against F_D (DIAGRAM_FD_FACTORS times --fd, at the median of --force-n),
row_diagram.png with --plot.
"""

from __future__ import annotations

import numpy as np

from ..conventions import SMALL_ROTATION_MRAD
from ..response import BladeMode, row_band, row_diagram, row_response
from ..response.row import engine_orders_of
from ..response.row_band import check_band_family
from ..status import RESULTS
from . import common as C
from . import exported

__all__ = ["add_row_args", "check_row_args", "run_row"]

# Flags of the one-mode blade that a modal file replaces: argument name -> (flag, BladeMode field
# whose default the flag has).
_MODE_FLAGS = {"f0_hz": ("--f0-hz", "f0_hz"),
               "modal_stiffness_n_per_mm": ("--modal-stiffness-n-per-mm", "k_b"),
               "loss_factor": ("--loss-factor", "eta"), "psi_per_mm": ("--psi-per-mm", "r")}


def add_row_args(p, with_h_l: bool = True) -> None:
    """--modes and --engine-order, and --h-l unless the command has it already (`response`
    takes it with the platform path's flags, `cli.motion_flags`)."""
    g = p.add_argument_group("blade row from modal data (docs/blade.md)")
    g.add_argument("--modes", metavar="FILE",
                   help="modal file (.npz or .json) of one mode family per nodal diameter: the "
                        "response per engine order replaces the one-mode blade's")
    g.add_argument("--engine-order", default="all", metavar="SPEC",
                   help="engine orders with --modes: a:b (inclusive), a,b,c or all (every nodal "
                        "diameter 0 ... N/2 once; default)")
    if with_h_l:
        g.add_argument("--h-l", type=float, default=None, metavar="MM",
                       help="with --modes: the damper's size, its left flank's length in mm, in "
                            "(0, 10000] (the platforms turn relative to each other at every nodal "
                            "diameter but 0)")


# The row diagram's grids: 13 forces over 2.5 decades and 13 F_D factors over a factor 16 (one row
# of peaks on the 26 forces they need, padded to 32).
DIAGRAM_FORCES_N = np.geomspace(0.2, 50.0, 13)
DIAGRAM_FD_FACTORS = np.geomspace(0.25, 4.0, 13)


def check_row_args(args) -> None:
    """Argument combinations, before any work (CliError: one line, exit 2)."""
    if args.modes is None:
        if args.engine_order != "all":
            raise C.CliError("--engine-order needs --modes FILE (the blade row)")
        return
    for flag, given in (("--ibpa", args.ibpa), ("--h-c", args.h_c), ("--motion", args.motion)):
        if given is not None:
            raise C.CliError(f"{flag} gives one platform path; with --modes the modal file gives "
                             "each engine order's: drop it")
    for flag, on in (("--uncertainty", getattr(args, "uncertainty", False)),):
        if on:
            raise C.CliError(f"{flag} is not available with --modes yet (one design's response "
                             f"only); leave it out")
    if args.stiffness != "exact":
        raise C.CliError("--stiffness interpolated is the paper's in-phase curve; with --modes "
                         "every engine order runs the exact cycle on its own path")
    default = BladeMode()
    for name, (flag, field) in _MODE_FLAGS.items():
        if getattr(args, name) != getattr(default, field):
            raise C.CliError(f"{flag} describes the one-mode blade; with --modes the modal file "
                             f"gives each nodal diameter's")
    if args.h_l is None:
        raise C.CliError("--h-l must be given with --modes: the damper's left flank length in "
                         "(0, 10000] mm")


def _band_entry(band, i, j) -> dict:
    ok = bool(RESULTS.has_numbers(band.status[i, j]))
    return {"peak_amplitude_min_mm": C.number(band.peak_min_mm[i, j]) if ok else None,
            "peak_amplitude_max_mm": C.number(band.peak_max_mm[i, j]) if ok else None,
            "resolution": C.number(float(np.max(band.resolution[i, j]))),
            "status": RESULTS.name_of(band.status[i, j])}


def _row_json(res, band=None) -> list:
    rows = []
    for i, e in enumerate(res.engine_order):
        per_force = []
        for j, force in enumerate(res.force_n):
            ok = bool(RESULTS.has_numbers(res.status[i, j]))
            amp = float(res.peaks.peak_amplitude_mm[i, j])
            free = float(res.free_peak_mm[i, j])
            per_force.append({
                "force_n": float(force), "tip_force_n": C.number(res.tip_force_n[i, j]),
                "peak_amplitude_mm": C.number(amp) if ok else None,
                "peak_frequency_hz": C.number(res.peaks.peak_frequency_hz[i, j]) if ok else None,
                "psi_a_mrad": C.number(res.peaks.psi_a_mrad[i, j]) if ok else None,
                "rotation_mrad": C.number(res.rotation_mrad[i, j]) if ok else None,
                "free_peak_amplitude_mm": C.number(free) if np.isfinite(free) else None,
                "peak_reduction": C.number(free / amp) if ok and amp > 0 and np.isfinite(free)
                else None,
                "status": RESULTS.name_of(res.status[i, j])})
            if band is not None:
                per_force[-1]["band"] = _band_entry(band, i, j)
        rows.append({"engine_order": int(e), "nodal_diameter": int(res.nodal_diameter[i]),
                     "ibpa_deg": C.number(res.ibpa_deg[i]),
                     "path": "elliptic" if res.elliptic[i] else "straight",
                     "frequency_hz": C.number(res.frequency_hz[i]),
                     "residual_mrad_per_nmm": C.number(res.residual_mrad_per_nmm[i]),
                     "forces": per_force})
    return rows


def _worst_json(res, band=None) -> list:
    out = []
    for j, force in enumerate(res.force_n):
        w = int(res.worst[j])
        out.append({"force_n": float(force),
                    "engine_order": int(res.engine_order[w]) if w >= 0 else None,
                    "nodal_diameter": int(res.nodal_diameter[w]) if w >= 0 else None,
                    "peak_amplitude_mm": C.number(res.peaks.peak_amplitude_mm[w, j])
                    if w >= 0 else None})
        if band is not None:
            valid = np.asarray(RESULTS.valid(band.status[:, j]))
            b = (int(np.argmax(np.where(valid, band.peak_max_mm[:, j], -np.inf))) if valid.any()
                 else -1)
            out[-1]["band"] = {"engine_order": int(band.engine_order[b]) if b >= 0 else None,
                               "nodal_diameter": int(band.nodal_diameter[b]) if b >= 0 else None,
                               "peak_amplitude_max_mm": C.number(band.peak_max_mm[b, j])
                               if b >= 0 else None}
    return out


def _diagram_json(dd) -> dict:
    def curve(x, worst, orders, status):
        return [{"x": float(v), "worst_mm_per_n": C.number(w) if np.isfinite(w) else None,
                 "engine_order": int(e) if e >= 0 else None, "status": RESULTS.name_of(s)}
                for v, w, e, s in zip(x, worst, orders, status)]

    return {"note": "the worst A*/F over the engine orders whose peak is valid; status: the most "
                    "severe over the row (large_rotation: a peak beyond the small-rotation model)",
            "vs_force": curve(dd.force_n, dd.worst_vs_force_mm_per_n, dd.engine_order_vs_force,
                              dd.status_vs_force),
            "force_at_fd_n": dd.force_at_fd_n,
            "vs_fd_factor": curve(dd.fd_factor, dd.worst_vs_fd_mm_per_n, dd.engine_order_vs_fd,
                                  dd.status_vs_fd)}


def _diagram_text(d: dict) -> str:
    lines = ["  the row's designer's diagram: worst A*/F over the row (mm/N), its engine order"]
    for key, label in (("vs_force", "F, N"), ("vs_fd_factor", "F_D/F_D0")):
        if key == "vs_fd_factor":
            lines.append(f"  against F_D at F = {d['force_at_fd_n']:g} N:")
        lines.append(f"  {label:>9} {'A*/F':>9} {'EO':>3}  status")
        for p in d[key]:
            w = "-" if p["worst_mm_per_n"] is None else f"{p['worst_mm_per_n']:9.4g}"
            e = "-" if p["engine_order"] is None else str(p["engine_order"])
            lines.append(f"  {p['x']:9.3g} {w:>9} {e:>3}  {p['status']}")
    return "\n".join(lines)


def _text(args, res, family, rows, worst) -> str:
    lines = [f"Blade row {family.name or args.modes}: {family.n_blades} blades, mu = {args.mu:g}, "
             f"F_D = {args.fd:g} N, h_L = {args.h_l:g} mm, history {res.initial}",
             f"  {'EO':>3} {'ND':>3} {'IBPA,deg':>8} {'path':>8} {'f0, Hz':>9} {'F, N':>7} "
             f"{'A*, mm':>10} {'f*, Hz':>10} {'rot, mrad':>10} {'A*free, mm':>11} "
             f"{'free/A*':>8}  status"]

    def fmt(v, spec):
        return format(v, spec) if v is not None else "-"

    for r in rows:
        for p in r["forces"]:
            lines.append(f"  {r['engine_order']:3d} {r['nodal_diameter']:3d} "
                         f"{r['ibpa_deg']:8.1f} {r['path']:>8} {r['frequency_hz']:9.2f} "
                         f"{p['force_n']:7g} {fmt(p['peak_amplitude_mm'], '10.5g')} "
                         f"{fmt(p['peak_frequency_hz'], '10.3f')} "
                         f"{fmt(p['rotation_mrad'], '10.4g')} "
                         f"{fmt(p['free_peak_amplitude_mm'], '11.5g')} "
                         f"{fmt(p['peak_reduction'], '8.3g')}  {p['status']}")
    beyond = sum(p["status"] == RESULTS.large_rotation.name for r in rows for p in r["forces"])
    if beyond:
        lines.append(f"  {beyond} of {sum(len(r['forces']) for r in rows)} peaks are "
                     f"large_rotation: the platforms turn (rot) beyond the small-rotation "
                     f"model's {SMALL_ROTATION_MRAD:g} mrad, outside its validity (a smaller "
                     f"--force-n or a larger --fd keeps them inside)")
    if args.band:
        lines.append("  band over every admissible contact history (peak amplitude, mm):")
        lines.append(f"  {'EO':>3} {'ND':>3} {'F, N':>7} {'A* min':>10} {'A* max':>10}  status")
        for r in rows:
            for p in r["forces"]:
                b = p["band"]
                lines.append(f"  {r['engine_order']:3d} {r['nodal_diameter']:3d} "
                             f"{p['force_n']:7g} {fmt(b['peak_amplitude_min_mm'], '10.5g')} "
                             f"{fmt(b['peak_amplitude_max_mm'], '10.5g')}  {b['status']}")
    for w in worst:
        lines.append(f"  worst at F = {w['force_n']:g} N: " + (
            f"engine order {w['engine_order']} (nodal diameter {w['nodal_diameter']}), A* = "
            f"{w['peak_amplitude_mm']:.5g} mm" if w["engine_order"] is not None
            else "no valid peak"))
        b = w.get("band")
        if b is not None:
            lines.append("    over every history: " + (
                f"engine order {b['engine_order']} (nodal diameter {b['nodal_diameter']}), A* up "
                f"to {b['peak_amplitude_max_mm']:.5g} mm" if b["engine_order"] is not None
                else "no valid band"))
    if args.plot:
        lines.append(f"  figure written to {args.plot}/row.png")
    return "\n".join(lines)


def run_row(args, scene, forces, shape, contacts, load) -> int:
    """The row run: the modal file and engine orders read and checked, then one or two compiled
    programs (straight and elliptic paths)."""
    from ..modal_file import load_modal_family

    plot_dir = None if args.plot is None else C.check_output_dir("--plot", args.plot)
    family = load_modal_family(args.modes)
    orders = engine_orders_of(args.engine_order, family.n_blades)
    if args.band:
        check_band_family(family, orders)
    bar = C.progress_bar(args, total=1 + bool(args.band) + bool(args.diagram), desc="peaks per engine order",
                         unit="stage")
    design = (scene.shape, scene.mu, scene.contacts, scene.load)
    res = row_response(*design, modes=family, engine_orders=orders, force_n=forces,
                       h_l_mm=args.h_l, initial=args.initial, runner=exported.Runner(
                           "row_peaks", args.initial))
    bar.update(1)
    band = None
    if args.band:
        bar.set_description("band over histories")
        band = row_band(*design, modes=family, engine_orders=orders, force_n=forces,
                        h_l_mm=args.h_l, runner=exported.Runner("row_band"))
        bar.update(1)
    diagram = None
    if args.diagram:
        bar.set_description("designer's diagram")
        diagram = row_diagram(*design, modes=family, engine_orders=orders, h_l_mm=args.h_l,
                              force_n=DIAGRAM_FORCES_N, fd_factor=DIAGRAM_FD_FACTORS,
                              force_at_fd_n=float(np.median(forces)), initial=args.initial,
                              runner=exported.Runner("row_peaks", args.initial))
        bar.update(1)
    bar.close()
    rows, worst = _row_json(res, band), _worst_json(res, band)
    statuses = [RESULTS[p["status"]] for r in rows for p in r["forces"]]
    statuses += [RESULTS[p["band"]["status"]] for r in rows for p in r["forces"] if "band" in p]
    # The document's status: the most severe of its peaks' (jaxdamp.status.SEVERITY).
    status = RESULTS(int(RESULTS.worst(statuses))).name if statuses else RESULTS.ok.name
    doc = C.document(status, {
        "inputs": {"shape": C.shape_echo(shape), "mu": args.mu, "contacts": C.contacts_echo(contacts),
                   "load": C.load_echo(load), "modes_file": str(args.modes),
                   "family": family.name, "n_blades": family.n_blades, "h_l_mm": args.h_l,
                   "engine_orders": orders, "force_n": list(forces), "initial": res.initial,
                   "band": bool(args.band),
                   "band_samples": None if band is None else band.n_samples},
        "engine_orders": rows, "worst": worst,
        **({} if diagram is None else {"diagram": _diagram_json(diagram)})},
        reason=C.status_reason(status, contacts, load))
    if plot_dir is not None:
        from ..plotting.response import row_figure

        shaded = "; shaded: every history" if band is not None else ""
        C.save_figure(row_figure(res, band=band, title=f"{family.name or 'blade row'}: peak "
                                 f"response per engine order ({res.initial} history{shaded})"),
                      plot_dir / "row.png", dpi=120)
        if diagram is not None:
            from ..plotting.response import row_diagram_figure

            C.save_figure(row_diagram_figure(diagram, title=f"{family.name or 'blade row'}: the "
                                             f"row's designer's diagram (mu {args.mu:g}, "
                                             f"{res.initial} history)"),
                          plot_dir / "row_diagram.png", dpi=120)
    text = _text(args, res, family, rows, worst)
    if diagram is not None:
        text += "\n" + _diagram_text(doc["diagram"])
    C.emit(args, doc, text)
    return 0
