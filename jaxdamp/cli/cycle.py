"""`jaxdamp cycle`: the Base-Cycle of one design: five numbers, transitions, energies."""

from __future__ import annotations

import functools

from . import common as C
from . import exported
from . import motion_flags as M

NUMBER_KEYS = ("psi_fs_mrad", "k_re_fs", "psi_bc_mrad", "k_re_bc", "k_im_bc")


def register(sub) -> None:
    p = sub.add_parser("cycle", help="the Base-Cycle: five numbers, transitions, energies")
    C.add_design_args(p)
    C.add_damper_args(p)
    M.add_motion_args(p, parameter="the left-hand blade's rotation")
    C.add_json_arg(p)
    p.set_defaults(func=run)


def _cycle_numbers(bc):
    """Everything the command prints, computed in one program (one trace and one compilation-cache
    read per process instead of one per quantity: the second call's cost is mostly those)."""
    from ..energy import contact_energies, work_shape_factors
    from ..harmonics import five_numbers_kernel

    return bc, five_numbers_kernel(bc), contact_energies(bc), work_shape_factors(bc)


@functools.cache
def _program():
    import jax

    from ..cycle import base_cycle_kernel

    return jax.jit(lambda *design: _cycle_numbers(base_cycle_kernel(*design)))


def cycle_payload(bc, nums, energy, factors) -> dict:
    """The numbers of a BaseCycle (with its five numbers, contact energies and work shape factors,
    as `_cycle_numbers` computes them); those that do not exist (liftoff, singular) are None."""
    from ..conventions import warn_small_rotation
    from ..cycle import transitions_chart

    status = C.status_name(bc)
    # Ill-conditioned numbers are wrong numbers: they are not shown (null), only the status.
    exists = status not in ("liftoff", "singular", "ill_conditioned")
    with C.model_warnings() as caught:
        warn_small_rotation(nums.psi_bc, stacklevel=2)
    p = {k: (C.number(v) if exists else None) for k, v in zip(NUMBER_KEYS, nums)}
    p["warnings"] = caught if exists else []
    p["spans_mm"] = {"forward": C.number(bc.forward.span) if exists else None,
                     "backward": C.number(bc.backward.span) if exists else None}
    p.update(half_cycles=int(bc.half_cycles))
    if exists:
        tracts = {"forward": [], "backward": []}
        for row in transitions_chart(bc):
            entry = {c: row[c] for c in ("R1", "L1", "L2")}
            entry["dv_mm"] = C.number(row["dv_mm"])
            if row.get("stretch"):
                entry["stretch"] = True
            tracts[row["half"]].append(entry)
        p["tracts"] = tracts
        p["energy_Nmm"] = {**C.named(energy.contacts), "moment": C.number(energy.moment)}
        p["work_shape_factors"] = {k: C.number(v) for k, v in factors._asdict().items()}
    else:
        p["tracts"] = None
        p["energy_Nmm"] = dict.fromkeys(("R1", "L1", "L2", "moment"))
        p["work_shape_factors"] = dict.fromkeys(("w_R1", "w_L1", "w_L2", "w_M"))
    return p


def refuse_path(args, load) -> None:
    """--ibpa 0 is the in-phase scene itself (the Base-Cycle as without it); any other path, one
    line and exit 2: the paper's Base-Cycle (full slip one way to full slip the other on the
    in-phase stroke) has no definition yet on a path that turns the platforms."""
    motion = M.motion_from_args(args, load)  # the flags' own checks first
    if motion is None or (args.ibpa is not None and args.ibpa % 360.0 == 0.0):
        return
    flag = "--ibpa" if args.ibpa is not None else "--motion"
    raise C.CliError(f"{flag}: `jaxdamp cycle` is the in-phase Base-Cycle (--ibpa 0); the exact "
                   "cycles on this path: jaxdamp amplitude " + (
                       f"--ibpa {args.ibpa:g} --h-c MM" if args.ibpa is not None
                       else "--motion du,dv,dtheta") + " --h-l MM --psi-a MRAD, its forced "
                   "response: jaxdamp response with the same flags")


def run(args) -> int:
    from ..params import prepare_inputs

    C.refuse_wedge(args, "cycle", "the Base-Cycle starts from the full-slip statics of three pads")
    contacts, load = C.contacts_from_args(args), C.load_from_args(args)  # --mu resolved here too
    refuse_path(args, load)
    shape = C.shape_from_args(args)
    # A saved program (exported.call): a repeat call neither traces nor lowers it, which was
    # 2.9 s of a 3.6 s repeat (benchmarks/results/compile_costs.json).
    results = exported.call("cycle", _program(), prepare_inputs(shape, args.mu, contacts, load))
    status = C.status_name(results[0])
    p = cycle_payload(*results)
    doc = C.document(status, p, reason=C.status_reason(status, contacts, load),
                     shape=C.shape_echo(shape), mu=args.mu, contacts=C.contacts_echo(contacts),
                     load=C.load_echo(load))
    head = (f"Base-Cycle, mu = {args.mu:g}, kn = {C.k_text(args.kn)} N/mm, "
            f"kt = {C.k_text(args.kt)} N/mm, F_D = {args.fd:g} N, q* = {args.q:g} mm")
    if p["psi_bc_mrad"] is None:
        C.emit(args, doc, head + "\n  no cycle (the status above says why)")
        return 0
    fmt = lambda v, f: "n/a" if v is None else format(v, f)  # noqa: E731
    lines = [head,
             f"  psi_fs = {fmt(p['psi_fs_mrad'], '.4f')} mrad   "
             f"k_Re,fs = {fmt(p['k_re_fs'], '.1f')} N mm/mrad",
             f"  psi_BC = {fmt(p['psi_bc_mrad'], '.4f')} mrad   "
             f"k_Re,BC = {fmt(p['k_re_bc'], '.1f')}   "
             f"k_Im,BC = {fmt(p['k_im_bc'], '.1f')} N mm/mrad",
             f"  spans: forward {fmt(p['spans_mm']['forward'], '.5f')} mm, backward "
             f"{fmt(p['spans_mm']['backward'], '.5f')} mm, half-cycles run: {p['half_cycles']}",
             *(f"  WARNING: {w}" for w in p["warnings"]),
             "  transitions:"]
    for half in ("forward", "backward"):
        for t in p["tracts"][half]:
            lines.append(f"    {half:8} dv = {fmt(t['dv_mm'], '.5f')} mm   R1 {t['R1']:9} "
                         f"L1 {t['L1']:9} L2 {t['L2']:9}"
                         + ("  (full-slip stretch)" if t.get("stretch") else ""))
    e = p["energy_Nmm"]
    lines.append("  energy per cycle (N mm): "
                 + "  ".join(f"{k} {fmt(e[k], '.3f')}" for k in ("R1", "L1", "L2", "moment")))
    w = p["work_shape_factors"]
    lines.append("  work shape factors: " + "  ".join(f"{k} {fmt(v, '.4f')}" for k, v in w.items()))
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["NUMBER_KEYS", "register", "cycle_payload", "run"]
