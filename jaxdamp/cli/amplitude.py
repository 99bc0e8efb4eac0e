"""`jaxdamp amplitude`: the exact steady cycle at prescribed platform rotation amplitudes.

    jaxdamp amplitude --shape 60sym --mu 0.5 --psi-a 0.5,1.2,3 [--initial assembly] [--band] [--json]
    jaxdamp amplitude --shape 60sym --mu 0.5 --psi-a 5,10,20 --ibpa 180 --h-c 20 --h-l 10
    jaxdamp amplitude --shape 60sym --mu 0.5 --psi-a 5 --motion 0.03,0.05,1.5 --h-l 12

Beyond the paper's in-phase motion: `--ibpa DEG` is a travelling wave with interblade phase angle
DEG (each platform turns about its blade's centre, --h-c mm below D; --psi-a is then the left-hand
blade's platform rotation; 180 is out-of-phase, a straight path, any other angle but 0 an
ellipse), `--motion du,dv,dtheta` any path (mm, mm, mrad per mrad of --psi-a; complex entries as
re+imj: an ellipse unless real up to one common phase). Both need the damper's size --h-l (its
left flank's length, mm) where the platforms turn; k is then that of the modal force
(jaxdamp.motion), and each row adds energy_nmm, slip_fraction and open_fraction per pad (zero on
a straight path, whose pads stay closed), dissipated_energy_nmm, tracts (the contact-state chart,
jaxdamp.transitions_chart; on an ellipse tau_start_deg, tau_end_deg and each pad's state, whose
open intervals the text lists), and with --h-l force_harmonic: the first harmonic of the damper's
generalised force on the right platform, {"F_u_n", "F_v_n", "M_nmm"} each {"re", "im"}
(jaxdamp.platform_force). On an ellipse the default history is assembly; its gross slip is a straight
move along the path's tau = 0 direction until every pad slips (docs/motions.md).

k_Re, k_Im in N mm/mrad (the Base-Cycle's sign and units), psi_a in mrad. JSON:
{"inputs": {...}, "status": .., "amplitudes": [{"psi_a_mrad", "k_re", "k_im", "status", "cycles",
"band": {"k_re_min", "k_re_max", "k_im_min", "k_im_max"}}]}; `band` only with --band; numbers that
are undefined (no valid cycle) are null.
"""

from __future__ import annotations

from . import common as C
from . import exported
from . import motion_flags as M


def register(sub) -> None:
    p = sub.add_parser("amplitude", help="exact steady cycles at prescribed amplitudes psi_a "
                       "(microslip included), from a named initial state; optionally the band")
    C.add_design_args(p)
    C.add_damper_args(p)
    p.add_argument("--psi-a", required=True,
                   help="platform rotation amplitudes, mrad, comma-separated, each in (0, 10000]")
    p.add_argument("--initial", default=None,
                   help="initial contact state: gross_slip (default) or assembly (the default on an "
                   "elliptic path)")
    p.add_argument("--band", action="store_true",
                   help="also the min/max of k_Re, k_Im over all statically admissible initial states "
                   "(in-phase motion only)")
    M.add_motion_args(p)
    C.add_progress_arg(p)
    C.add_json_arg(p)
    p.set_defaults(func=run)


def _amplitudes(text: str) -> list[float]:
    from .._validate import check_range

    values = list(C.float_list(text, "--psi-a", example="0.5,1.2,3"))
    check_range("--psi-a", values, 0.0, 1e4, lo_open=True, unit="mrad")
    return values


def _merged(spans):
    """Adjacent (start, end) intervals joined: a pad open over several tracts is one interval."""
    out = []
    for a, b in spans:
        if out and abs(out[-1][1] - a) < 1e-9:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def run(args) -> int:
    import numpy as np

    from ..amplitude import INITIAL_STATES, amplitude_cycle, slip_fraction
    from ..ellipse import elliptic_cycle
    from ..geometry import is_wedge, pad_names
    from ..motion import in_phase_motion
    from ..params import prepare_inputs
    from ..platform_force import PLATFORM_FORCE_NAMES, platform_force_harmonic
    from ..status import RESULTS

    # Every input is checked before any work (ValueError / CliError -> one line, exit code 2).
    contacts, load = C.contacts_from_args(args), C.load_from_args(args)  # --mu resolved here too
    psis = _amplitudes(args.psi_a)
    wedge = args.damper == "wedge"
    shape = C.damper_from_args(args, C.shape_from_args(args, need_br=not wedge))
    prepare_inputs(shape, args.mu, contacts, load, wedge_ok=wedge)
    motion = M.motion_from_args(args, load)
    if wedge and args.band:
        raise C.CliError("--band is computed for the curved-flat damper only; drop --band or "
                         "--damper wedge")
    if wedge and motion is None:
        motion = in_phase_motion(load.q_star)  # a wedge runs on the path engine, in-phase too
    # Ellipses, and a wedge on any path (a straight one as an ellipse of zero width), run the
    # engine with pads that open; the curved-flat damper's straight paths the paper's model
    # (amplitude_cycle: the engine with pads that may not open).
    elliptic = motion is not None and (motion.quadrature is not None or is_wedge(shape))
    if args.initial is None:
        args.initial = "assembly" if elliptic else "gross_slip"
    if args.initial not in INITIAL_STATES:
        raise ValueError(f"--initial must be one of {', '.join(INITIAL_STATES)}; got {args.initial!r}")
    if motion is not None and args.band:
        raise C.CliError("--band is computed for the paper's in-phase motion only; drop --ibpa / --motion")

    rows, warned = [], []
    bar = C.progress_bar(args, total=len(psis), desc="amplitudes", unit="amplitude")
    for psi in psis:
        with C.model_warnings() as caught:  # an amplitude above the small-rotation limit
            if elliptic:
                ac = elliptic_cycle(shape, args.mu, psi, motion, contacts, load, initial=args.initial)
            else:
                # A saved program (exported.call): a later process, or a first one with the
                # program shipped in the package, neither traces nor lowers it.
                ac = amplitude_cycle(shape, args.mu, psi, contacts, load, initial=args.initial,
                                     motion=motion, runner=exported.Runner(
                                         "amplitude", str(args.initial)))
        warned.extend(m for m in caught if m not in warned)
        valid = bool(RESULTS.valid(ac.status))
        row = {"psi_a_mrad": psi, "k_re": C.number(ac.k_re) if valid else None,
               "k_im": C.number(ac.k_im) if valid else None,
               "status": RESULTS.name_of(ac.status),
               "cycles": int(ac.periods if elliptic else ac.cycles)}
        if motion is not None:
            row.update(M.pad_fields(shape, ac, valid, None if elliptic else slip_fraction(ac)))
            if args.h_l is not None:  # the moment about D needs the damper's size
                g = np.asarray(platform_force_harmonic(ac, args.h_l))
                row["force_harmonic"] = {name: {"re": C.number(v.real), "im": C.number(v.imag)}
                                         if valid else None
                                         for name, v in zip(PLATFORM_FORCE_NAMES, g)}
        if args.band:
            from ..band import amplitude_band

            row["band"] = amplitude_band(shape, args.mu, psi, contacts, load).as_dict()
        rows.append(row)
        bar.update(1)
    bar.close()
    bad = [r["status"] for r in rows if r["status"] not in ("ok", "shakedown")]
    inputs = {"shape": args.shape and C.shape_name(args.shape), "damper": args.damper,
              "pads": list(pad_names(shape)), "theta_l": float(shape.theta_l),
              "theta_r": float(shape.theta_r),
              "br_over_hr": None if wedge else float(shape.br_over_hr),
              "br2_over_hr": float(shape.br2_over_hr) if wedge else None,
              "bl2_over_hl": float(shape.bl2_over_hl), "x_d": shape.x_d,
              "mu": args.mu, "kn": args.kn, "kt": args.kt, "F_D": args.fd, "q_star": args.q,
              "r_sin_beta": args.r_sin_beta, "psi_a_mrad": psis, "initial": args.initial,
              "band": bool(args.band), "motion": M.motion_echo(args, motion)}
    status = bad[0] if bad else "ok"
    doc = C.document(status, {"inputs": inputs, "amplitudes": rows, "warnings": warned},
                     reason=C.status_reason(status, contacts, load))

    fmt = lambda v: "      null" if v is None else f"{v:10.1f}"  # noqa: E731
    path = M.motion_text(inputs["motion"])
    damper = (f"wedge R1, R2 | L1, L2 (2b/h_R = {float(shape.br2_over_hr):g}), " if wedge else "")
    lines = [f"Steady cycles at prescribed amplitude from {args.initial}, {damper}mu = {args.mu:g}, "
             f"kn = {C.k_text(args.kn)} N/mm, kt = {C.k_text(args.kt)} N/mm (k in N mm/mrad), {path}",
             f"{'psi_a':>8} {'k_Re':>10} {'k_Im':>10} {'status':>14} {'cycles':>6}"
             + ("   band k_Re [min, max]   band k_Im [min, max]" if args.band else "")]
    for r in rows:
        line = (f"{r['psi_a_mrad']:8.3f} {fmt(r['k_re'])} {fmt(r['k_im'])} {r['status']:>14} "
                f"{r['cycles']:6d}")
        if args.band:
            b = r["band"]
            line += (f"   [{fmt(b['k_re_min'])}, {fmt(b['k_re_max'])}]"
                     f"   [{fmt(b['k_im_min'])}, {fmt(b['k_im_max'])}]")
        lines.append(line)
        opened = {p: [(t["tau_start_deg"], t["tau_end_deg"]) for t in r.get("tracts", [])
                      if t[p] == "open"] for p in r.get("open_fraction", {})}
        for pad, spans in opened.items():
            if spans:
                lines.append(f"{'':8} {pad} open over tau = " + ", ".join(
                    f"{a:.1f}-{b:.1f}" for a, b in _merged(spans)) + " deg")
    lines += [f"  WARNING: {m}" for m in warned]
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["register", "run"]
