"""`jaxdamp sweep`: a theta_L x theta_R x mu grid; heatmaps, sweep.npz and sweep.json.

Before any computing the size is estimated (memory and time) and printed on stderr; beyond
MAX_DESIGNS designs or MAX_BYTES the sweep is refused unless --force. The printed summary and
sweep.json's "summary" are one dict."""

from __future__ import annotations

import sys

import numpy as np

from . import common as C

MAX_DESIGNS = 2_000_000
MAX_BYTES = 2 * 1024**3
# Host memory per design: the DesignSummary (9 float64, 3 bool, 1 int64 = 83 B) held about three
# times (chunks, concatenation, reshape), the batched inputs (14 float64 = 112 B) twice, and
# sweep.json: ~15 per-point values as Python floats in lists (~32 B each) plus their JSON text
# (~20 B each) and json.dumps' intermediate copy.
BYTES_PER_DESIGN = 3 * 83 + 2 * 112 + 15 * (32 + 2 * 20)
# Device working set per design of one compiled chunk (XLA temp + arguments + outputs): jax's
# memory_analysis of the batched solver at 1024 designs on CPU gives 3.5 MB temp + 0.17 MB in/out,
# 3.6 kB per design; doubled for the second (max_pairs) stage and other backends.
CHUNK_BYTES_PER_DESIGN = 8 * 1024
# Conservative throughput per device (benchmarks/results/batch.json measures ~9e4 designs/s per
# CPU device at chunk 1024) and compile time of the batched solver on a slow CPU.
DESIGNS_PER_S_PER_DEVICE = 5e4
COMPILE_S = 30.0


def register(sub) -> None:
    p = sub.add_parser("sweep", help="theta_L x theta_R x mu grid: heatmaps of psi_BC, k_Im,BC, w_M "
                                     "and the liftoff region, plus a data file")
    p.add_argument("--theta-l", default="40:90:11", help="theta_L values, deg: 'a,b,c' or "
                   "'start:stop:count' (default 40:90:11)")
    p.add_argument("--theta-r", default="40:90:11", help="theta_R values, deg (default 40:90:11)")
    p.add_argument("--mu", default="0.3,0.5,0.7", help="friction coefficients (default 0.3,0.5,0.7)")
    p.add_argument("--br", default="centred", help="b_R/h_R in [-0.5, 0.5], or 'centred' (the "
                   "paper's rule at --mu-max; default)")
    p.add_argument("--mu-max", type=float, default=None,
                   help="mu of the centring rule, in (0, 5] (default: the largest --mu)")
    p.add_argument("--bl2", type=float, default=0.8, help="2b_L/h_L, in (0, 1] (default 0.8)")
    C.add_contact_args(p)
    p.add_argument("--out", required=True, help="output directory (created if missing)")
    p.add_argument("--force", action="store_true",
                   help=f"run even beyond {MAX_DESIGNS:.0e} designs or {MAX_BYTES / 1024**3:g} GB estimated")
    C.add_json_arg(p)
    C.add_progress_arg(p)
    p.set_defaults(func=run)


def parse_values(text: str, flag: str) -> np.ndarray:
    """'a,b,c' or 'start:stop:count' (inclusive linspace, count in [1, 1e7])."""
    try:
        if ":" in text:
            start, stop, count = text.split(":")
            count = int(count)
            if not 1 <= count <= 10_000_000:
                raise ValueError
            return np.linspace(float(start), float(stop), count)
        values = np.array([float(v) for v in text.split(",") if v.strip()])
        if values.size == 0:
            raise ValueError
        return values
    except ValueError:
        raise C.CliError(f"{flag} must be 'a,b,c' or 'start:stop:count' (count in [1, 1e7]); "
                         f"got {text!r}") from None


def estimate(n_designs: int, n_devices: int, chunk: int) -> dict:
    """Memory (bytes) and time (s) a sweep of n_designs is expected to need."""
    working = CHUNK_BYTES_PER_DESIGN * min(n_designs, chunk * n_devices)
    return {"designs": int(n_designs), "devices": int(n_devices),
            "memory_bytes": int(BYTES_PER_DESIGN * n_designs + working),
            "time_s": COMPILE_S + n_designs / (DESIGNS_PER_S_PER_DEVICE * n_devices)}


def summary_of(res) -> dict:
    """Counts per status of the sweep (the printed summary and sweep.json's 'summary')."""
    from ..plotting.sweep import STATUS, status_codes

    from ..status import RESULTS

    codes = status_codes(res)
    counts = {name.replace(" ", "_").replace("b_R_undefined", "br_undefined"): int((codes == i).sum())
              for i, name in enumerate(STATUS)}
    # The heatmap's "not converged" class, split by status (points with a defined b_R).
    status = np.asarray(res.summary.status)[codes != 3]
    counts["not_converged"] = int(np.sum(status == RESULTS.not_converged))
    counts.update(singular=int(np.sum(status == RESULTS.singular)),
                  ill_conditioned=int(np.sum(status == RESULTS.ill_conditioned)))
    return {"points": int(codes.size), **counts}


def run(args) -> int:
    import jax

    from ..batch import check_sweep_inputs, device_chunk, device_mesh, sweep, values_chunk
    from ..plotting.sweep import write_sweep

    tl = parse_values(args.theta_l, "--theta-l")
    tr = parse_values(args.theta_r, "--theta-r")
    mus = parse_values(args.mu, "--mu")
    br = C.parse_br(args.br)
    contacts = C.contacts_from_args(args, shared=True)
    check_sweep_inputs(tl, tr, mus, br, mu_max=args.mu_max, bl2_over_hl=args.bl2, contacts=contacts)
    n = tl.size * tr.size * mus.size
    # The chunk evaluate_designs takes (its values chunk on CPU, else the platform's default).
    est = estimate(n, len(jax.devices()), values_chunk() or device_chunk(device_mesh()))
    gb = est["memory_bytes"] / 1024**3
    line = (f"sweep: {n} designs on {est['devices']} device(s): about {gb:.2g} GB of memory and "
            f"{est['time_s']:.0f} s")
    if (n > MAX_DESIGNS or est["memory_bytes"] > MAX_BYTES) and not args.force:
        raise C.CliError(f"{line}, beyond the limit of {MAX_DESIGNS:.0e} designs or "
                         f"{MAX_BYTES / 1024**3:g} GB: use a coarser grid or --force")
    out = C.check_output_dir("--out", args.out)  # created: before any work, after the size check
    print(line, file=sys.stderr)
    bar = C.progress_bar(args, total=n, desc="sweep", unit="design")
    try:
        res = sweep(tl, tr, mus, br, mu_max=args.mu_max, bl2_over_hl=args.bl2, contacts=contacts,
                    progress=bar.update)
    finally:
        bar.close()
    summary = summary_of(res)
    # Liftoff points are results of a sweep; a point with no valid cycle for another reason is not.
    status = next((k for k in ("ill_conditioned", "singular", "not_converged") if summary[k]), "ok")
    inputs = {"theta_l_deg": tl, "theta_r_deg": tr, "mu": mus, "br_over_hr": br,
              "mu_max": res.mu_max, "bl2_over_hl": args.bl2, "contacts": C.contacts_echo(contacts),
              "load": C.load_echo(res_load())}
    head = C.document(status, {"inputs": inputs, "summary": summary, "estimate": est},
                      reason=C.status_reason(status, contacts, res_load()))
    files = write_sweep(res, out, extra=head)
    doc = {**head, **summary, "files": [str(f) for f in files]}
    text = (f"{summary['points']} designs: {summary['valid']} valid, {summary['liftoff']} liftoff, "
            f"{summary['not_converged']} not converged, {summary['singular']} singular, "
            f"{summary['ill_conditioned']} ill-conditioned, "
            f"{summary['br_undefined']} without a centring b_R\n"
            + "\n".join(f"wrote {f}" for f in files))
    C.emit(args, doc, text)
    return 0


def res_load():
    from ..params import LoadCase

    return LoadCase()  # sweep runs the reference load case


__all__ = ["MAX_DESIGNS", "MAX_BYTES", "BYTES_PER_DESIGN", "CHUNK_BYTES_PER_DESIGN",
           "DESIGNS_PER_S_PER_DEVICE", "COMPILE_S", "register", "parse_values", "estimate",
           "summary_of", "run", "res_load"]
