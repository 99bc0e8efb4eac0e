"""`jaxdamp fit-loops`: contact parameters (mu, kn, kt) from measured hysteresis loops (moment against
platform rotation, or one contact's force against its relative displacement), with standard errors,
intervals, correlations and a statement of what the loops do not identify."""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

from . import common as C

MOMENT_COLUMNS = ("psi_mrad", "moment_nmm")
CONTACT_COLUMNS = ("disp_mm", "force_n")
CONTACT_NAMES = ("R1", "L1", "L2")  # as jaxdamp.geometry (not imported here: no JAX at CLI start)
COMPONENTS = ("tangential", "normal")


def register(sub) -> None:
    p = sub.add_parser("fit-loops", help="fit mu, kn, kt to measured loops (CSV psi_mrad,moment_nmm or "
                                         "disp_mm,force_n, or NPZ), with their uncertainty")
    p.add_argument("files", nargs="+", metavar="FILE",
                   help="one loop per file: CSV with a header row psi_mrad,moment_nmm (rotation in mrad, "
                        "moment in N mm) or disp_mm,force_n (one contact's relative displacement in mm "
                        "and its tangential or normal force in N: give --contact, --component and "
                        "--psi-a), or NPZ with arrays of those names; several periods, any sampling; "
                        "amplitude, centre and offsets are found from the data")
    C.add_shape_args(p)
    C.add_load_args(p)
    p.add_argument("--contact", default=None,
                   help="per-contact loops: the contact, R1, L1 or L2; one for all such files or a comma "
                        "list with one per such file, in order")
    p.add_argument("--component", default=None,
                   help="per-contact loops: tangential (force along the up-flank tangent against the "
                        "platform's displacement relative to the damper along it) or normal (compressive "
                        "force against the approach); one, or a comma list with one per such file")
    p.add_argument("--psi-a", default=None, metavar="MRAD",
                   help="per-contact loops: the platform rotation amplitude (mrad) the loop was recorded "
                        "at (needed: a contact's own displacement range depends on the unknown "
                        "stiffnesses); one, or a comma list with one per such file")
    p.add_argument("--flip-moment", action="store_true",
                   help="negate the moment column of every moment loop before anything else: for a "
                        "rig whose moment sign is opposite to the convention (the integral of M dpsi "
                        "is the energy dissipated, positive); a loop that encloses negative energy "
                        "is refused and says to use this flag")
    p.add_argument("--flip-force", action="store_true",
                   help="negate the force column of every per-contact loop (as --flip-moment for "
                        "moment loops): a tangential loop must enclose positive energy, the integral "
                        "of T d(disp)")
    p.add_argument("--history", choices=("gross_slip", "assembly"), default="gross_slip",
                   help="the history of the model's steady cycle (default gross_slip)")
    p.add_argument("--per-contact", default="",
                   help="parameters fitted per contact (R1, L1, L2): a comma list of mu, kn, kt "
                        "(default: none, one value shared by the three contacts)")
    p.add_argument("--per-side", default="",
                   help="parameters fitted per side (R1 | L1 = L2): a comma list of kn, kt")
    p.add_argument("--start-mu", type=float, default=None, help="start mu, in (0, 5] (default 0.5, generic)")
    p.add_argument("--start-kn", type=float, default=None, help="start kn, N/mm (default 1e4, generic)")
    p.add_argument("--start-kt", type=float, default=None, help="start kt, N/mm (default 5e3, generic)")
    p.add_argument("--no-robust", action="store_true",
                   help="plain least squares only (default: a second stage with a pseudo-Huber loss)")
    p.add_argument("--max-steps", type=int, default=100, help="Levenberg-Marquardt steps per stage (default 100)")
    p.add_argument("--plot", metavar="DIR", default=None,
                   help="write a figure per loop (measured, fitted, residual) and parameters.csv here")
    p.add_argument("--out", metavar="FILE", default=None,
                   help="also write the JSON document here (usable as --contacts-from FILE)")
    C.add_json_arg(p)
    p.add_argument("--no-progress", action="store_true", help="no convergence lines on stderr")
    p.set_defaults(func=run)


def _groups(args) -> dict:
    out = {"mu": "shared", "kn": "shared", "kt": "shared"}
    for flag, text, allowed, kind in (("--per-contact", args.per_contact, ("mu", "kn", "kt"), "contact"),
                                      ("--per-side", args.per_side, ("kn", "kt"), "side")):
        for name in (s.strip().lower() for s in text.split(",") if s.strip()):
            if name not in allowed:
                raise C.CliError(f"{flag} takes a comma list of {', '.join(allowed)}; got {name!r}")
            if out[name] != "shared":
                raise C.CliError(f"{name} is given both per contact and per side; choose one")
            out[name] = kind
    return out


def read_loop(path) -> tuple[str, np.ndarray, np.ndarray]:
    """(kind, x, y) of a CSV (header row) or NPZ file: kind "moment" (x psi_mrad, y moment_nmm) or
    "contact" (x disp_mm, y force_n); CliError in one line otherwise."""
    p = Path(path).expanduser()
    label = str(path)
    if not p.is_file():
        raise C.CliError(f"{label!r} does not exist or is not a file")
    known = MOMENT_COLUMNS + CONTACT_COLUMNS
    if p.suffix.lower() == ".npz":
        try:
            with np.load(p, allow_pickle=False) as z:
                cols = {k.lower(): np.asarray(z[k]) for k in z.files}
        except Exception as exc:  # noqa: BLE001 - any unreadable archive
            raise C.CliError(f"{label!r} is not a readable NPZ file ({type(exc).__name__})") from None
        header = list(cols)
    else:
        try:
            with open(p, newline="", encoding="utf-8-sig") as fh:
                rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
        except (OSError, UnicodeDecodeError) as exc:
            raise C.CliError(f"{label!r} cannot be read as CSV: {exc}") from None
        if not rows:
            raise C.CliError(f"{label!r} is empty; expected a header row {','.join(MOMENT_COLUMNS)} "
                             f"or {','.join(CONTACT_COLUMNS)}")
        header = [h.strip().lower() for h in rows[0]]
        cols = {}
        for j, h in enumerate(header):
            vals = []
            for k, r in enumerate(rows[1:], start=2):
                text = r[j].strip() if j < len(r) else ""
                try:
                    vals.append(float(text) if text else np.nan)
                except ValueError:
                    if h in known:
                        raise C.CliError(f"{label!r} line {k}: {h} is not a number ({text!r})") from None
                    vals.append(np.nan)
            cols[h] = np.asarray(vals)
    has_m = [c in header for c in MOMENT_COLUMNS]
    has_c = [c in header for c in CONTACT_COLUMNS]
    if all(has_m) and all(has_c):
        raise C.CliError(f"{label!r} holds both a moment loop ({','.join(MOMENT_COLUMNS)}) and a "
                         f"per-contact loop ({','.join(CONTACT_COLUMNS)}); give one loop per file")
    if any(has_c) and not any(has_m):
        missing = [c for c, h in zip(CONTACT_COLUMNS, has_c) if not h]
        if missing:
            raise C.CliError(f"{label!r} has no column {', '.join(missing)}; a per-contact loop needs "
                             f"columns {','.join(CONTACT_COLUMNS)} (displacement in mm, force in N); "
                             f"found {','.join(header)}")
        x, y = (np.asarray(cols[c], float).reshape(-1) for c in CONTACT_COLUMNS)
        return "contact", x, y
    missing = [c for c in MOMENT_COLUMNS if c not in header]
    if missing:
        raise C.CliError(f"{label!r} has no column {', '.join(missing)}; expected columns "
                         f"{','.join(MOMENT_COLUMNS)} (rotation in mrad, moment in N mm) or "
                         f"{','.join(CONTACT_COLUMNS)} (one contact); found {','.join(header) or 'none'}")
    psi, m = (np.asarray(cols[c], float).reshape(-1) for c in MOMENT_COLUMNS)
    return "moment", psi, m


def _per_file(flag: str, text, n: int, parse) -> list:
    """A per-contact flag's values, one per per-contact file (a single value serves them all)."""
    if text is None:
        return []
    items = [t.strip() for t in str(text).split(",")]
    if len(items) == 1:
        items = items * n
    if len(items) != n:
        raise C.CliError(f"{flag} takes one value or one per per-contact file ({n}); got {len(items)}")
    return [parse(flag, t) for t in items]


def _parse_contact(flag, t):
    if t.upper() not in CONTACT_NAMES:
        raise C.CliError(f"{flag} takes R1, L1 or L2; got {t!r}")
    return t.upper()


def _parse_component(flag, t):
    if t.lower() not in COMPONENTS:
        raise C.CliError(f"{flag} takes tangential or normal; got {t!r}")
    return t.lower()


def _parse_psi_a(flag, t):
    try:
        v = float(t)
    except ValueError:
        raise C.CliError(f"{flag} takes numbers in (0, 10000] mrad; got {t!r}") from None
    if not 0.0 < v <= 1e4:
        raise C.CliError(f"{flag} must be in (0, 10000] mrad; got {t}")
    return v


def _fmt(v, digits=5) -> str:
    return "-" if v is None or not np.isfinite(v) else f"{v:.{digits}g}"


def _check_direction(loop, name: str, args, kind: str) -> None:
    """One line and exit 2 for a loop that encloses negative energy (numpy; before any fitting)."""
    from ..fit import loop_direction_error

    why = loop_direction_error(loop, name)
    if why is None:
        return
    flag = "--flip-moment" if kind == "moment" else "--flip-force"
    given = args.flip_moment if kind == "moment" else args.flip_force
    how = f" ({flag} was given: drop it)" if given else f" (rerun with {flag})"
    raise C.CliError(why + how)


def run(args) -> int:
    groups = _groups(args)
    shape = C.shape_from_args(args)
    load = C.load_from_args(args)
    start = _start(args)  # checked once, by the library (fit_problem)
    if args.max_steps < 1:
        raise C.CliError(f"--max-steps must be an integer >= 1; got {args.max_steps}")
    plot_dir = None if args.plot is None else C.check_output_dir("--plot", args.plot)
    out = None if args.out is None else C.check_output_file("--out", args.out, suffixes=(".json",))
    loops = read_loops(args)
    fit = _fit(args, loops, shape, load, start, groups)
    doc, notes, loop_rows, sigma_unit = _document(args, fit, shape, load, start, groups)
    lines = _text(args, fit, groups, loops, notes, loop_rows, sigma_unit)
    if plot_dir is not None:
        lines += _write_plots(args, fit, shape, load, plot_dir)
    if out is not None:
        C.write_text(out, C.dumps(doc) + "\n")
        lines.append(f"wrote {out}")
    C.emit(args, doc, "\n".join(lines))
    return 0


def _start(args) -> dict:
    """The start values of the flags, DEFAULT_START where not given (checked by fit_problem)."""
    from ..fit import DEFAULT_START

    start = {"mu": args.start_mu, "kn": args.start_kn, "kt": args.start_kt}
    return {k: (DEFAULT_START[k] if v is None else v) for k, v in start.items()}


def read_loops(args) -> list:
    """Every file's loop, read, flipped as the flags say, analysed and checked for its direction
    (CliError in one line naming the file or the flag)."""
    from ..fit import LoopError, analyse_contact_loop, analyse_loop

    read = [read_loop(f) for f in args.files]
    flip = {"moment": args.flip_moment, "contact": args.flip_force}
    read = [(kind, x, -y if flip[kind] else y) for kind, x, y in read]
    n_c = sum(kind == "contact" for kind, _, _ in read)
    if n_c == 0:
        given = [fl for fl, v in (("--contact", args.contact), ("--component", args.component),
                                  ("--psi-a", args.psi_a)) if v is not None]
        if given:
            raise C.CliError(f"{', '.join(given)} describe per-contact loops (disp_mm,force_n); none of "
                             "the files is one")
    else:
        for flag, v in (("--contact", args.contact), ("--component", args.component),
                        ("--psi-a", args.psi_a)):
            if v is None:
                first = next(f for f, (kind, _, _) in zip(args.files, read) if kind == "contact")
                raise C.CliError(f"{str(first)!r} is a per-contact loop (disp_mm,force_n): give {flag} "
                                 "(--contact R1|L1|L2, --component tangential|normal, --psi-a MRAD: "
                                 "the platform amplitude it was recorded at)")
    contacts_of = _per_file("--contact", args.contact, n_c, _parse_contact)
    components = _per_file("--component", args.component, n_c, _parse_component)
    psi_as = _per_file("--psi-a", args.psi_a, n_c, _parse_psi_a)
    loops, k = [], 0
    for f, (kind, x, y) in zip(args.files, read):
        try:
            if kind == "moment":
                loops.append(analyse_loop(x, y, name=repr(str(f))))
            else:
                loops.append(analyse_contact_loop(x, y, contacts_of[k], components[k], psi_as[k],
                                                  name=repr(str(f))))
                k += 1
        except LoopError as exc:
            raise C.CliError(str(exc)) from None
        _check_direction(loops[-1], repr(str(f)), args, kind)
    return loops


def _fit(args, loops, shape, load, start, groups):
    """fit_loops on the loops, its progress lines on stderr unless --no-progress."""
    from ..fit import fit_loops
    from . import exported

    progress = not args.no_progress

    def tick(stage, step, loss):
        if progress:
            what = "least squares" if stage == 0 else "robust (pseudo-Huber)"
            print(f"fit-loops: stage {stage + 1} ({what}) step {step:3d}  loss {loss:.6e}",
                  file=sys.stderr, flush=True)

    return fit_loops(loops, shape, load=load, initial=args.history, start=start,
                     robust=not args.no_robust, max_steps=args.max_steps, callback=tick,
                     names=[repr(str(f)) for f in args.files],
                     runner=exported.Runner("fit_loops"), **groups)


def _document(args, fit, shape, load, start, groups):
    """(the JSON document, the notes, one row per loop, the residual's unit)."""
    from ..fit import ContactLoop
    from ..status import RESULTS

    status = RESULTS.name_of(fit.status)
    names = fit.names
    params = fit.as_dict()
    unident = [n for n, ok in zip(names, fit.identifiable) if not ok]
    mu_out = fit.mu if np.ndim(fit.mu) == 0 else [float(v) for v in fit.mu]
    # a shared stiffness as one number: commands that take one pair (sweep, optimize) read it too
    k_out = lambda k, g: float(k[0]) if g == "shared" else [float(v) for v in k]  # noqa: E731
    contacts = {"kn_n_per_mm": k_out(fit.kn, groups["kn"]), "kt_n_per_mm": k_out(fit.kt, groups["kt"]),
                "mu": mu_out}
    notes = ["kn, kt, mu under 'contacts' are the solver's end values, for --contacts-from; "
             "'parameters' holds the results with their intervals (null where not identifiable)"]
    if unident:
        notes.append(f"not identifiable from these loops: {', '.join(unident)}; their values under "
                     "'contacts' are not measurements (any value along the Jacobian's null direction "
                     f"fits as well); the intervals of the others are for what the loops determine (pseudo-inverse "
                     "of J^T J without the null directions)")
    if groups["mu"] == "contact":
        notes.append("per-contact mu: the other commands' --contacts-from takes one mu only")
    def loop_row(i, f, lp):
        row = {"file": str(f), "samples": int(lp.x.size), "periods": int(lp.periods)}
        if isinstance(lp, ContactLoop):
            row.update({"kind": "contact", "contact": CONTACT_NAMES[lp.contact], "component": lp.component,
                        "psi_a_mrad": C.number(lp.psi_a), "disp_a_mm": C.number(lp.disp_a),
                        "disp_c_mm": C.number(lp.disp_c), "offset_n": C.number(fit.offsets[i]),
                        "rms_n": C.number(fit.rms[i]), "monotone": bool(fit.monotone[i])})
        else:
            row.update({"kind": "moment", "psi_a_mrad": C.number(lp.psi_a),
                        "psi_c_mrad": C.number(lp.psi_c), "offset_nmm": C.number(fit.offsets[i]),
                        "rms_nmm": C.number(fit.rms[i])})
        row["cycle_status"] = RESULTS.name_of(fit.statuses[i])
        return row

    kinds = {isinstance(lp, ContactLoop) for lp in fit.loops}
    sigma_unit = ("N mm" if kinds == {False} else "N" if kinds == {True}
                  else "none (mixed units: see each loop's rms)")
    loop_rows = [loop_row(i, f, lp) for i, (f, lp) in enumerate(zip(args.files, fit.loops))]
    bent = [str(f) for f, lp, ok in zip(args.files, fit.loops, fit.monotone) if not ok]
    if bent:
        notes.append(f"at the fitted parameters the model's contact displacement of {', '.join(bent)} "
                     "turns within a half-cycle, so its force is not a function of the displacement "
                     "there and the comparison is only approximate: prefer moment loops or another contact")
    payload = {"contacts": contacts, "parameters": params["parameters"],
               "correlation": {"names": names, "matrix": params["correlation"]},
               "confidence": 0.95, "not_identifiable": unident,
               "sigma_nmm": params["sigma_nmm"] if sigma_unit == "N mm" else None,
               "sigma": params["sigma_nmm"], "sigma_unit": sigma_unit,
               "loops": loop_rows,
               "convergence": {"steps": fit.steps,
                               "history": [{"stage": s + 1, "step": k, "loss": v} for s, k, v in fit.history]},
               "notes": notes}
    from ..params import Contacts

    reason = C.status_reason(status, Contacts(np.asarray(fit.kn, float), np.asarray(fit.kt, float)), load)
    doc = C.document(status, payload, reason=reason, files=[str(f) for f in args.files],
                     shape=C.shape_echo(shape),
                     load=C.load_echo(load), history=args.history, groups=groups,
                     start={"mu": start["mu"], "kn_n_per_mm": start["kn"], "kt_n_per_mm": start["kt"]},
                     robust=not args.no_robust, max_steps=args.max_steps,
                     flip_moment=bool(args.flip_moment), flip_force=bool(args.flip_force))
    return doc, notes, loop_rows, sigma_unit


def _text(args, fit, groups, loops, notes, loop_rows, sigma_unit) -> list:
    """The text report's lines."""
    from ..status import RESULTS

    names = fit.names
    lines = [f"Contact parameters from {len(loops)} loop{'s' if len(loops) != 1 else ''} "
             f"({args.history} history; mu {groups['mu']}, kn {groups['kn']}, kt {groups['kt']})",
             f"  {'parameter':12} {'value':>12} {'std err':>10}   95 % interval"]
    for i, n in enumerate(names):
        if fit.identifiable[i]:
            lines.append(f"  {n:12} {_fmt(fit.value[i]):>12} {_fmt(fit.se[i], 3):>10}   "
                         f"[{_fmt(fit.lo[i])}, {_fmt(fit.hi[i])}]")
        else:
            lines.append(f"  {n:12} {'NOT IDENTIFIABLE':>12}   {fit.why[i]}")
    lines.append("  units: mu -, kn and kt N/mm, offsets N mm for moment loops and N for per-contact loops "
                 "(offset_i: loop i's force offset)")
    lines.append(f"  residual sd {_fmt(fit.sigma, 3)} {sigma_unit}; LM steps {fit.steps}; "
                 f"status {RESULTS.name_of(fit.status)}")
    for row in loop_rows:
        if row["kind"] == "contact":
            lines.append(f"  {row['file']}: {row['contact']} {row['component']} at psi_a "
                         f"{_fmt(row['psi_a_mrad'])} mrad, displacement amplitude "
                         f"{_fmt(row['disp_a_mm'], 4)} mm, centre {_fmt(row['disp_c_mm'], 4)} mm, "
                         f"{row['periods']} period(s), {row['samples']} samples, rms "
                         f"{_fmt(row['rms_n'], 3)} N")
        else:
            lines.append(f"  {row['file']}: psi_a {_fmt(row['psi_a_mrad'])} mrad, centre "
                         f"{_fmt(row['psi_c_mrad'], 4)} mrad, {row['periods']} period(s), "
                         f"{row['samples']} samples, rms {_fmt(row['rms_nmm'], 3)} N mm")
    big = [(names[a], names[b], fit.correlation[a, b]) for a in range(len(names))
           for b in range(a + 1, len(names)) if np.isfinite(fit.correlation[a, b])
           and abs(fit.correlation[a, b]) > 0.9]
    for a, b, c in big:
        lines.append(f"  strongly correlated: {a} and {b} ({c:+.3f})")
    lines += [f"  note: {n}" for n in notes[1:]]
    return lines


def _write_plots(args, fit, shape, load, plot_dir) -> list:
    """--plot: a figure per loop and parameters.csv; the lines that say so."""
    from ..fit import ContactLoop
    from ..plotting.fit import plot_loop_fit
    import matplotlib.pyplot as plt

    lines, names = [], fit.names
    for i, f in enumerate(args.files):
        lp = fit.loops[i]
        what = (f"{CONTACT_NAMES[lp.contact]} {lp.component}, " if isinstance(lp, ContactLoop) else "")
        fig = plot_loop_fit(fit, i, shape, load, title=f"{Path(f).name}: {what}psi_a = "
                            f"{lp.psi_a:.4g} mrad")
        path = plot_dir / f"loop_{i + 1}_{Path(f).stem}.png"
        C.save_figure(fig, path, dpi=110)
        plt.close(fig)
        lines.append(f"wrote {path}")
    rows = ["parameter,value,std_err,lo_95,hi_95,identifiable,why"]
    for i, n in enumerate(names):
        rows.append(",".join([n, _fmt(fit.value[i], 10), _fmt(fit.se[i], 6), _fmt(fit.lo[i], 10),
                              _fmt(fit.hi[i], 10), str(bool(fit.identifiable[i])).lower(),
                              '"' + fit.why[i].replace('"', "'") + '"']))
    C.write_text(plot_dir / "parameters.csv", "\n".join(rows) + "\n")
    lines.append(f"wrote {plot_dir / 'parameters.csv'}")
    return lines


__all__ = ["MOMENT_COLUMNS", "CONTACT_COLUMNS", "CONTACT_NAMES", "COMPONENTS", "register",
           "read_loop", "read_loops", "run"]
