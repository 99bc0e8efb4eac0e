"""`jaxdamp amplitude`: the exact steady cycle at prescribed platform rotation amplitudes.

    jaxdamp amplitude --shape 60sym --mu 0.5 --psi-a 0.5,1.2,3 [--initial assembly] [--band] [--json]

k_Re, k_Im in N mm/mrad (the Base-Cycle's sign and units), psi_a in mrad. JSON:
{"inputs": {...}, "status": .., "amplitudes": [{"psi_a_mrad", "k_re", "k_im", "status", "cycles",
"band": {"k_re_min", "k_re_max", "k_im_min", "k_im_max"}}]}; `band` only with --band; numbers that
are undefined (no valid cycle) are null.
"""

from __future__ import annotations

from . import common as C


def register(sub) -> None:
    p = sub.add_parser("amplitude", help="exact steady cycles at prescribed amplitudes psi_a "
                       "(microslip included), from a named initial state; optionally the band")
    C.add_design_args(p)
    p.add_argument("--psi-a", required=True,
                   help="platform rotation amplitudes, mrad, comma-separated, each in (0, 10000]")
    p.add_argument("--initial", default="gross_slip",
                   help="initial contact state: gross_slip (default) or assembly")
    p.add_argument("--band", action="store_true",
                   help="also the min/max of k_Re, k_Im over all statically admissible initial states")
    C.add_progress_arg(p)
    C.add_json_arg(p)
    p.set_defaults(func=run)


def _amplitudes(text: str) -> list[float]:
    from .._validate import check_range

    values = list(C.float_list(text, "--psi-a", example="0.5,1.2,3"))
    check_range("--psi-a", values, 0.0, 1e4, lo_open=True, unit="mrad")
    return values


def run(args) -> int:
    from ..amplitude import INITIAL_STATES, amplitude_cycle
    from ..params import prepare_inputs
    from ..status import RESULTS

    # Every input is checked before any work (ValueError / CliError -> one line, exit code 2).
    contacts, load = C.contacts_from_args(args), C.load_from_args(args)  # --mu resolved here too
    psis = _amplitudes(args.psi_a)
    if args.initial not in INITIAL_STATES:
        raise ValueError(f"--initial must be one of {', '.join(INITIAL_STATES)}; got {args.initial!r}")
    shape = C.shape_from_args(args)
    prepare_inputs(shape, args.mu, contacts, load)

    rows, warned = [], []
    bar = C.progress_bar(args, total=len(psis), desc="amplitudes", unit="amplitude")
    for psi in psis:
        with C.model_warnings() as caught:  # an amplitude above the small-rotation limit
            ac = amplitude_cycle(shape, args.mu, psi, contacts, load, initial=args.initial)
        warned.extend(m for m in caught if m not in warned)
        valid = bool(RESULTS.valid(ac.status))
        row = {"psi_a_mrad": psi, "k_re": C.number(ac.k_re) if valid else None,
               "k_im": C.number(ac.k_im) if valid else None,
               "status": RESULTS.name_of(ac.status), "cycles": int(ac.cycles)}
        if args.band:
            from ..band import amplitude_band

            row["band"] = amplitude_band(shape, args.mu, psi, contacts, load).as_dict()
        rows.append(row)
        bar.update(1)
    bar.close()
    bad = [r["status"] for r in rows if r["status"] not in ("ok", "shakedown")]
    inputs = {"shape": args.shape and C.shape_name(args.shape), "theta_l": float(shape.theta_l),
              "theta_r": float(shape.theta_r), "br_over_hr": float(shape.br_over_hr),
              "bl2_over_hl": float(shape.bl2_over_hl), "x_d": shape.x_d,
              "mu": args.mu, "kn": args.kn, "kt": args.kt, "F_D": args.fd, "q_star": args.q,
              "r_sin_beta": args.r_sin_beta, "psi_a_mrad": psis, "initial": args.initial,
              "band": bool(args.band)}
    status = bad[0] if bad else "ok"
    doc = C.document(status, {"inputs": inputs, "amplitudes": rows, "warnings": warned},
                     reason=C.status_reason(status, contacts, load))

    fmt = lambda v: "      null" if v is None else f"{v:10.1f}"  # noqa: E731
    lines = [f"Steady cycles at prescribed amplitude from {args.initial}, mu = {args.mu:g}, "
             f"kn = {C.k_text(args.kn)} N/mm, kt = {C.k_text(args.kt)} N/mm (k in N mm/mrad)",
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
    lines += [f"  WARNING: {m}" for m in warned]
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["register", "run"]
