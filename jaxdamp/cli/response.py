"""`jaxdamp response`: blade forced response with the damper (amplitude-layered, first harmonic).

Peaks A* (every root, isolas included) at each force, the FRFs with the damper, free and stuck,
and the designer's diagram (peak against F and against F_D, mu band 0.3 ... 0.7).
"""

from __future__ import annotations

from . import common as C
from .uncertainty_report import add_uncertainty_args
from .uncertainty_report import report as uncertainty_report

STIFFNESS_NOTE = ("k(psi_a): with --stiffness exact (default) the steady travel-limited cycle at each "
                  "amplitude from the --initial history; with --stiffness interpolated the paper's "
                  "linear microslip interpolation between psi_fs and psi_BC (exact above psi_BC).")


def register(sub) -> None:
    from ..response import BladeMode

    m = BladeMode()
    p = sub.add_parser("response", help="blade forced response with the damper: peaks, FRFs, "
                       "designer's diagram", description=__doc__ + "\n" + STIFFNESS_NOTE)
    C.add_design_args(p, mu_default=0.5)
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
    p.add_argument("--initial", default="gross_slip", choices=("gross_slip", "assembly"),
                   help="contact history of the exact curve (default gross_slip)")
    p.add_argument("--band", action="store_true",
                   help="also the peak's bounds over every admissible contact history (the band "
                        "of k(psi_a) tabulated on 24 amplitudes; about a minute)")
    p.add_argument("--plot", metavar="DIR", help="write frf.png and designer_diagram.png to DIR")
    add_uncertainty_args(p)
    C.add_progress_arg(p)
    C.add_json_arg(p)
    p.set_defaults(func=run)


def _forces(text):
    from .._validate import check_positive

    vals = list(C.float_list(str(text), "--force-n"))
    check_positive("force_n", vals, unit="N")
    return vals


_num = C.number


def _masked(values, mask):
    return [_num(v) if bool(m) else None for v, m in zip(values, mask)]


def run(args) -> int:
    import jax.numpy as jnp
    import numpy as np

    from ..params import prepare_inputs
    from ..response import (BladeMode, designer_diagram, frf, frf_amplitude_grid, no_damper,
                            stuck_damper, validate_mode)
    from ..status import RESULTS

    # Every check before any work.
    shape = C.shape_from_args(args)
    forces = _forces(args.force_n)
    mode = BladeMode(args.f0_hz, args.modal_stiffness_n_per_mm, args.loss_factor, args.psi_per_mm)
    validate_mode(mode)
    contacts, load = C.contacts_from_args(args), C.load_from_args(args)
    prepare_inputs(shape, args.mu, contacts, load)
    plot_dir = None if args.plot is None else C.check_output_dir("--plot", args.plot)
    options = {"initial": args.initial} if args.stiffness == "exact" else {}
    if args.uncertainty:  # the Monte Carlo peak distribution instead of one design's peaks
        return uncertainty_report(args, shape, forces, mode, contacts, load)

    import jax

    from ..response import damper_stiffness, peak_response

    @jax.jit
    def solve(force):
        d = damper_stiffness(shape, args.mu, contacts, load, args.stiffness, **options)
        return peak_response(d, mode, force), d.k_re_stuck, d.status

    @jax.jit
    def curves(force, top):
        d = damper_stiffness(shape, args.mu, contacts, load, args.stiffness, **options)
        grid = frf_amplitude_grid(top)
        stuck = stuck_damper(d.k_re_stuck)
        return (frf(d, mode, force, grid), frf(no_damper(), mode, force, grid),
                frf(stuck, mode, force, grid))

    peaks, frfs = [], []
    damper_status = RESULTS.ok
    bar = C.progress_bar(args, total=len(forces) + 1, desc="response", unit="step")
    for force in forces:
        bar.update(1)
        p, k_stuck, dstat = solve(jnp.asarray(force))
        damper_status = int(dstat)
        valid = bool(RESULTS.valid(p.status))
        roots = [{"amplitude_mm": _num(a), "frequency_hz": _num(f)}
                 for a, f, ok in zip(p.roots_mm, p.frequency_hz, p.found) if bool(ok)]
        peaks.append({
            "force_n": force,
            "peak_amplitude_mm": _num(p.peak_amplitude_mm) if valid else None,
            "peak_frequency_hz": _num(p.peak_frequency_hz) if valid else None,
            "psi_a_mrad": _num(p.psi_a_mrad) if valid else None,
            "max_amplitude_mm": _num(p.max_amplitude_mm) if valid else None,
            "status": RESULTS.name_of(p.status), "roots": roots if valid else [],
            "isola": valid and len(roots) > 1})
        top = float(p.max_amplitude_mm) if valid else force / (float(mode.eta) * float(mode.k_b))
        frfs.append((force, valid, curves(jnp.asarray(force), jnp.asarray(top))))

    frf_json = {"forces": []}
    for force, valid, (c, free, stuck) in frfs:
        entry = {"force_n": force}
        for name, cur in (("damper", c), ("free", free), ("stuck", stuck)):
            ok = valid or name != "damper"
            entry[name] = {"amplitude_mm": [_num(v) for v in np.asarray(cur.amplitude_mm)],
                           "f_low_hz": _masked(cur.f_low_hz, cur.has_low & ok),
                           "f_high_hz": _masked(cur.f_high_hz, cur.has_high & ok)}
        frf_json["forces"].append(entry)

    if args.band:
        from ..response import peak_band

        bar.set_description("band over histories")
        highest, lowest, _, _ = peak_band(shape, args.mu, contacts, load, mode,
                                          jnp.asarray(forces))
        for i, p in enumerate(peaks):
            ok = bool(RESULTS.valid(highest.status[i])) and bool(RESULTS.valid(lowest.status[i]))
            p["band"] = {"peak_amplitude_min_mm": _num(lowest.peak_amplitude_mm[i]) if ok else None,
                         "peak_amplitude_max_mm": _num(highest.peak_amplitude_mm[i]) if ok else None}

    dd = None
    bar.set_description("designer's diagram")
    if RESULTS.valid(damper_status):
        # 21 levels per decade-spanning sweep: enough for a readable diagram at half the cost.
        dd = designer_diagram(shape, mode, contacts, load, force_at_fd_n=float(np.median(forces)),
                              force_n=np.geomspace(0.05, 100.0, 21), fd_n=np.geomspace(
                                  float(load.F_D) / 30.0, float(load.F_D) * 30.0, 21),
                              method=args.stiffness, **options)
    bar.update(1)
    bar.close()

    def rows(a):
        return [[_num(v) for v in row] for row in np.atleast_2d(a)]

    dd_json = None if dd is None else {
        "mu": [float(m) for m in dd.mu], "status": [RESULTS.name_of(s) for s in dd.status],
        "force_n": [float(v) for v in dd.force_n], "peak_vs_force_mm": rows(dd.peak_vs_force_mm),
        "band_force_mm": rows(dd.band_force_mm), "free_vs_force_mm": rows(dd.free_vs_force_mm)[0],
        "stuck_vs_force_mm": rows(dd.stuck_vs_force_mm)[0],
        "fd_n": [float(v) for v in dd.fd_n], "force_at_fd_n": dd.force_at_fd_n,
        "peak_vs_fd_mm": rows(dd.peak_vs_fd_mm), "band_fd_mm": rows(dd.band_fd_mm),
        "free_vs_fd_mm": rows(dd.free_vs_fd_mm)[0], "stuck_vs_fd_mm": rows(dd.stuck_vs_fd_mm)[0],
        "stuck_frequency_hz": [_num(v) for v in dd.stuck_frequency_hz]}

    worst = max((RESULTS[p["status"]] for p in peaks), default=RESULTS.ok)
    inputs = {"shape": shape._asdict(), "mu": args.mu, "kn": args.kn, "kt": args.kt,
              "fd": args.fd, "q": args.q, "r_sin_beta": args.r_sin_beta,
              "f0_hz": args.f0_hz, "modal_stiffness_n_per_mm": args.modal_stiffness_n_per_mm,
              "loss_factor": args.loss_factor, "psi_per_mm": args.psi_per_mm,
              "force_n": forces, "initial": args.initial, "band": bool(args.band),
              "stiffness_method": args.stiffness, "stiffness_note": STIFFNESS_NOTE}
    inputs["shape"] = {k: (None if v is None else float(v)) for k, v in inputs["shape"].items()}
    doc = C.document(RESULTS(int(worst)).name, {"inputs": inputs, "peaks": peaks, "frf": frf_json,
                                                "designer_diagram": dd_json})

    if args.plot:
        from ..plotting.response import designer_diagram_figure, frf_figure

        plot_dir.mkdir(parents=True, exist_ok=True)
        ok = [(f, cs) for f, v, cs in frfs if v]
        if ok:
            fig = frf_figure([cs[0] for _, cs in ok], [f for f, _ in ok],
                             [cs[1] for _, cs in ok], [cs[2] for _, cs in ok])
            fig.savefig(plot_dir / "frf.png", dpi=120)
        if dd is not None:
            fig = designer_diagram_figure(dd)
            fig.savefig(plot_dir / "designer_diagram.png", dpi=120)

    lines = [f"Blade response, mu = {args.mu:g}, F_D = {args.fd:g} N; f0 = {args.f0_hz:g} Hz, "
             f"k_b = {args.modal_stiffness_n_per_mm:g} N/mm, eta = {args.loss_factor:g}, "
             f"r = {args.psi_per_mm:g} mrad/mm",
             f"  damper stiffness: {args.stiffness}"
             + (f" (history: {args.initial})" if args.stiffness == "exact" else ""),
             f"  {'F, N':>8} {'A*, mm':>11} {'f*, Hz':>10} {'psi_a, mrad':>12}  status"]
    for p in peaks:
        def fmt(v, spec):
            return format(v, spec) if v is not None else "-"
        lines.append(f"  {p['force_n']:8g} {fmt(p['peak_amplitude_mm'], '11.5g')} "
                     f"{fmt(p['peak_frequency_hz'], '10.4f')} {fmt(p['psi_a_mrad'], '12.5g')}  "
                     f"{p['status']}" + ("  (isola: roots " + ", ".join(
                         f"{r['amplitude_mm']:.4g}" for r in p["roots"]) + " mm)"
                         if p["isola"] else ""))
    if args.plot:
        lines.append(f"  figures written to {args.plot}")
    C.emit(args, doc, "\n".join(lines))
    return 0

