"""`jaxdamp response --uncertainty`: one design's peak distribution over mu, per-pair kn and kt,
and F_D by Monte Carlo on the exact curve (`jaxdamp.uncertainty`): quantiles of A*/F per force and
the exceedance probability of a peak limit."""

from __future__ import annotations

from . import common as C

__all__ = ["add_uncertainty_args", "report"]


def add_uncertainty_args(p) -> None:
    g = p.add_argument_group("uncertainty (with --uncertainty: Monte Carlo over mu, kn, kt, F_D)")
    g.add_argument("--uncertainty", action="store_true",
                   help="report the distribution of A*/F over the ranges below instead of one peak")
    g.add_argument("--samples", type=int, default=1000,
                   help="Monte Carlo samples, an integer in [2, 1000000] (default 1000)")
    g.add_argument("--mu-range", default="0.3:0.7", metavar="LOW:HIGH",
                   help="mu uniform on LOW:HIGH, 0 < LOW <= HIGH <= 5 (default 0.3:0.7)")
    g.add_argument("--fd-spread", type=float, default=0.2,
                   help="F_D uniform on F_D (1 -/+ spread), spread in [0, 1) (default 0.2)")
    g.add_argument("--kn-range", type=float, default=2.0,
                   help="kn log-uniform within this factor each way, per contact pair, in [1, 100] "
                        "(default 2)")
    g.add_argument("--kt-range", type=float, default=2.0,
                   help="kt likewise, in [1, 100] (default 2)")
    g.add_argument("--peak-limit-mm-per-n", type=float, default=None,
                   help="report the probability that A*/F exceeds this limit (mm/N, > 0)")
    g.add_argument("--seed", type=int, default=0, help="random seed (default 0)")


def _mu_range(text):
    try:
        lo, hi = (float(x) for x in str(text).split(":"))
    except ValueError:
        raise C.CliError(f"--mu-range must be LOW:HIGH with 0 < LOW <= HIGH <= 5; got {text!r}") from None
    return lo, hi


def report(args, scene, forces) -> int:
    """Check the flags, sample around the Scene (`response.prepare_scene`: checked already, and not
    again), print or emit the document; exit code."""
    import jax
    import numpy as np

    from ..status import RESULTS
    from ..uncertainty import Uncertainty, peak_distribution, sample_scenarios, validate_uncertainty

    if not 2 <= args.samples <= 1_000_000:
        raise C.CliError(f"--samples must be an integer in [2, 1000000]; got {args.samples}")
    limit = args.peak_limit_mm_per_n
    if limit is not None and not limit > 0:
        raise C.CliError(f"--peak-limit-mm-per-n must be > 0 mm/N; got {limit:g}")
    try:
        u = validate_uncertainty(Uncertainty(*_mu_range(args.mu_range), args.fd_spread,
                                             args.kn_range, args.kt_range))
    except ValueError as e:
        flag = {"mu range": "--mu-range", "fd_spread": "--fd-spread", "kn_factor": "--kn-range",
                "kt_factor": "--kt-range"}
        msg = str(e)
        for k, v in flag.items():
            msg = msg.replace(k, v, 1) if msg.startswith(k) else msg
        raise C.CliError(msg) from None
    scen = sample_scenarios(jax.random.PRNGKey(args.seed), args.samples, u, scene.contacts,
                            scene.load)
    history = "gross_slip" if args.initial == "gross_slip" else "assembly"
    bar = C.progress_bar(args, desc="samples", unit="chunk")
    try:
        d = peak_distribution(scene, scen, force_n=np.asarray(forces), history=history,
                              levels=(0.05, 0.5, 0.95), limit_mm_per_n=limit,
                              progress=lambda k: bar.update(1))
    finally:
        bar.close()
    bad = d.status[d.status != RESULTS.ok]
    status = "ok" if bad.size == 0 else RESULTS(int(bad.max())).name
    payload = {"uncertainty": u._asdict(), "samples": args.samples, "history": history,
               "force_n": list(map(float, forces)), "n_ok": d.n_ok,
               "quantile_levels": [0.05, 0.5, 0.95],
               "quantiles_mm_per_n": [[C.number(x) for x in row] for row in d.quantiles],
               "worst_mm_per_n": [C.number(x) for x in d.worst],
               "peak_limit_mm_per_n": limit,
               "exceedance": None if limit is None else [C.number(x) for x in d.exceedance]}
    doc = C.document(status, payload)
    lines = [f"A*/F over {d.n_ok} of {args.samples} samples (mu {u.mu_low:g}-{u.mu_high:g}, F_D "
             f"+/-{u.fd_spread:g}, kn x/÷{u.kn_factor:g}, kt x/÷{u.kt_factor:g} per pair, "
             f"{history} history), mm/N",
             "  F (N)      q05      q50      q95    worst" + ("  P(>limit)" if limit else "")]
    for j, f in enumerate(forces):
        q = d.quantiles[:, j]
        lines.append(f"  {f:6.3g} {q[0]:8.4f} {q[1]:8.4f} {q[2]:8.4f} {d.worst[j]:8.4f}"
                     + (f"  {d.exceedance[j]:8.4f}" if limit else ""))
    C.emit(args, doc, "\n".join(lines))
    return 0
