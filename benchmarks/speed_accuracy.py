"""Speed versus accuracy: the direct method against the conventional ones (issue 6).

For 60sym, 74R and 90R (mu = 0.5, the reference contact pair) this measures, in one run on one
machine, the error of k_Re,BC, k_Im,BC and psi_BC against the direct method's exact values versus
warm wall time (jit compilation excluded, median of repeats) for

* time marching with incremental return mapping (`jaxdamp.baselines.timemarch`) over N steps per half-cycle,
* HBM-AFT (`jaxdamp.baselines.hbm`) at the exact psi_BC over Nt samples per period, 3 and 8 periods,
* a tanh-regularised friction law evaluated the HBM-AFT way (`jaxdamp.baselines.regularized`) over eps,
* the direct method, one design per call and batched (`jd.evaluate_designs`).

The time marcher's step is h = S / (N + 1/2), with S the exact longer half-span: the marcher is
handed an ideal step size and a gross-slip step that falls half-way through a step (the average
case). HBM-AFT is handed the exact amplitude psi_BC, which it cannot find by itself. 90R's k_Im is
~0, so its k_Im error is measured relative to k_Re,BC (all other errors are relative to the value
itself). A method's "time to 1e-4" is the log-log interpolated wall time at which its k_Im error
falls below 1e-4 and stays below for every finer setting of the sweep; the speedup is that time
over the direct method's single-design time.

    python benchmarks/speed_accuracy.py            # full run: results/speed_accuracy.json and
                                                   # docs/speed_accuracy.png
    python benchmarks/speed_accuracy.py --quick --json   # reduced (< 5 min), prints the summary

The machine is described in the JSON (lscpu, platform, load average before and after the run).

Every method runs with JAX's CPU calls executed on the calling thread
(jax_cpu_enable_async_dispatch = False): by default the CPU client hands each call to a worker
thread, which adds a hand-off of the order of 50-100 us to every call and would dominate the
timing of sub-millisecond calls. `--async-dispatch` keeps JAX's default instead.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)
# Read by the CPU client when it is created (on the first computation, which importing jaxdamp
# already makes), so it is set here; see the module docstring.
ASYNC_DISPATCH = "--async-dispatch" in sys.argv[1:]
jax.config.update("jax_cpu_enable_async_dispatch", ASYNC_DISPATCH)

import jaxdamp as jd  # noqa: E402
from jaxdamp import base_cycle_kernel  # noqa: E402
from jaxdamp.baselines.hbm import hbm_aft_kernel  # noqa: E402
from jaxdamp.baselines.regularized import regularized_aft_kernel  # noqa: E402
from jaxdamp.baselines.timemarch import time_march_kernel  # noqa: E402
from bench_batch import two_device_throughput  # noqa: E402
from bench_common import machine as common_machine, time_below, warm_times  # noqa: E402

OUT = Path(__file__).parent / "results"
DOCS = Path(__file__).resolve().parent.parent / "docs"  # the full run's figure (docs/performance.md)
CASES = (("60sym", 0.5), ("74R", 0.5), ("90R", 0.5))
TARGET = 1e-4

FULL = dict(tm_steps=(250, 500, 1000, 2000, 4000, 8000, 16000, 32000, 64000),
            hbm_nt=(16, 32, 64, 128, 256, 512, 1024, 2048, 4096), hbm_periods=(3, 8),
            reg_eps=(1e-2, 1e-3, 1e-4, 1e-5), reg_nt=512, batch=20000, repeats=7, direct_repeats=300)
QUICK = dict(tm_steps=(1000, 4000, 16000, 32000), hbm_nt=(16, 64, 256, 1024), hbm_periods=(3, 8),
             reg_eps=(1e-2, 1e-3, 1e-4), reg_nt=256, batch=4000, repeats=3, direct_repeats=100)


def machine() -> dict:
    """bench_common's machine record, with lscpu's description of the CPU (and cpu_count, which
    notebook 04 reads)."""
    info = dict(common_machine(), cpu_count=os.cpu_count())
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10).stdout
        keep = ("Model name", "CPU(s)", "Thread(s) per core", "Core(s) per socket", "CPU MHz",
                "L2 cache", "L3 cache", "Hypervisor vendor")
        info["lscpu"] = {k.strip(): v.strip() for k, v in (line.split(":", 1) for line in out.splitlines()
                                                           if ":" in line) if k.strip() in keep}
    except (OSError, subprocess.SubprocessError):
        info["lscpu"] = None
    return info


def timed(fn, *args, repeats=5, budget_s=0.5, max_repeats=200):
    """(median warm wall time in s, result): one call to compile, then at least `repeats` timed calls,
    more (up to max_repeats) while their total stays under budget_s (a shared machine is noisy)."""
    times, out = warm_times(fn, *args, repeats=repeats, budget_s=budget_s, max_repeats=max_repeats)
    return float(np.median(times)), out


def arrays(shape):
    return jd.DamperShape(*(jnp.asarray(v, float) for v in shape[:4]))


CONTACTS = jd.Contacts(jnp.asarray(jd.REFERENCE_KN), jnp.asarray(jd.REFERENCE_KT))
LOAD = jd.LoadCase(*(jnp.asarray(v, float) for v in (1000.0, 100.0, 0.0)))


@jax.jit
def direct_five(shape, mu):
    return jnp.stack(jd.five_numbers(base_cycle_kernel(shape, mu, CONTACTS, LOAD)).numbers())


def errors(exact, k_re=None, k_im=None, psi_bc=None, psi_fs=None, k_re_fs=None):
    """Relative errors against the direct values; k_Im relative to k_Re where k_Im ~ 0 (90R)."""
    scale_im = abs(exact["k_im_bc"]) if abs(exact["k_im_bc"]) > 1e-3 * abs(exact["k_re_bc"]) \
        else abs(exact["k_re_bc"])
    out = {}
    for key, val, scale in (("k_re_bc", k_re, abs(exact["k_re_bc"])), ("k_im_bc", k_im, scale_im),
                            ("psi_bc", psi_bc, abs(exact["psi_bc"])), ("psi_fs", psi_fs, abs(exact["psi_fs"])),
                            ("k_re_fs", k_re_fs, abs(exact["k_re_fs"]))):
        if val is not None:
            out[f"err_{key}"] = float(abs(float(val) - exact[key]) / scale)
    return out


def time_to_target(points, key="err_k_im_bc", target=TARGET):
    """Interpolated time at which the error falls below target and stays below (points ordered from
    cheap to accurate). Returns (time or None, how: 'interpolated' / 'first point' / 'not reached')."""
    ok = [p for p in points if p.get("flagged") is False]
    if not ok:
        return None, "not reached"
    return time_below([p["time_s"] for p in ok], [p[key] for p in ok], target,
                      "first point (upper bound)")


def run(cfg, progress=print):
    res = {"machine": machine(), "load_average_start": list(os.getloadavg()), "config": cfg,
           "target_rel_error": TARGET, "cases": {}}
    # Direct method: one design per call, and batched.
    for name, mu in CASES:
        shape = arrays(jd.family_shape(name))
        t, five = timed(direct_five, shape, jnp.asarray(mu), repeats=cfg["direct_repeats"])
        exact = dict(zip(("psi_fs", "k_re_fs", "psi_bc", "k_re_bc", "k_im_bc"), map(float, five)))
        bc = jd.base_cycle(jd.family_shape(name), mu, CONTACTS, LOAD)
        span = max(float(bc.forward.span), float(bc.backward.span))
        res["cases"][f"{name}@{mu}"] = {"exact": exact, "span_mm": span, "direct_single_s": t,
                                        "time_marching": [], "hbm_aft": [], "regularized": []}
        progress(f"direct {name}: {t * 1e3:.3f} ms")
    # The floor of any single jitted call with the same arguments (dispatch, no work).
    shape = arrays(jd.family_shape("60sym"))
    res["dispatch_floor_s"], _ = timed(jax.jit(lambda s, m: m * s.theta_l), shape, jnp.asarray(0.5),
                                       repeats=cfg["direct_repeats"])
    # Batched: what a user with many designs runs, jd.evaluate_designs sharded over both cores
    # (2 host devices), with JAX's default asynchronous dispatch that overlaps the host's
    # preparation of one chunk with the computation of the previous one; in a fresh process.
    n = cfg["batch"]
    two = two_device_throughput([n], chunks=False)
    rate = two["designs_per_s"][str(n)]
    res["direct_batch"] = {"size": n, "time_s": n / rate, "designs_per_s": rate,
                           "devices": two["devices"],
                           "designs": "random theta_l, theta_r in [35, 90] deg, b_R/h_R in [-0.3, 0.4], "
                                      "mu in [0.1, 0.9]; jd.evaluate_designs over 2 host devices "
                                      "(chunked, two-stage): five numbers, w_i and flags"}
    progress(f"direct batch: {rate:.0f} designs/s on {two['devices']} host devices")

    # Time marching over N steps per half-cycle.
    for N in cfg["tm_steps"]:
        fn = jax.jit(lambda s, m, h, N=N: time_march_kernel(s, m, CONTACTS, LOAD, h,
                                                      n_steps=int(N * 1.02) + 4))
        for key, case in res["cases"].items():
            name, mu = key.split("@")
            h = case["span_mm"] / (N + 0.5)
            reps = cfg["repeats"] if N <= 8000 else 3
            t, r = timed(fn, arrays(jd.family_shape(name)), jnp.asarray(float(mu)), jnp.asarray(h),
                         repeats=reps)
            flagged = jd.RESULTS.name_of(r.status) != "ok"
            case["time_marching"].append(dict(
                N=N, h_mm=h, time_s=t, flagged=flagged, half_cycles=int(r.half_cycles),
                **errors(case["exact"], r.k_re_bc, r.k_im_bc, r.psi_bc, r.psi_fs, r.k_re_fs)))
        progress(f"time marching N={N} done")

    # HBM-AFT at the exact psi_BC over Nt samples per period.
    for periods in cfg["hbm_periods"]:
        for nt in cfg["hbm_nt"]:
            fn = jax.jit(lambda s, m, a, nt=nt, P=periods: hbm_aft_kernel(s, m, CONTACTS, LOAD, a, n_time=nt,
                                                                    n_periods=P))
            for key, case in res["cases"].items():
                name, mu = key.split("@")
                t, r = timed(fn, arrays(jd.family_shape(name)), jnp.asarray(float(mu)),
                             jnp.asarray(case["exact"]["psi_bc"]), repeats=cfg["repeats"])
                case["hbm_aft"].append(dict(
                    Nt=nt, periods=periods, time_s=t, flagged=jd.RESULTS.name_of(r.status) != "ok",
                    periodicity=float(r.periodicity), **errors(case["exact"], r.k_re, r.k_im)))
            progress(f"HBM-AFT Nt={nt} P={periods} done")

    # tanh-regularised friction, HBM-AFT evaluation, over eps.
    for eps in cfg["reg_eps"]:
        nt = cfg["reg_nt"]
        fn = jax.jit(lambda s, m, a, e, nt=nt: regularized_aft_kernel(s, m, CONTACTS, LOAD, a, e, n_time=nt))
        for key, case in res["cases"].items():
            name, mu = key.split("@")
            t, r = timed(fn, arrays(jd.family_shape(name)), jnp.asarray(float(mu)),
                         jnp.asarray(case["exact"]["psi_bc"]), jnp.asarray(eps),
                         repeats=max(1, cfg["repeats"] // 2))
            case["regularized"].append(dict(eps=eps, Nt=nt, time_s=t, flagged=jd.RESULTS.name_of(r.status) != "ok",
                                            **errors(case["exact"], r.k_re, r.k_im)))
        progress(f"regularized eps={eps:g} done")

    # Where the direct method interpolates: between psi_fs and psi_BC (microslip) the paper's (and
    # jaxdamp's) k_Re, k_Im are a linear interpolation, not a computed loop. Compare with HBM-AFT.
    fn = jax.jit(lambda s, m, a: hbm_aft_kernel(s, m, CONTACTS, LOAD, a, n_time=2048, n_periods=8))
    for key, case in res["cases"].items():
        name, mu = key.split("@")
        ex = case["exact"]
        psi_m = 0.5 * (ex["psi_fs"] + ex["psi_bc"])
        r = fn(arrays(jd.family_shape(name)), jnp.asarray(float(mu)), jnp.asarray(psi_m))
        bc = jd.base_cycle(jd.family_shape(name), float(mu), CONTACTS, LOAD)
        k_re, k_im = (float(x) for x in jd.complex_stiffness(bc, psi_m, method="interpolated"))
        case["microslip_midpoint"] = {
            "psi_a_mrad": psi_m, "direct_interpolated": [k_re, k_im],
            "hbm_aft_Nt2048_P8": [float(r.k_re), float(r.k_im)], "hbm_status": jd.RESULTS.name_of(r.status),
            "rel_diff_k_re": abs(k_re - float(r.k_re)) / abs(float(r.k_re)),
            "rel_diff_k_im": abs(k_im - float(r.k_im)) / max(abs(float(r.k_im)), 1e-3 * abs(float(r.k_re)))}
    progress("microslip midpoint done")

    # Time to reach the target on k_Im, and speedups of the direct method.
    summary = {}
    for key, case in res["cases"].items():
        t_tm, how_tm = time_to_target(case["time_marching"])
        hbm_times = []
        for periods in cfg["hbm_periods"]:
            pts = [p for p in case["hbm_aft"] if p["periods"] == periods]
            t, how = time_to_target(pts)
            hbm_times.append((t, how, periods))
        reached = [x for x in hbm_times if x[0] is not None]
        t_hbm, how_hbm, p_hbm = min(reached) if reached else (None, "not reached", None)
        t_reg, how_reg = time_to_target(case["regularized"])
        d = case["direct_single_s"]
        case["time_to_target_s"] = {"time_marching": t_tm, "time_marching_how": how_tm,
                                    "hbm_aft": t_hbm, "hbm_aft_how": how_hbm, "hbm_aft_periods": p_hbm,
                                    "regularized": t_reg, "regularized_how": how_reg}
        case["speedup"] = {k: (None if v is None else v / d) for k, v in
                           (("time_marching", t_tm), ("hbm_aft", t_hbm), ("regularized", t_reg))}
        summary[key] = case["speedup"]

    def worst(method):
        vals = [s[method] for s in summary.values()]
        return None if any(v is None for v in vals) else float(min(vals))

    res["summary"] = {
        "speedup_vs_time_marching_at_1e-4": worst("time_marching"),
        "speedup_vs_hbm_aft_at_1e-4": worst("hbm_aft"),
        "speedup_vs_regularized_at_1e-4": worst("regularized"),
        "batch_designs_per_s": res["direct_batch"]["designs_per_s"],
        "direct_single_ms": {k: 1e3 * c["direct_single_s"] for k, c in res["cases"].items()},
        "dispatch_floor_ms": 1e3 * res["dispatch_floor_s"],
        "speedups_per_case": summary,
        "note": "speedups are the worst case over 60sym, 74R, 90R (mu = 0.5); None = the method did "
                "not reach 1e-4 relative error on k_Im in the sweep",
        "targets_met": {},
    }
    s = res["summary"]
    s["targets_met"] = {
        "time_marching_1000x": s["speedup_vs_time_marching_at_1e-4"] is not None
        and s["speedup_vs_time_marching_at_1e-4"] >= 1000,
        "hbm_aft_1000x": s["speedup_vs_hbm_aft_at_1e-4"] is not None and s["speedup_vs_hbm_aft_at_1e-4"] >= 1000,
        "batch_100k_per_s": s["batch_designs_per_s"] >= 1e5,
    }
    res["load_average_end"] = list(os.getloadavg())
    return res


def plot(res, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases = list(res["cases"])
    fig, axes = plt.subplots(2, len(cases), figsize=(5.2 * len(cases), 8.5), squeeze=False)
    floor = 1e-13
    for col, key in enumerate(cases):
        case = res["cases"][key]
        for row, (err, label) in enumerate((("err_k_im_bc", "k_Im,BC"), ("err_k_re_bc", "k_Re,BC"))):
            ax = axes[row, col]

            def series(points, fmt, name, knob):
                pts = [p for p in points if err in p]
                if not pts:
                    return
                t = [p["time_s"] for p in pts]
                e = [max(p[err], floor) for p in pts]
                ax.loglog(t, e, fmt, label=name, ms=5)
                for p, ti, ei in zip(pts, t, e):
                    if p.get("flagged"):
                        ax.plot(ti, ei, "x", color="k", ms=8)
                if row == 0:
                    for p, ti, ei in list(zip(pts, t, e))[:: max(1, len(pts) // 4)]:
                        ax.annotate(f"{p[knob]:g}", (ti, ei), fontsize=6, xytext=(3, 3),
                                    textcoords="offset points")

            series(case["time_marching"], "o-", "time marching (N steps/half)", "N")
            for periods, fmt in zip(res["config"]["hbm_periods"], ("s-", "s--")):
                series([p for p in case["hbm_aft"] if p["periods"] == periods], fmt,
                       f"HBM-AFT, {periods} periods (Nt)", "Nt")
            series(case["regularized"], "^-", f"tanh-regularised AFT (eps), Nt={res['config']['reg_nt']}", "eps")
            d = case["direct_single_s"]
            ax.loglog([d], [floor], "*", color="C3", ms=14, label="direct, 1 design (exact)")
            per = res["direct_batch"]["time_s"] / res["direct_batch"]["size"]
            ax.loglog([per], [floor], "P", color="C3", ms=10, label="direct, batched (per design)")
            ax.axhline(TARGET, color="grey", lw=0.8, ls=":")
            ax.set_xlabel("warm wall time per design (s)")
            ax.set_ylabel(f"relative error of {label}")
            sp = case["speedup"]
            txt = ", ".join(f"{k.replace('_', ' ')} {v:.0f}x" if v is not None else f"{k.replace('_', ' ')} n/r"
                            for k, v in sp.items())
            ax.set_title(f"{key}: {label}" + (f"\nspeedup at 1e-4: {txt}" if row == 0 else ""), fontsize=8)
            ax.grid(True, which="both", alpha=0.2)
    axes[0, 0].legend(fontsize=6, loc="lower left")
    m = res["machine"]
    cpu = (m.get("lscpu") or {}).get("Model name", platform.processor())
    fig.suptitle(f"jaxdamp speed vs accuracy ({cpu}, {m['cpu_count']} cores, jax {m['jax']}; "
                 f"load avg {res['load_average_start'][0]:.1f}); x = flagged "
                 f"(not periodic / not closed); direct shown at the plot floor (closed form)", fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="reduced sweep (< 5 min)")
    ap.add_argument("--json", action="store_true", help="print only the summary JSON on stdout")
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--async-dispatch", action="store_true",
                    help="keep JAX's default asynchronous CPU dispatch (a thread hand-off per call)")
    args = ap.parse_args(argv)
    if args.async_dispatch != ASYNC_DISPATCH:
        raise SystemExit("--async-dispatch must be given on the command line (it is read at import)")
    cfg = dict(QUICK if args.quick else FULL, async_dispatch=args.async_dispatch)
    say = (lambda *a: print(*a, file=sys.stderr)) if args.json else print
    t0 = time.perf_counter()
    res = run(cfg, progress=say)
    res["wall_time_s"] = time.perf_counter() - t0
    stem = "speed_accuracy_quick" if args.quick else "speed_accuracy"
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / f"{stem}.json").write_text(json.dumps(res, indent=2))
    # the full run's figure is the docs' copy; a quick run's, or one with --out, stays beside its JSON
    to_docs = args.out.resolve() == OUT.resolve() and not args.quick
    png = (DOCS if to_docs else args.out) / f"{stem}.png"
    plot(res, png)
    if args.json:
        print(json.dumps(res["summary"], indent=2))
    else:
        print(json.dumps(res["summary"], indent=2))
        print(f"wrote {args.out / stem}.json and {png} in {res['wall_time_s']:.0f} s")


if __name__ == "__main__":
    main()
