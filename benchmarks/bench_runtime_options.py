"""JAX CPU runtime options, measured (issue 15): XLA flags, host device count, async dispatch,
and the batching chunk, on the batched job (`jaxdamp.evaluate_designs`) and on one warm public
`base_cycle` + `five_numbers` call.

XLA flags must be set before JAX starts, so every option set runs in its own worker process. The
workers are started and warmed first; then the parent asks them for one measurement each in turn,
round after round (A B C A B C ...), so that the load of a shared machine hits every option alike.
Reported: the median over rounds and the spread (min, max), with the load average of each round.

    python benchmarks/bench_runtime_options.py [--quick] [--designs N] [--rounds R]

Writes benchmarks/results/cpu_runtime_options.json.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

OUT = Path(__file__).parent / "results"

# name -> (extra XLA_FLAGS, JAX config updates, jaxdamp.runtime.CPU_BATCH_OPTIONS or None to keep
# the library's). "default" is what jaxdamp does: its batched programs compile with
# CPU_BATCH_OPTIONS (YNNPACK reduction fusion off); "xla_default_reductions" compiles them with
# XLA's defaults, as jaxdamp did before; "ynn_off_flag" sets the same option for the whole process.
OPTIONS = {
    "default": ("", {}, None),
    "xla_default_reductions": ("", {}, {}),
    "ynn_off_flag": ("--xla_cpu_experimental_ynn_fusion_type=", {}, {}),
    "host_devices_2": ("--xla_force_host_platform_device_count=2", {}, None),
    "no_async_dispatch": ("", {"jax_cpu_enable_async_dispatch": False}, None),
    "eigen_single_thread": ("--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1", {},
                            None),
    "thunk_runtime_off": ("--xla_cpu_use_thunk_runtime=false", {}, None),
    "host_devices_2_no_async": ("--xla_force_host_platform_device_count=2",
                                {"jax_cpu_enable_async_dispatch": False}, None),
    "vector_width_512": ("--xla_cpu_prefer_vector_width=512", {}, None),
    "fusion_emitters_off": ("--xla_cpu_use_fusion_emitters=false", {}, None),
}
CHUNKS = (1024, 4096, 8192, 16384)  # swept in the "default" worker; the others run the default chunk


def worker(config: dict, batch_options, n: int, single_calls: int, chunks) -> None:
    """Serve measurements on stdin/stdout: 'go' -> one JSON line; 'quit' -> exit."""
    import jax
    import numpy as np

    jax.config.update("jax_enable_x64", True)
    for k, v in config.items():
        jax.config.update(k, v)
    import jaxdamp as jd
    from jaxdamp import runtime
    from bench_common import call_time  # this file's folder is sys.path[0]: the worker runs it

    if batch_options is not None:  # before the first batched program is compiled
        runtime.CPU_BATCH_OPTIONS = batch_options

    rng = np.random.default_rng(0)
    shape = jd.DamperShape(rng.uniform(35, 90, n), rng.uniform(35, 90, n), rng.uniform(-0.3, 0.4, n),
                           np.full(n, 0.8))
    designs = jd.stack_designs(shape, rng.uniform(0.1, 0.9, n))
    one = jd.DamperShape(60.0, 45.0, 0.1, 0.8)

    def single():
        return jax.block_until_ready(jd.five_numbers(jd.base_cycle(one, 0.5)))

    for c in chunks:
        jd.evaluate_designs(designs, chunk_size=c)
    for _ in range(20):
        single()
    print(json.dumps({"ready": True, "devices": len(jax.devices())}), flush=True)
    for line in sys.stdin:
        if line.strip() != "go":
            break
        res = {}
        for c in chunks:
            dt, _ = call_time(lambda: jd.evaluate_designs(designs, chunk_size=c))
            res["base_cycles_per_s" if c is None else f"chunk_{c}"] = n / dt
        ts = [call_time(single)[0] for _ in range(single_calls)]
        res["single_latency_us"] = 1e6 * float(np.median(ts))
        print(json.dumps(res), flush=True)


def compiler_options_ab(n: int = 8192, rounds: int = 10) -> dict:
    """In one process, the same batched programs compiled with and without
    jaxdamp.runtime.CPU_BATCH_OPTIONS, timed alternately (ms per call, median and min over rounds):
    the direct method's first stage on n random designs (one chunk) and HBM-AFT (Nt 64, 3 periods)
    handed psi_BC on 256 of them. The worker processes above compare whole option sets; this
    isolates the compiled program from process-to-process noise."""
    import jax
    import numpy as np

    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd
    from jaxdamp import batch as B
    from jaxdamp.baselines import hbm_aft_kernel
    from jaxdamp.runtime import CPU_BATCH_OPTIONS

    sys.path.insert(0, str(Path(__file__).parent))
    from bench_common import random_shapes, warm_times

    designs = jax.device_put(jd.stack_designs(*random_shapes(n, seed=0)))
    few = B.take(designs, np.arange(256))
    psi_bc = jd.evaluate_designs(few).psi_bc
    psi_bc = np.where(psi_bc > 0, psi_bc, 1.0)
    hbm = jax.vmap(lambda d, p: hbm_aft_kernel(*d, p, n_time=64).k_im)
    programs = {"first_stage": (jax.vmap(B.first_stage_summary), (designs,)),
                "hbm_aft_nt64_256": (hbm, (few, psi_bc))}
    compiled = {}
    for name, (fn, args) in programs.items():
        low = jax.jit(fn).lower(*args)
        compiled[name, "xla_default"] = (low.compile(), args)
        compiled[name, "jaxdamp"] = (low.compile(compiler_options=CPU_BATCH_OPTIONS), args)
    times = {k: [] for k in compiled}
    for _ in range(rounds):
        for k, (prog, args) in compiled.items():
            times[k].append(1e3 * warm_times(prog, *args, repeats=1)[0][0])  # one untimed call first
    out = {}
    for name in programs:
        a, b = times[name, "xla_default"], times[name, "jaxdamp"]
        out[name] = {"xla_default_ms": {"median": float(np.median(a)), "min": float(np.min(a))},
                     "jaxdamp_options_ms": {"median": float(np.median(b)), "min": float(np.min(b))},
                     "speedup_median": float(np.median(a) / np.median(b))}
    return {"options": CPU_BATCH_OPTIONS, "designs": n, "rounds": rounds, **out}


def start(name, n, single_calls):
    flags, config, batch_options = OPTIONS[name]
    env = dict(os.environ, JAX_PLATFORMS="cpu",
               XLA_FLAGS=(os.environ.get("XLA_FLAGS", "") + " " + flags).strip())
    chunks = list(CHUNKS) + [None] if name == "default" else [None]
    cmd = [sys.executable, __file__, "--worker", json.dumps([config, batch_options]), "--designs", str(n),
           "--single-calls", str(single_calls), "--chunks", json.dumps(chunks)]
    return subprocess.Popen(cmd, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--designs", type=int, default=None)
    p.add_argument("--rounds", type=int, default=None)
    p.add_argument("--single-calls", type=int, default=300)
    p.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    p.add_argument("--chunks", default="[null]", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.worker is not None:
        config, batch_options = json.loads(args.worker)
        worker(config, batch_options, args.designs, args.single_calls, json.loads(args.chunks))
        return 0
    n = args.designs or (4096 if args.quick else 16384)
    rounds = args.rounds or (3 if args.quick else 7)
    sys.path.insert(0, str(Path(__file__).parent))
    from bench_common import machine

    procs = {name: start(name, n, args.single_calls) for name in OPTIONS}
    ready, rejected = {}, {}
    for name, proc in procs.items():
        line = proc.stdout.readline()
        if not line:
            rejected[name] = proc.stderr.read().strip().splitlines()[-1:]
            continue
        ready[name] = json.loads(line)
    samples = {name: [] for name in ready}
    loads = []
    for _ in range(rounds):
        loads.append(os.getloadavg()[0])
        for name in ready:
            procs[name].stdin.write("go\n")
            procs[name].stdin.flush()
            samples[name].append(json.loads(procs[name].stdout.readline()))
    for proc in procs.values():
        if proc.poll() is None:
            proc.stdin.write("quit\n")
            proc.stdin.flush()
            proc.wait(timeout=60)

    import numpy as np

    results = {}
    for name, rows in samples.items():
        keys = rows[0].keys()
        results[name] = {
            "xla_flags": OPTIONS[name][0], "jax_config": OPTIONS[name][1],
            "jaxdamp_batch_compiler_options": OPTIONS[name][2],
            "devices": ready[name]["devices"],
            **{k: {"median": float(np.median([r[k] for r in rows])),
                   "min": float(np.min([r[k] for r in rows])),
                   "max": float(np.max([r[k] for r in rows]))} for k in keys}}
    out = {"machine": machine(), "designs": n, "rounds": rounds,
           "load_average_1min_per_round": loads,
           "units": {"base_cycles_per_s": "designs (= Base-Cycles) per s, evaluate_designs, default chunk",
                     "jaxdamp_batch_compiler_options": "null: the library's own (CPU_BATCH_OPTIONS); {}: XLA's defaults",
                     "chunk_*": "the same at that chunk_size (designs per device per call)",
                     "single_latency_us": "median us of a warm five_numbers(base_cycle(...))"},
           "options": results, "rejected": rejected}
    out["compiler_options_ab"] = compiler_options_ab(rounds=5 if args.quick else 10)
    previous = OUT / "cpu_runtime_options.json"
    if previous.exists():  # an earlier run's separate A/B, kept with its own note
        old = json.loads(previous.read_text())
        if "process_ab" in old:
            out["process_ab"] = old["process_ab"]
    OUT.mkdir(exist_ok=True)
    (OUT / "cpu_runtime_options.json").write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
