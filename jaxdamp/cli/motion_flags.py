"""The flags of a relative platform path, shared by `amplitude`, `response` and `cycle`: --ibpa,
--h-c, --h-l and --motion (`jaxdamp.motion`), their checks (one line, exit 2) and their echo."""

from __future__ import annotations

from .common import CliError

__all__ = ["add_motion_args", "motion_from_args", "motion_echo", "motion_text", "pad_fields"]


def add_motion_args(p, parameter: str = "--psi-a", h_l_extra: str = "") -> None:
    """--ibpa, --h-c, --h-l and --motion: the relative platform path (`jaxdamp.motion`);
    parameter: the flag whose mrad the path's direction is given per."""
    p.add_argument("--ibpa", type=float, default=None,
                   help="interblade phase angle, deg, in [-360, 360]: 0 is in-phase (the default "
                   "motion), 180 out-of-phase, any other an elliptic path")
    p.add_argument("--h-c", type=float, default=None,
                   help="depth of the blades' rotation centre C below D, mm, in [-10000, 10000] "
                   "(needed with --ibpa)")
    p.add_argument("--h-l", type=float, default=None, metavar="MM",
                   help="the damper's size: its left flank's length, mm, in (0, 10000] (needed "
                   "where the platforms turn relative to each other" + h_l_extra + ")")
    p.add_argument("--motion", default=None,
                   help=f"a relative platform path du,dv,dtheta (mm, mm, mrad per mrad of "
                   f"{parameter}; complex entries as re+imj: an ellipse unless real up to one "
                   "phase), instead of --ibpa; write --motion=-0.02,... when the first entry is "
                   "negative")


def motion_from_args(args, load):
    """The jaxdamp.Motion of --ibpa / --motion (None: the paper's in-phase motion), checked."""
    from ..motion import general_motion, interblade_motion

    if args.ibpa is not None and args.motion is not None:
        raise CliError("--ibpa and --motion are two ways to give the path: use one")
    if args.h_c is not None and args.ibpa is None:
        raise CliError("--h-c places the blades' rotation centre for --ibpa: give --ibpa DEG, "
                       "in [-360, 360]")
    if args.motion is not None:
        try:
            direction = [complex(v.strip()) for v in args.motion.split(",")]
        except ValueError:
            raise CliError(f"--motion must be three numbers du,dv,dtheta (mm, mm, mrad; complex as "
                           f"re+imj), e.g. --motion 0.03,0.05,1.5; got {args.motion!r}") from None
        if len(direction) != 3:
            raise CliError(f"--motion must be three numbers du,dv,dtheta, e.g. --motion 0.03,0.05,1.5; "
                           f"got {args.motion!r}")
        return general_motion(direction, args.h_l)
    if args.ibpa is not None:
        if args.h_c is None:
            raise CliError("--h-c (depth of the blades' rotation centre below D, mm, in "
                           "[-10000, 10000]) is needed with --ibpa")
        return interblade_motion(args.ibpa, args.h_c, load.q_star, args.h_l)
    if args.h_l is not None:
        raise CliError("--h-l is the damper's size on a path that turns the platforms: give "
                       "--ibpa or --motion (in-phase results do not depend on it)")
    return None


def motion_echo(args, motion, parameter: str = "psi_a") -> dict | None:
    """The path of a run for its JSON inputs (None: in-phase); parameter: what the direction is
    given per mrad of."""
    if motion is None:
        return None
    return {"ibpa_deg": args.ibpa, "h_c_mm": args.h_c, "h_l_mm": args.h_l,
            "direction": [float(v) for v in motion.direction],
            "quadrature": (None if motion.quadrature is None
                           else [float(v) for v in motion.quadrature]),
            "direction_units": f"du mm, dv mm, dtheta mrad per mrad of {parameter}"}


def motion_text(echo: dict | None) -> str:
    """The path of a run's JSON inputs (`motion_echo`) in one phrase, for a text report."""
    if echo is None:
        return "in-phase"
    quadrature = echo["quadrature"] or [0.0] * 3
    return "{} path (du, dv, dtheta) = ({}) mm, mm, mrad per mrad".format(
        "straight" if echo["quadrature"] is None else "elliptic",
        ", ".join(f"{complex(r, i):.4g}".strip("()").replace("+0j", "")
                  for r, i in zip(echo["direction"], quadrature)))


def pad_fields(shape, cycle, valid: bool, slip_fraction=None) -> dict:
    """The per-pad numbers of a cycle on a path for the JSON (each an object keyed by pad name:
    R1, L1, L2 or R1, R2, L1, L2; null where the cycle has no valid numbers):
    dissipated_energy_nmm, energy_nmm, slip_fraction, open_fraction and the contact-state chart
    `tracts` (`transitions_chart`), on every path. slip_fraction: the fractions where the cycle
    does not carry them (`amplitude.slip_fraction`)."""
    import numpy as np

    from ..charts import transitions_chart
    from ..ellipse import EllipticCycle
    from ..geometry import pad_names
    from .common import number

    def per_pad(values):
        return {p: number(v) if valid else None for p, v in zip(pad_names(shape), np.asarray(values))}

    elliptic = isinstance(cycle, EllipticCycle)
    fractions = cycle.slip_fraction if slip_fraction is None else slip_fraction
    out = dict(dissipated_energy_nmm=number(np.sum(cycle.energy)) if valid else None,
               energy_nmm=per_pad(cycle.energy), slip_fraction=per_pad(fractions))
    # A straight path's solver keeps the curved-flat damper's three pads closed: a pad whose
    # normal force reaches zero ends the cycle as liftoff, so in a valid cycle none is ever open.
    opened = cycle.open_fraction if elliptic else np.zeros(len(pad_names(shape)))
    out.update(open_fraction=per_pad(opened), tracts=transitions_chart(cycle) if valid else [])
    return out
