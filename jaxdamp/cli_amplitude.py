"""`jaxdamp amplitude`: the exact steady cycle at prescribed platform rotation amplitudes.

    jaxdamp amplitude --shape 60sym --mu 0.5 --psi-a 0.5,1.2,3 [--initial assembly] [--band] [--json]

k_Re, k_Im in N mm/mrad (the Base-Cycle's sign and units), psi_a in mrad. JSON:
{"inputs": {...}, "status": .., "amplitudes": [{"psi_a_mrad", "k_re", "k_im", "status", "cycles",
"band": {"k_re_min", "k_re_max", "k_im_min", "k_im_max"}}]}; `band` only with --band; numbers that
are undefined (no valid cycle) are null.
"""

from __future__ import annotations

import math

from .cli import add_contact_args, add_load_args, add_shape_args, emit, shape_from_args


def register(sub) -> None:
    p = sub.add_parser("amplitude", help="exact steady cycles at prescribed amplitudes psi_a "
                       "(microslip included), from a named initial state; optionally the band")
    add_shape_args(p)
    p.add_argument("--mu", type=float, required=True, help="friction coefficient, in (0, 5]")
    add_contact_args(p)
    add_load_args(p)
    p.add_argument("--psi-a", required=True,
                   help="platform rotation amplitudes, mrad, comma-separated, each in (0, 10000]")
    p.add_argument("--initial", default="gross_slip",
                   help="initial contact state: gross_slip (default) or assembly")
    p.add_argument("--band", action="store_true",
                   help="also the min/max of k_Re, k_Im over all statically admissible initial states")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)


# The existing parser collects extra commands through `register_cli`.
register_cli = register


def _amplitudes(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        values = []
    if not values or any(not math.isfinite(v) or not 0.0 < v <= 1e4 for v in values):
        raise ValueError(f"--psi-a must be comma-separated amplitudes in (0, 10000] mrad; got {text!r}")
    return values


def _number(v):
    v = float(v)
    return v if math.isfinite(v) else None


def run(args) -> int:
    from .amplitude import INITIAL_STATES, amplitude_cycle
    from .params import Contacts, LoadCase, prepare_inputs
    from .status import RESULTS

    # Every input is checked before any work (ValueError / CliError -> one line, exit code 2).
    psis = _amplitudes(args.psi_a)
    if args.initial not in INITIAL_STATES:
        raise ValueError(f"--initial must be one of {', '.join(INITIAL_STATES)}; got {args.initial!r}")
    shape = shape_from_args(args)
    contacts = Contacts(args.kn, args.kt)
    load = LoadCase(args.fd, args.q, args.r_sin_beta)
    prepare_inputs(shape, args.mu, contacts, load)

    rows = []
    for psi in psis:
        ac = amplitude_cycle(shape, args.mu, psi, contacts, load, initial=args.initial)
        valid = bool(RESULTS.valid(ac.status))
        row = {"psi_a_mrad": psi, "k_re": _number(ac.k_re) if valid else None,
               "k_im": _number(ac.k_im) if valid else None,
               "status": RESULTS.name_of(ac.status), "cycles": int(ac.cycles)}
        if args.band:
            from .band import amplitude_band

            row["band"] = amplitude_band(shape, args.mu, psi, contacts, load).as_dict()
        rows.append(row)
    bad = [r["status"] for r in rows if r["status"] not in ("ok", "shakedown")]
    inputs = {"shape": args.shape, "theta_l": float(shape.theta_l), "theta_r": float(shape.theta_r),
              "br_over_hr": float(shape.br_over_hr), "bl2_over_hl": float(shape.bl2_over_hl),
              "mu": args.mu, "kn": args.kn, "kt": args.kt, "F_D": args.fd, "q_star": args.q,
              "r_sin_beta": args.r_sin_beta, "psi_a_mrad": psis, "initial": args.initial,
              "band": bool(args.band)}
    payload = {"inputs": inputs, "status": bad[0] if bad else "ok", "amplitudes": rows}

    fmt = lambda v: "      null" if v is None else f"{v:10.1f}"  # noqa: E731
    lines = [f"Steady cycles at prescribed amplitude from {args.initial}, mu = {args.mu:g}, "
             f"kn = {args.kn:g} N/mm, kt = {args.kt:g} N/mm (k in N mm/mrad)",
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
    emit(args, payload, "\n".join(lines))
    return 0
