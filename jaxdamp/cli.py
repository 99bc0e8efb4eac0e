"""Command-line interface: `jaxdamp <command> ...`.

Units: angles in degrees, b_R/h_R and 2b_L/h_L dimensionless (fractions of the flank lengths),
forces normalised to the centrifugal force F_D (statics) or in N, stiffness in N/mm, q* in mm,
platform rotation psi in mrad, rotational stiffness k in N mm/mrad, energy in N mm per cycle.
"""

from __future__ import annotations

import argparse
import json
import sys

UNITS = __doc__.split("\n\n", 1)[1]


class CliError(Exception):
    pass


def add_shape_args(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("damper shape (either --shape or the three angles/offsets)")
    g.add_argument("--shape", help="a paper shape: 90L, 74L, 60sym, 74R, 90R, 45sym")
    g.add_argument("--theta-l", type=float, help="left base angle, deg, in (0, 90]")
    g.add_argument("--theta-r", type=float, help="right base angle, deg, in (0, 90]")
    g.add_argument("--br", type=float, help="b_R/h_R: offset of pad R1 up the right flank, in [-0.5, 0.5]")
    g.add_argument("--bl2", type=float, default=None, help="2b_L/h_L: pad spacing on the left flank, in (0, 1] (default 0.8)")


def shape_from_args(args):
    from .geometry import DamperShape, family_shape

    angles = (args.theta_l, args.theta_r, args.br)
    if args.shape and any(v is not None for v in angles):
        raise CliError("give either --shape or --theta-l/--theta-r/--br, not both")
    if args.shape:
        shape = family_shape(args.shape)
        return shape if args.bl2 is None else shape._replace(bl2_over_hl=args.bl2)
    if any(v is None for v in angles):
        raise CliError("a shape needs --shape NAME or all of --theta-l, --theta-r, --br")
    return DamperShape(args.theta_l, args.theta_r, args.br, 0.8 if args.bl2 is None else args.bl2)


def add_contact_args(p, required=False):
    from .params import REFERENCE_KN, REFERENCE_KT

    p.add_argument("--kn", type=float, default=None if required else REFERENCE_KN, required=required,
                   help=f"normal contact stiffness, N/mm (default {REFERENCE_KN:g})")
    p.add_argument("--kt", type=float, default=None if required else REFERENCE_KT, required=required,
                   help=f"tangential contact stiffness, N/mm (default {REFERENCE_KT:g})")


def add_load_args(p) -> None:
    p.add_argument("--fd", type=float, default=1000.0, help="centrifugal force F_D, N (default 1000)")
    p.add_argument("--q", type=float, default=100.0, help="virtual blade pitch q*, mm (default 100)")
    p.add_argument("--r-sin-beta", type=float, default=0.0, help="r sin(beta), mm (default 0)")


def emit(args, payload: dict, text: str) -> None:
    print(json.dumps(payload, indent=2) if args.json else text)


def _named(values) -> dict:
    from .geometry import CONTACT_NAMES

    return {c: float(v) for c, v in zip(CONTACT_NAMES, values)}


# ---------------------------------------------------------------- statics / design-br
def cmd_statics(args):
    from .statics import full_slip_statics

    st = full_slip_statics(shape_from_args(args), args.mu)

    def end(s):
        return {"N": _named(s.N), "T": _named(s.T), "resultant_pos_pct": float(s.resultant_pos_pct)}

    payload = {"start": end(st.start), "mid": end(st.mid), "liftoff": bool(st.liftoff),
               "min_normal_over_fd": float(st.min_normal_over_fd)}
    lines = [f"Full-slip statics, mu = {args.mu:g} (forces in units of F_D)",
             f"{'':12}{'N_R1':>9}{'N_L1':>9}{'N_L2':>9}{'T_R1':>9}{'T_L1':>9}{'T_L2':>9}  resultant (% L1->L2)"]
    for label, s in (("cycle start", st.start), ("mid-cycle", st.mid)):
        nums = "".join(f"{float(v):9.4f}" for v in list(s.N) + list(s.T))
        lines.append(f"{label:12}{nums}  {float(s.resultant_pos_pct):8.2f}")
    lines.append(f"min normal force / F_D = {float(st.min_normal_over_fd):.4f}; "
                 f"liftoff: {'YES' if st.liftoff else 'no'}")
    emit(args, payload, "\n".join(lines))


def cmd_design_br(args):
    from .statics import design_br

    res = design_br(shape_from_args(args), args.mu_max)
    payload = {"br_over_hr": float(res.br_over_hr), "found": bool(res.found),
               "margin_pct": float(res.margin_pct), "inside": bool(res.inside), "mu_max": args.mu_max}
    text = (f"b_R/h_R = {float(res.br_over_hr):.4f} centres the left resultant at mu_max = {args.mu_max:g}: "
            f"{float(res.margin_pct):.2f} % of L1-L2 from the nearer pad at both ends"
            + ("" if res.inside else "  (OUTSIDE L1-L2: no b_R avoids liftoff)"))
    emit(args, payload, text)


# ---------------------------------------------------------------- cycle
def cycle_payload(bc) -> dict:
    from .cycle import transitions_chart
    from .energy import contact_energies, work_shape_factors
    from .harmonics import five_numbers

    nums = five_numbers(bc)
    energy = contact_energies(bc)
    w = work_shape_factors(bc)
    tracts = {"forward": [], "backward": []}
    for row in transitions_chart(bc):
        entry = {c: row[c] for c in ("R1", "L1", "L2")}
        entry["dv_mm"] = row["dv_mm"]
        if row.get("stretch"):
            entry["stretch"] = True
        tracts[row["half"]].append(entry)
    return {
        "psi_fs_mrad": float(nums.psi_fs), "k_re_fs": float(nums.k_re_fs),
        "psi_bc_mrad": float(nums.psi_bc), "k_re_bc": float(nums.k_re_bc),
        "k_im_bc": float(nums.k_im_bc),
        "spans_mm": {"forward": float(bc.forward.span), "backward": float(bc.backward.span)},
        "converged": bool(bc.converged), "liftoff": bool(bc.liftoff), "failed": bool(bc.failed),
        "half_cycles": int(bc.half_cycles), "tracts": tracts,
        "energy_Nmm": {**_named(energy.contacts), "moment": float(energy.moment)},
        "work_shape_factors": {k: float(v) for k, v in w._asdict().items()},
    }


def cmd_cycle(args):
    from .cycle import base_cycle
    from .params import Contacts, LoadCase

    bc = base_cycle(shape_from_args(args), args.mu, Contacts(args.kn, args.kt),
                    LoadCase(args.fd, args.q, args.r_sin_beta))
    p = cycle_payload(bc)
    if p["liftoff"]:
        p_text = "LIFTOFF: a normal force reaches zero; this shape/mu is not a valid damper design."
        emit(args, p, p_text)
        return
    lines = [f"Base-Cycle, mu = {args.mu:g}, kn = {args.kn:g} N/mm, kt = {args.kt:g} N/mm, "
             f"F_D = {args.fd:g} N, q* = {args.q:g} mm"
             + ("" if p["converged"] else "   [NOT CONVERGED]"),
             f"  psi_fs = {p['psi_fs_mrad']:.4f} mrad   k_Re,fs = {p['k_re_fs']:.1f} N mm/mrad",
             f"  psi_BC = {p['psi_bc_mrad']:.4f} mrad   k_Re,BC = {p['k_re_bc']:.1f}   "
             f"k_Im,BC = {p['k_im_bc']:.1f} N mm/mrad",
             f"  spans: forward {p['spans_mm']['forward']:.5f} mm, backward "
             f"{p['spans_mm']['backward']:.5f} mm, half-cycles run: {p['half_cycles']}",
             "  transitions:"]
    for half in ("forward", "backward"):
        for t in p["tracts"][half]:
            lines.append(f"    {half:8} dv = {t['dv_mm']:.5f} mm   R1 {t['R1']:9} L1 {t['L1']:9} L2 {t['L2']:9}"
                         + ("  (full-slip stretch)" if t.get("stretch") else ""))
    e = p["energy_Nmm"]
    lines.append(f"  energy per cycle (N mm): R1 {e['R1']:.3f}  L1 {e['L1']:.3f}  L2 {e['L2']:.3f}  "
                 f"moment {e['moment']:.3f}")
    w = p["work_shape_factors"]
    lines.append("  work shape factors: " + "  ".join(f"{k} {v:.4f}" for k, v in w.items()))
    emit(args, p, "\n".join(lines))


# ---------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="jaxdamp", description="Underplatform damper Base-Cycles by the direct method.\n\n" + UNITS,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("statics", help="full-slip contact forces at cycle start and mid-cycle")
    add_shape_args(p)
    p.add_argument("--mu", type=float, required=True, help="friction coefficient, > 0")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=cmd_statics)

    p = sub.add_parser("design-br", help="the b_R/h_R that centres the left resultant at mu_max (§3)")
    add_shape_args(p)
    p.add_argument("--mu-max", type=float, default=0.7, help="highest friction coefficient (default 0.7)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_design_br)

    p = sub.add_parser("cycle", help="the Base-Cycle: five numbers, transitions, energies")
    add_shape_args(p)
    p.add_argument("--mu", type=float, required=True, help="friction coefficient, > 0")
    add_contact_args(p)
    add_load_args(p)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_cycle)

    for register in _extra_commands():
        register(sub)
    return parser


# Modules that contribute subcommands through a `register_cli(subparsers)` function.
EXTRA_COMMAND_MODULES = ("jaxdamp.gradients", "jaxdamp.batch", "jaxdamp.calibration",
                         "optimize.cli", "jaxdamp.study", "jaxdamp.cli_response")


def _extra_commands():
    import importlib

    found = []
    for mod in EXTRA_COMMAND_MODULES:
        try:
            module = importlib.import_module(mod)
        except ModuleNotFoundError as exc:
            if exc.name == mod:  # not written yet; any other missing import is a real error
                continue
            raise
        if hasattr(module, "register_cli"):
            found.append(module.register_cli)
    return found


def main(argv=None) -> int:
    import jax

    jax.config.update("jax_enable_x64", True)
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        args.func(args)
    except (ValueError, CliError) as exc:
        print(f"jaxdamp {args.command}: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
