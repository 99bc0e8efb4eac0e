"""Batch and gradient benchmark (issue 4): warm single-design latency, batched throughput for batch
sizes 1 ... 100,000 (one device, and two host devices in a subprocess), the cost of jacfwd / jacrev /
grad relative to one forward evaluation, and compile times.

Every timing is the median of repeats of warm (already compiled) calls; ratios compare numbers
measured in the same run. Compile times are lower().compile() of each program.

    python benchmarks/bench_batch.py [--quick]

Writes benchmarks/results/batch.json and its figure, docs/batch.png.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from bench_common import (use_measured_xla_flags, random_shapes, interleaved_ms,  # noqa: E402
                          interleaved_times, machine, median_time)

use_measured_xla_flags()  # before JAX starts: both sides of every comparison get it
from jaxdamp import batch as B  # noqa: E402
from jaxdamp import gradients as G  # noqa: E402

OUT = Path(__file__).parent / "results"
TARGET_DESIGNS_PER_S = 100_000
TARGET_GRADIENT_RATIO = 4.0


def compile_time(jitted, *args):
    t = time.perf_counter()
    jitted.lower(*args).compile()
    return time.perf_counter() - t


def random_designs(n, seed=0):
    return B.stack_designs(*random_shapes(n, seed))


def throughput(sizes, repeats=5) -> dict:
    """evaluate_designs (sharded, two-stage, chunked) in designs per second, per batch size."""
    out = {}
    big = random_designs(max(sizes))
    for n in sizes:
        d = B.take(big, np.arange(n))
        reps = repeats if n < 50_000 else 3
        t = median_time(lambda: B.evaluate_designs(d), repeats=reps)
        out[str(n)] = n / t
    return out


def chunk_sweep(chunks=(1024, 2048, 4096, 8192, 16384), n=40_000, repeats=3) -> dict:
    """evaluate_designs designs/s per chunk size (designs per device per call), best of repeats."""
    d = random_designs(n)
    # round-robin, so that machine load hits every size alike
    times, _ = interleaved_times({c: (lambda c=c: B.evaluate_designs(d, chunk_size=c)) for c in chunks},
                                 repeats=repeats)
    return {str(c): n / min(t) for c, t in times.items()}


def plain_vmap_throughput(sizes) -> dict:
    """Baseline: jax.jit(jax.vmap(jaxdamp.base_cycle)) + five numbers on the whole batch at once."""
    f = jax.jit(jax.vmap(lambda s, m, c, lo: jnp.stack(jd.five_numbers(jd.base_cycle(s, m, c, lo)).numbers())))
    big = random_designs(max(sizes))
    out = {}
    for n in sizes:
        d = jax.tree_util.tree_map(jnp.asarray, B.take(big, np.arange(n)))
        out[str(n)] = n / median_time(f, *d, repeats=3)
    return out


def gradient_costs() -> dict:
    """Warm times of one forward evaluation and of derivatives with respect to all 7 design
    variables (theta_l, theta_r, b_R/h_R, 2b_L/h_L, mu, kn, kt), and their compile times.

    "five": the five numbers; "all": the five numbers and k_Im(psi_a) (what jaxdamp.gradients
    differentiates). grad is reverse mode for one scalar output (k_Im,BC)."""
    dv = jd.Design(jd.family_shape("60sym"), 0.5).prepared()
    psi_a = jnp.asarray(3.0)
    five = lambda d, p: jnp.stack(list(G.outputs(d, p)[0])[:5])  # noqa: E731
    every = lambda d, p: jnp.stack(list(G.outputs(d, p)[0]))  # noqa: E731
    k_im = lambda d, p: G.outputs(d, p)[0].k_im_bc  # noqa: E731
    programs = {
        "forward_five": jax.jit(five),
        "jacfwd_five": jax.jit(jax.jacfwd(five)),
        "jacrev_five": jax.jit(jax.jacrev(five)),
        "grad_k_im_bc": jax.jit(jax.grad(k_im)),
        "jacfwd_k_im_bc": jax.jit(jax.jacfwd(k_im)),
        "forward_all": jax.jit(every),
        "jacfwd_all": jax.jit(jax.jacfwd(every)),
        "jacrev_all": jax.jit(jax.jacrev(every)),
    }
    res = {"compile_s": {k: compile_time(f, dv, psi_a) for k, f in programs.items()}}
    res["warm_ms"] = interleaved_ms(programs, dv, psi_a, repeats=100)
    w = res["warm_ms"]
    res["ratio_to_forward"] = {k: w[k] / w["forward_all" if k.endswith("_all") else "forward_five"]
                               for k in w if not k.startswith("forward")}
    # The public API (input validation and host round trips included).
    s = jd.family_shape("60sym")
    res["api_warm_ms"] = interleaved_ms({
        "base_cycle+five_numbers": lambda: jd.five_numbers(jd.base_cycle(s, 0.5)),
        "five_numbers_jacobian_fwd": lambda: G.five_numbers_jacobian(s, 0.5),
        "five_numbers_jacobian_rev": lambda: G.five_numbers_jacobian(s, 0.5, mode="rev"),
    }, repeats=30)
    return res


def batch_compile_times() -> dict:
    chunk = B.default_chunk("cpu")
    d = jax.tree_util.tree_map(jnp.asarray, B.take(random_designs(chunk), np.arange(chunk)))
    run = jax.jit(jax.vmap(B.summary_kernel, in_axes=(0, None)), static_argnums=1)
    return {f"evaluate_designs_chunk{chunk}_pairs{p}": compile_time(run, d, p)
            for p in (1, jd.cycle.MAX_PAIRS)}


TWO_DEVICES = """
import json, sys
sys.path.insert(0, {here!r})
import bench_batch as bb
import jax
print(json.dumps({{"devices": len(jax.devices()), "designs_per_s": bb.throughput({sizes}),
                  "chunk_sweep": bb.chunk_sweep() if {chunks} else None}}))
"""


def two_device_throughput(sizes, chunks=True) -> dict:
    """throughput(sizes) (and chunk_sweep() if chunks) on 2 host devices, in a fresh process with
    JAX's default dispatch."""
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2", JAX_PLATFORMS="cpu")
    code = TWO_DEVICES.format(here=str(Path(__file__).parent), sizes=list(sizes), chunks=chunks)
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(proc.stderr[-3000:])
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    sizes = [1, 10, 100, 1000, 10_000] + ([] if args.quick else [100_000])
    res = {"machine": machine(), "targets": {"designs_per_s": TARGET_DESIGNS_PER_S,
                                             "gradient_over_forward": TARGET_GRADIENT_RATIO}}
    res["gradients"] = gradient_costs()
    res["compile_s_batch"] = batch_compile_times()
    res["throughput_designs_per_s"] = {"evaluate_designs_1_device": throughput(sizes)}
    res["throughput_designs_per_s"]["plain_vmap_1_device"] = plain_vmap_throughput(
        [n for n in sizes if n <= 10_000])
    two = two_device_throughput(sizes)
    res["throughput_designs_per_s"]["evaluate_designs_2_host_devices"] = two["designs_per_s"]
    res["chunk_sweep_designs_per_s"] = {"1_device": chunk_sweep(), "2_host_devices": two["chunk_sweep"],
                                        "default_chunk": B.default_chunk("cpu"),
                                        "values_chunk": B.values_chunk()}
    one = res["throughput_designs_per_s"]["evaluate_designs_1_device"]
    best = max(max(one.values()), max(two["designs_per_s"].values()))
    ratios = res["gradients"]["ratio_to_forward"]
    res["verdict"] = {
        "best_designs_per_s": best, "throughput_target_met": best >= TARGET_DESIGNS_PER_S,
        **{f"{k}_over_forward": v for k, v in ratios.items()},
        "gradient_target_met_by": sorted(k for k, v in ratios.items() if v <= TARGET_GRADIENT_RATIO),
    }
    res["machine"]["load_average_1min_at_end"] = os.getloadavg()[0]
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "batch.json").write_text(json.dumps(res, indent=2))
    plot(res)
    print(json.dumps(res, indent=2))


def plot(res):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 8), layout="constrained")
    FigureCanvasAgg(fig)
    (a, b), (c, d) = fig.subplots(2, 2)
    for label, series in res["throughput_designs_per_s"].items():
        n = np.array([int(k) for k in series])
        a.loglog(n, list(series.values()), "o-", label=label.replace("_", " "))
    a.axhline(TARGET_DESIGNS_PER_S, color="k", ls="--", lw=1, label="target 100,000/s")
    a.set_xlabel("batch size (designs)")
    a.set_ylabel("Base-Cycles + five numbers per second")
    a.legend(fontsize=8)
    a.set_title("batched throughput (warm, median)")
    g = res["gradients"]
    names = list(g["ratio_to_forward"])
    b.bar([n.replace("_", "\n", 1) for n in names], [g["ratio_to_forward"][n] for n in names],
          color=[f"C{i}" for i in range(len(names))])
    b.axhline(TARGET_GRADIENT_RATIO, color="k", ls="--", lw=1, label="target 4x")
    b.set_ylabel("warm time / one forward evaluation")
    b.set_title("derivatives w.r.t. all 7 design variables / one forward evaluation\n"
                f"(forward: five numbers {g['warm_ms']['forward_five']:.3f} ms, "
                f"with k_Im(psi_a) {g['warm_ms']['forward_all']:.3f} ms)", fontsize=9)
    b.legend(fontsize=8)
    comp = {**g["compile_s"], **res["compile_s_batch"]}
    c.barh([k.replace("_", " ") for k in comp], list(comp.values()), color="C4")
    c.set_xlabel("compile time (s)")
    c.set_title("compile (lower + compile)")
    api = g["api_warm_ms"]
    d.bar([k.replace("_", "\n") for k in api], list(api.values()), color="C5")
    d.set_ylabel("warm latency (ms)")
    d.set_title("single design through the public API")
    m = res["machine"]
    fig.suptitle(f"jaxdamp batch & gradients - {m['cpu']}, {m['cores']} cores, jax {m['jax']}, "
                 f"load avg {m['load_average_1min_at_start']:.1f}", fontsize=10)
    fig.savefig(OUT.parent.parent / "docs" / "batch.png", dpi=110)  # docs/performance.md


if __name__ == "__main__":
    main()
