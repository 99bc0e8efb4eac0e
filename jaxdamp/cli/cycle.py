"""`jaxdamp cycle`: the Base-Cycle of one design: five numbers, transitions, energies; on any
straight platform path and for a wedge, the same construction on the tract engine
(`jaxdamp.path_base_cycle`)."""

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
def cycle_program():
    import jax

    from ..cycle import base_cycle_kernel

    return jax.jit(lambda *design: _cycle_numbers(base_cycle_kernel(*design)))


@functools.cache
def _path_program():
    import jax

    from ..path_base_cycle import path_base_cycle_kernel

    return jax.jit(path_base_cycle_kernel)


def cycle_payload(bc, nums, energy, factors) -> dict:
    """The numbers of a BaseCycle (with its five numbers, contact energies and work shape factors,
    as `_cycle_numbers` computes them); those that do not exist (liftoff, singular) are None."""
    from ..conventions import warn_small_rotation
    from ..charts import transitions_chart

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


def refuse_ellipse(args, motion) -> None:
    """One line, exit 2, for an elliptic path: no half of it ends in gross slip, so it has no
    Base-Cycle (`jaxdamp.path_base_cycle`); its exact cycles are the amplitude command's."""
    if motion.quadrature is None:
        return
    flag = "--ibpa" if args.ibpa is not None else "--motion"
    raise C.CliError(f"{flag}: this path is an ellipse, which has no Base-Cycle (no half of it "
                     "ends in gross slip: the Base-Cycle is defined on straight paths, --ibpa 0 or "
                     "180 or a real --motion); its exact cycles: jaxdamp amplitude " + (
                         f"--ibpa {args.ibpa:g} --h-c MM" if args.ibpa is not None
                         else "--motion du,dv,dtheta") + " --h-l MM --psi-a MRAD, its forced "
                     "response: jaxdamp response with the same flags")


def path_payload(pbc, shape) -> dict:
    """The numbers of a `PathBaseCycle` under the in-phase command's keys (amplitudes in mrad of the
    path's parameter), with the per-pad fields of a cycle on a path (`motion_flags.pad_fields`);
    null where the status says there are none."""
    from ..conventions import warn_small_rotation
    from ..status import RESULTS

    valid = bool(RESULTS.valid(pbc.status))
    nums = (pbc.a_fs, pbc.k_re_fs, pbc.a_bc, pbc.k_re_bc, pbc.k_im_bc)
    p = {k: (C.number(v) if valid else None) for k, v in zip(NUMBER_KEYS, nums)}
    with C.model_warnings() as caught:
        warn_small_rotation(pbc.a_bc, stacklevel=2)
    p["warnings"] = caught if valid else []
    spans = [C.number(v) if valid else None for v in pbc.spans]
    p["spans_mm"] = {"forward": spans[0], "backward": spans[1]}
    p["half_cycles"] = 2 * int(pbc.pairs)
    p.update(M.pad_fields(shape, pbc.cycle, valid))
    return p


def _run_path(args, shape, contacts, load, motion) -> int:
    from ..geometry import pad_names
    from ..path_base_cycle import path_base_cycle_inputs

    refuse_ellipse(args, motion)
    pbc = exported.call("cycle-path", _path_program(),
                        path_base_cycle_inputs(shape, args.mu, motion, contacts, load))
    status = C.status_name(pbc)
    p = path_payload(pbc, shape)
    echo = M.motion_echo(args, motion) if args.ibpa is not None or args.motion is not None else None
    reason = C.status_reason(status, contacts, load)
    if status == "unreachable":  # the history exists; a half of the Base-Cycle does not end
        reason = ("moving along this path one way or the other never brings every pad to slip "
                  "(the pads stay inside their friction cones, take turns to stick and slip, or "
                  "one opens first): no Base-Cycle; the exact cycles at an amplitude: jaxdamp "
                  "amplitude with the same flags and --psi-a MRAD")
    shape_echo = C.shape_echo(shape)
    if args.damper == "wedge":  # R1, R2 at +-b from the right flank's midpoint; no curved pad
        shape_echo.update(br_over_hr=None, br2_over_hr=C.number(shape.br2_over_hr))
    doc = C.document(status, p, reason=reason,
                     shape=shape_echo, damper=args.damper, pads=list(pad_names(shape)),
                     mu=args.mu, contacts=C.contacts_echo(contacts), load=C.load_echo(load),
                     motion=echo)
    damper = (f"wedge R1, R2 | L1, L2 (2b/h_R = {float(shape.br2_over_hr):g})"
              if args.damper == "wedge" else "curved-flat R1 | L1, L2")
    head = (f"Base-Cycle, {M.motion_text(echo)}, {damper}, mu = {args.mu:g}, "
            f"kn = {C.k_text(args.kn)} N/mm, kt = {C.k_text(args.kt)} N/mm, F_D = {args.fd:g} N")
    if p["psi_bc_mrad"] is None:
        C.emit(args, doc, head + "\n  no cycle (the status above says why)")
        return 0
    # Rounded before printing, plus 0.0: a zero-width loop's k_Im of -4e-28 prints as 0.0.
    fixed = lambda v, digits: f"{round(v, digits) + 0.0:.{digits}f}"  # noqa: E731
    lines = [head,
             f"  a_fs = {p['psi_fs_mrad']:.4f} mrad   k_Re,fs = {fixed(p['k_re_fs'], 1)} N mm/mrad",
             f"  a_BC = {p['psi_bc_mrad']:.4f} mrad   k_Re,BC = {fixed(p['k_re_bc'], 1)}   "
             f"k_Im,BC = {fixed(p['k_im_bc'], 1)} N mm/mrad   (mrad of "
             + ("the left-hand blade's rotation)" if args.ibpa is not None else
                "the path's parameter)" if args.motion is not None else "psi)"),
             f"  spans: forward {p['spans_mm']['forward']:.5f} mm, backward "
             f"{p['spans_mm']['backward']:.5f} mm, half-cycles run: {p['half_cycles']}",
             *(f"  WARNING: {w}" for w in p["warnings"]),
             f"  energy per cycle (N mm): total {fixed(p['dissipated_energy_nmm'], 3)}   "
             + "  ".join(f"{k} {fixed(v, 3)}" for k, v in p["energy_nmm"].items()),
             "  slip fraction: " + "  ".join(f"{k} {v:.3f}" for k, v in p["slip_fraction"].items()),
             "  open fraction: " + "  ".join(f"{k} {v:.3f}" for k, v in p["open_fraction"].items()),
             "  transitions (tau of the period, deg):"]
    names = pad_names(shape)
    for t in p["tracts"]:
        lines.append(f"    {t['tau_start_deg']:7.2f} - {t['tau_end_deg']:7.2f}   "
                     + "  ".join(f"{n} {t[n]:5}" for n in names))
    C.emit(args, doc, "\n".join(lines))
    return 0


def run(args) -> int:
    from ..motion import in_phase_motion
    from ..params import prepare_inputs

    contacts, load = C.contacts_from_args(args), C.load_from_args(args)  # --mu resolved here too
    wedge = args.damper == "wedge"
    shape = C.damper_from_args(args, C.shape_from_args(args, need_br=not wedge))
    prepare_inputs(shape, args.mu, contacts, load, wedge_ok=wedge)
    motion = M.motion_from_args(args, load)
    # The paper's Base-Cycle where it is defined (the curved-flat damper in-phase: --ibpa 0 is
    # that path exactly); a wedge, or any other straight path, the same construction on the
    # tract engine (jaxdamp.path_base_cycle).
    if wedge or not (motion is None or (args.ibpa is not None and args.ibpa % 360.0 == 0.0)):
        return _run_path(args, shape, contacts, load,
                         in_phase_motion(load.q_star) if motion is None else motion)
    # A saved program (exported.call): a repeat call neither traces nor lowers it, which was
    # 2.9 s of a 3.6 s repeat (benchmarks/results/compile_costs.json).
    results = exported.call("cycle", cycle_program(), prepare_inputs(shape, args.mu, contacts, load))
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


__all__ = ["NUMBER_KEYS", "register", "cycle_program", "cycle_payload", "path_payload", "run"]
