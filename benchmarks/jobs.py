"""Speed on the jobs users run (issue 15): the direct method against the standard techniques.

Every job is measured in one run on one machine: float64, both sides jit-compiled and warm, equal
batching (`jax.vmap` on both sides, the whole batch in one call), `block_until_ready`, median of
repeats, against a converged reference, with a time-vs-error (Pareto) chart.

Job 1, "one amplitude": k_Im at psi_BC.
  * direct: `jaxdamp.base_cycle_kernel` + `jaxdamp.five_numbers` (exact: no discretisation);
  * HBM-AFT handed the exact psi_BC (`jaxdamp.baselines.hbm_aft_kernel`), Nt samples per period,
    3 periods (as a friction-damper code evaluates a friction element at a given amplitude);
  * time marching (`jaxdamp.baselines.time_march_kernel`) with N steps per half-cycle, handed the
    ideal step h = S / (N + 1/2), S the exact longer half-span;
  for one design (60sym, mu 0.5) and for a batch of random designs (1000; 256 with --quick). The
  direct value is checked against a very fine HBM-AFT (Nt 4096 for one design, 2048 on a subset of
  the batch). Error = |k_Im - k_Im,direct| / max(|k_Im,direct|, 1e-3 |k_Re,BC|) per design; a batch
  reports its median (the ratio's basis) and 95th percentile. A competitor's time at 1e-4 is the
  log-log interpolation of its (time, median error) curve where the error crosses 1e-4 for the last
  time, or the time of a finer setting that is faster still (log-log extrapolation from the two
  finest settings, flagged, when the sweep does not reach 1e-4); the ratio is that time over the
  direct method's time for the same batch.

Jobs 2-4 (whole curve, forced response, gradient of the peak) are `benchmarks/jobs_layered.py`
(its full run writes results/jobs_layered.json and the Pareto charts docs/jobs_curve.png,
docs/jobs_response.png, docs/jobs_gradient.png); this script reports their summaries.

All calls run with JAX's async dispatch off (`jax_cpu_enable_async_dispatch = False`, both sides
alike): on CPU the default hands every call to a worker thread, a fixed cost that would dominate
sub-millisecond calls (benchmarks/results/cpu_runtime_options.json measures it).

    python benchmarks/jobs.py --quick --json   # reduced sizes (< 5 min), prints the summary
    python benchmarks/jobs.py                  # full: results/jobs.json, docs/jobs_one_amplitude.png
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_enable_async_dispatch", False)

import jaxdamp as jd  # noqa: E402
from jaxdamp.baselines import hbm_aft_kernel, time_march_kernel  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import use_measured_xla_flags, loadavg as load_averages, machine, warm_times  # noqa: E402

use_measured_xla_flags()  # before JAX starts: both sides of every comparison get it

OUT = Path(__file__).parent / "results"
TARGET = 1e-4

# Time marching costs ~N steps per half-cycle for every design: on 2 CPU cores a batch of 1000
# designs at N = 20000 takes minutes per call, so the batch sweep stops at tm_steps_batch and its
# time at 1e-4 is extrapolated (flagged) along its measured log-log slope (error ~ 1/N).
FULL = dict(designs=1000, hbm_nt=(16, 32, 64, 128, 256, 512, 1024),
            tm_steps=(100, 300, 1000, 3000, 10000, 20000), tm_steps_batch=(100, 300, 1000, 3000),
            check_nt=2048, check_designs=20, repeats=5, throughput_designs=32768, single_repeats=500)
QUICK = dict(designs=256, hbm_nt=(16, 64, 256), tm_steps=(300, 3000), tm_steps_batch=(300, 1000),
             check_nt=512, check_designs=2, repeats=3, throughput_designs=8192, single_repeats=200)


def timed(fn, *args, repeats=5):
    """(median warm wall time in s, (min, max), result): one call first so compilation is not timed."""
    times, out = warm_times(fn, *args, repeats=repeats)
    return float(np.median(times)), (float(min(times)), float(max(times))), out


def loadavg() -> float:
    return load_averages()[0]


# ---------------------------------------------------------------- the three methods, one design
def direct_one(design: jd.Design):
    """k_Re,BC, k_Im,BC, psi_BC (mrad), span (mm) and validity of one prepared design: exact."""
    bc = jd.base_cycle_kernel(*design)
    nums = jd.five_numbers(bc)
    span = jnp.maximum(bc.forward.span, bc.backward.span)
    ok = bc.status == jd.RESULTS.ok
    return nums.k_re_bc, nums.k_im_bc, nums.psi_bc, span, ok


def hbm_one(design: jd.Design, psi_bc, n_time: int):
    r = hbm_aft_kernel(*design, psi_bc, n_time=n_time)
    return r.k_im, r.status == jd.RESULTS.ok


def march_one(design: jd.Design, h, n_steps: int):
    r = time_march_kernel(*design, h, n_steps=int(n_steps * 1.02) + 4)
    return r.k_im_bc, r.status == jd.RESULTS.ok


def batched(fn, **static):
    return jax.jit(jax.vmap(lambda d, *a: fn(d, *a, **static)))


# ---------------------------------------------------------------- designs
def one_design() -> jd.Design:
    return jd.Design(jd.family_shape("60sym"), 0.5).prepared()


def random_valid_designs(n: int, seed: int = 0) -> jd.Design:
    """n random designs whose Base-Cycle converges without liftoff (the job is about dampers that
    work; liftoff designs have no k_Im to compare)."""
    rng = np.random.default_rng(seed)
    m = 4 * n
    shape = jd.DamperShape(rng.uniform(35, 90, m), rng.uniform(35, 90, m), rng.uniform(-0.3, 0.4, m),
                           np.full(m, 0.8))
    designs = jd.stack_designs(shape, rng.uniform(0.1, 0.9, m))
    s = jd.evaluate_designs(designs)
    good = np.nonzero(s.status == jd.RESULTS.ok)[0][:n]
    if good.size < n:
        raise RuntimeError(f"only {good.size} valid designs among {m}")
    return jax.tree_util.tree_map(lambda x: None if x is None else jnp.asarray(np.asarray(x)[good]),
                                  designs)


def rel_err(k_im, exact_im, exact_re):
    scale = np.maximum(np.abs(exact_im), 1e-3 * np.abs(exact_re))
    return np.abs(np.asarray(k_im) - exact_im) / scale


def time_at(points, target=TARGET):
    """(time at which the median error crosses `target`, extrapolated?) from (time, error) points
    ordered from coarse to fine; None when the errors do not decrease."""
    pts = [(t, max(e, 1e-300)) for t, e in points if np.isfinite(e)]
    # The crossing after which the error stays below target for every finer setting (errors of one
    # design are not monotone: a lucky cancellation at a coarse setting does not count).
    # A finer setting that is faster (batched Newton iterations can make a coarser one slower)
    # counts too: the time is the fastest way to 1e-4 on that part of the curve.
    above = [i for i, (_, e) in enumerate(pts) if e > target]
    if above and above[-1] + 1 < len(pts):
        (t0, e0), (t1, e1) = pts[above[-1]], pts[above[-1] + 1]
        f = np.log(target / e0) / np.log(e1 / e0)
        cross = float(np.exp(np.log(t0) + f * np.log(t1 / t0)))
        return min([cross] + [t for t, _ in pts[above[-1] + 1:]]), False
    if pts and not above:
        return float(pts[0][0]), False  # already below at the coarsest setting: an upper bound
    if len(pts) >= 2 and pts[-1][1] < pts[-2][1]:
        (t0, e0), (t1, e1) = pts[-2], pts[-1]
        f = np.log(target / e0) / np.log(e1 / e0)
        return float(np.exp(np.log(t0) + f * np.log(t1 / t0))), True
    return None, False


# ---------------------------------------------------------------- job 1
def job_one_amplitude(cfg: dict, log=print) -> dict:
    """k_Im at psi_BC, one design and a batch: direct vs HBM-AFT (handed psi_BC) vs time marching."""
    out = {}
    for label, designs in (("one_design", stack_one(one_design())),
                           (f"designs_{cfg['designs']}", random_valid_designs(cfg["designs"]))):
        n = int(np.shape(designs.mu)[0])
        direct = batched(direct_one)
        t_direct, spread, (k_re, k_im, psi_bc, span, ok) = timed(direct, designs, repeats=max(
            cfg["repeats"], 50 if n == 1 else cfg["repeats"]))
        k_re, k_im, psi_bc, span, ok = (np.asarray(v) for v in (k_re, k_im, psi_bc, span, ok))
        if not ok.all():
            raise RuntimeError(f"{label}: {int((~ok).sum())} designs did not converge")
        log(f"[job1 {label}] direct {t_direct * 1e3:.3f} ms for {n} designs, load {loadavg():.1f}")
        res = {"designs": n, "direct": {"time_s": t_direct, "time_min_max_s": spread,
                                        "load_average_1min": loadavg()}}
        # The direct value against a very fine HBM-AFT (on a subset of a batch).
        k = min(n, cfg["check_designs"])
        sub = jax.tree_util.tree_map(lambda x: None if x is None else x[:k], designs)
        nt = 2 * cfg["check_nt"] if n == 1 else cfg["check_nt"]
        fine, conv = batched(hbm_one, n_time=nt)(sub, jnp.asarray(psi_bc[:k]))
        res["reference_check"] = {"hbm_nt": nt, "designs": k,
                                  "max_rel_diff_k_im": float(np.max(rel_err(fine, k_im[:k], k_re[:k]))),
                                  "hbm_converged": bool(np.all(conv))}
        curves = {"hbm_aft": [], "time_marching": []}
        for nt in cfg["hbm_nt"]:
            t, spr, (kim, conv) = timed(batched(hbm_one, n_time=nt), designs, jnp.asarray(psi_bc),
                                        repeats=cfg["repeats"])
            e = rel_err(kim, k_im, k_re)
            curves["hbm_aft"].append({"Nt": nt, "time_s": t, "time_min_max_s": spr,
                                      "median_err": float(np.median(e)),
                                      "p95_err": float(np.quantile(e, 0.95)),
                                      "converged": float(np.mean(np.asarray(conv))), "load": loadavg()})
            log(f"[job1 {label}] HBM-AFT Nt {nt}: {t * 1e3:.2f} ms, median err {np.median(e):.2e}")
        for N in (cfg["tm_steps"] if n == 1 else cfg["tm_steps_batch"]):
            h = jnp.asarray(span / (N + 0.5))
            t, spr, (kim, conv) = timed(batched(march_one, n_steps=N), designs, h,
                                        repeats=1 if N * n >= 1e6 else cfg["repeats"])
            e = rel_err(kim, k_im, k_re)
            curves["time_marching"].append({"steps_per_half": N, "time_s": t, "time_min_max_s": spr,
                                            "median_err": float(np.median(e)),
                                            "p95_err": float(np.quantile(e, 0.95)),
                                            "converged": float(np.mean(np.asarray(conv))),
                                            "load": loadavg()})
            log(f"[job1 {label}] time marching N {N}: {t * 1e3:.2f} ms, median err {np.median(e):.2e}")
        res.update(curves)
        for name, key in (("hbm_aft", "vs_hbm"), ("time_marching", "vs_time_marching")):
            for stat in ("median_err", "p95_err"):
                t, extrap = time_at([(p["time_s"], p[stat]) for p in curves[name]])
                res[f"ratio_{key}" + ("" if stat == "median_err" else "_p95")] = (
                    None if t is None else t / t_direct)
                res[f"ratio_{key}" + ("" if stat == "median_err" else "_p95") + "_extrapolated"] = extrap
        out[label] = res
    return out


def stack_one(design: jd.Design) -> jd.Design:
    return jax.tree_util.tree_map(lambda x: None if x is None else jnp.asarray(x)[None], design)


# ---------------------------------------------------------------- jobs 2-4
def _summary(result: dict) -> dict:
    keep = ("ratio_vs_hbm", "target_1000x_met", "sizes", "extrapolated")
    return {k: result[k] for k in keep if k in result} | {"details": "results/jobs_layered.json"}


def layered_jobs(cfg: dict) -> dict:
    """Jobs 2-4 (benchmarks/jobs_layered.py): 2, whole curve (exact amplitude cycles at 64
    amplitudes plus psi_BC against an HBM-AFT amplitude sweep handed psi_BC); 3, forced response
    (amplitude-layered peaks at 10 forces and FRFs against coupled HBM-AFT with continuation); 4,
    gradient of job 3's peaks w.r.t. the shape (AD through the root against central differences
    of coupled HBM-AFT). The full run writes results/jobs_layered.json and its charts, once."""
    import jobs_layered

    if cfg is QUICK:
        out = {k: getattr(jobs_layered, f"job_{k}")(True) for k in ("curve", "response", "gradient")}
    else:
        out = jobs_layered.main(quick=False)
    return {k: _summary(out[k]) for k in ("curve", "response", "gradient")}


# ---------------------------------------------------------------- raw floor
def base_cycles_per_s(n: int, repeats: int) -> dict:
    """`jaxdamp.evaluate_designs` (the one batching path, default chunk) on n random designs."""
    rng = np.random.default_rng(1)
    shape = jd.DamperShape(rng.uniform(35, 90, n), rng.uniform(35, 90, n), rng.uniform(-0.3, 0.4, n),
                           np.full(n, 0.8))
    designs = jd.stack_designs(shape, rng.uniform(0.1, 0.9, n))
    t, spread, _ = timed(lambda: jd.evaluate_designs(designs), repeats=repeats)
    flops = first_stage_flops(designs)
    return {"designs": n, "per_s": n / t, "per_s_min_max": [n / spread[1], n / spread[0]],
            "load_average_1min": loadavg(), **flops,
            "achieved_gflop_per_s": flops["flops_per_design"] * n / t / 1e9}


def first_stage_flops(designs) -> dict:
    """The arithmetic of one design in the batched first stage, as XLA counts it: cost_analysis of
    the compiled program on one chunk, divided by its designs. XLA counts a loop body once, not
    once per trip, so the program is lowered here with every scan unrolled (the scans run all
    their slots, masked: the unrolled count is the work done). This is the work evaluate_designs
    does for ~98 % of random designs (the rest rerun in the second stage)."""
    from jaxdamp import batch as B

    n = int(B.values_chunk() or B.default_chunk(jax.devices()[0].platform))
    chunk = B.take(designs, np.arange(n) % int(np.shape(designs.mu)[0]))
    scan = jax.lax.scan

    def unrolled(f, init, xs=None, length=None, **kw):
        return scan(f, init, xs, length=length, **{**kw, "unroll": True})

    jax.clear_caches()  # the kernels' cached traces hold rolled scans
    jax.lax.scan = unrolled
    try:
        cost = jax.jit(jax.vmap(B.first_stage_summary)).lower(chunk).compile().cost_analysis()
    finally:
        jax.lax.scan = scan
        jax.clear_caches()
    cost = cost[0] if isinstance(cost, list) else cost
    return {"flops_per_design": float(cost.get("flops", np.nan)) / n,
            "transcendentals_per_design": float(cost.get("transcendentals", np.nan)) / n,
            "bytes_accessed_per_design": float(cost.get("bytes accessed", np.nan)) / n}


def single_latency_us(repeats: int) -> dict:
    """A warm public single-design call with its five numbers, median us: `jd.cycle_numbers` (the
    single-design entry point), and `five_numbers(base_cycle(...))` (the whole cycle returned)."""
    shape = jd.family_shape("60sym")
    t, spread, _ = timed(lambda: jd.cycle_numbers(shape, 0.5), repeats=repeats)
    t_bc, spread_bc, _ = timed(lambda: jd.five_numbers(jd.base_cycle(shape, 0.5)), repeats=repeats)
    return {"us": 1e6 * t, "us_min_max": [1e6 * spread[0], 1e6 * spread[1]],
            "call": "jaxdamp.cycle_numbers(family_shape('60sym'), 0.5)",
            "five_numbers_base_cycle_us": 1e6 * t_bc,
            "five_numbers_base_cycle_us_min_max": [1e6 * spread_bc[0], 1e6 * spread_bc[1]],
            "load_average_1min": loadavg()}


def plot(job1: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(job1), figsize=(6 * len(job1), 4.5), squeeze=False)
    for ax, (label, r) in zip(axes[0], job1.items()):
        for name, key, marker in (("hbm_aft", "Nt", "o-"), ("time_marching", "steps_per_half", "s-")):
            pts = r[name]
            ax.loglog([p["time_s"] for p in pts], [p["median_err"] for p in pts], marker,
                      label=f"{name.replace('_', ' ')} (median)")
            for p in pts:
                ax.annotate(str(p[key]), (p["time_s"], p["median_err"]), fontsize=7)
        ax.axvline(r["direct"]["time_s"], color="k", ls="--", label="direct (exact)")
        ax.axhline(TARGET, color="gray", ls=":")
        ax.set_xlabel("wall time per batch, s (warm, median)")
        ax.set_ylabel("relative error of k_Im at psi_BC")
        ax.set_title(fontsize=9, label=f"job 1, {r['designs']} design(s): ratio vs HBM-AFT "
                     f"{_fmt(r['ratio_vs_hbm'])}, vs time marching {_fmt(r['ratio_vs_time_marching'])}")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def _fmt(x):
    return "n/a" if x is None else f"{x:.0f}x"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description="jaxdamp speed on the jobs users run (issue 15)")
    p.add_argument("--quick", action="store_true", help="reduced sizes (< 5 min)")
    p.add_argument("--json", action="store_true", help="print the summary JSON on stdout")
    args = p.parse_args(argv)
    cfg = QUICK if args.quick else FULL
    log = (lambda *a: print(*a, file=sys.stderr)) if args.json else print
    t0 = time.perf_counter()
    info = machine()
    job1 = job_one_amplitude(cfg, log)
    batch_key = f"designs_{cfg['designs']}"
    b = job1[batch_key]
    summary = {
        "jobs": {"one_amplitude": {
            "ratio_vs_hbm": b["ratio_vs_hbm"], "ratio_vs_time_marching": b["ratio_vs_time_marching"],
            "ratio_vs_hbm_extrapolated": b["ratio_vs_hbm_extrapolated"],
            "ratio_vs_time_marching_extrapolated": b["ratio_vs_time_marching_extrapolated"],
            "designs": b["designs"],
            "one_design": {k: job1["one_design"][k] for k in (
                "ratio_vs_hbm", "ratio_vs_time_marching", "ratio_vs_hbm_extrapolated",
                "ratio_vs_time_marching_extrapolated")},
            "target_rel_error": TARGET},
            **layered_jobs(cfg)},
        "base_cycles_per_s": None, "single_latency_us": None,
    }
    tp = base_cycles_per_s(cfg["throughput_designs"], cfg["repeats"])
    lat = single_latency_us(cfg["single_repeats"])
    summary["base_cycles_per_s"] = tp["per_s"]
    summary["single_latency_us"] = lat["us"]
    info["load_average_1min_at_end"] = loadavg()
    info["async_dispatch"] = False
    summary["machine"] = info
    summary["wall_time_s"] = time.perf_counter() - t0
    if not args.quick:
        OUT.mkdir(exist_ok=True)
        full = dict(summary, details={"one_amplitude": job1, "base_cycles": tp, "single": lat},
                    config={k: list(v) if isinstance(v, tuple) else v for k, v in cfg.items()})
        (OUT / "jobs.json").write_text(json.dumps(full, indent=1) + "\n")
        plot(job1, OUT.parent.parent / "docs" / "jobs_one_amplitude.png")  # docs/performance.md
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(json.dumps(summary, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
