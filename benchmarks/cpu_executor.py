"""How XLA's CPU runtime runs a small batch's loop, and what that costs (issue 60).

XLA on the CPU runs a compiled program as a sequence of thunks (one kernel per fusion), and each
loop body or branch as a sequence of its own. Such a sequence runs in order on the calling thread
only where every buffer it touches is at most 512 bytes or it has at most 8 thunks (XLA's
`ThunkExecutor::Options`, fixed where `CpuExecutable` builds them: no flag or option reaches
them); otherwise a dataflow executor dispatches its thunks, ready ones handed to the other
threads of XLA's pool. A batch of 16 path cycles has buffers of 16 lanes times a few numbers
(16 x 2 x 3 doubles = 768 bytes), so its loop runs on the dataflow executor (JAX's profiler shows
its loop's kernels on two threads, about half on each, 2026-12-02).

Measured here: the batch job of `path_speed_accuracy.py` (60sym, phi = 90 deg, 2 mrad from
assembly, mu 0.5: 1 and 16 cycles on the exact engine, 16 by HBM-AFT at its periods and the two
samplings that bracket 1e-4 there), each setting in fresh processes (they act when JAX's CPU
client starts): the process as it starts by default, with XLA's pool of one thread (`NPROC=1`,
read by the CPU client at its start), pinned to one core (`taskset -c 0`), and with XLA's
small-while-loop threshold raised (`jaxdamp.runtime.SMALL_LOOP_FLAG`: a loop with no scatter,
sort or dot compiled as one kernel; both methods' programs, as every setting). Processes
alternate setting by setting, `--rounds` times; in each, the programs are timed round-robin.

    .venv/bin/python benchmarks/cpu_executor.py [--rounds 2] [--quick]

Writes benchmarks/results/cpu_executor.json.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from jaxdamp.runtime import SMALL_LOOP_FLAG

OUT = Path(__file__).parent / "results" / "cpu_executor.json"
# setting -> (environment added to the child's; XLA_FLAGS is appended to), command prefix
SETTINGS = {"default": ({}, []), "nproc_1": ({"NPROC": "1"}, []),
            "one_core": ({}, ["taskset", "-c", "0"]),
            # the small batch's loop compiled as one kernel
            "small_loops": ({"XLA_FLAGS": SMALL_LOOP_FLAG}, [])}
HBM_NT = (64, 256)  # path_speed_accuracy.json: 60sym's batch reaches 1e-4 between these
HBM_PERIODS = 3
NOTE = ("2-core VM; each setting in fresh child processes, which run in float64 with "
        "bench_common's measured XLA flags (this record is the parent process's)")


def child_settings(calls: int) -> dict:
    import jax
    import jax.numpy as jnp
    import numpy as np

    jax.config.update("jax_enable_x64", True)
    sys.path.insert(0, str(Path(__file__).parent))
    from bench_common import call_time, interleaved_times, use_measured_xla_flags
    use_measured_xla_flags()
    from path_speed_accuracy import CASES, ENGINE_BATCH, HBM_BATCH, prepared

    case = CASES[0]  # 60sym, phi 90 deg, 2 mrad
    _, args, motion = prepared(case)
    one = jnp.asarray([case["amplitude"]])
    amps = jnp.asarray(case["amplitude"] * np.linspace(0.9, 1.1, 16))
    programs = {"engine_1": lambda: ENGINE_BATCH(*args, one, motion),
                "engine_16": lambda: ENGINE_BATCH(*args, amps, motion)}
    for nt in HBM_NT:
        programs[f"hbm_16_nt{nt}"] = (lambda nt=nt: HBM_BATCH(*args, amps, motion, nt, HBM_PERIODS))
    first = {k: call_time(f)[0] for k, f in programs.items()}  # trace, compile and one run
    times, outs = interleaved_times(programs, repeats=calls // 5, calls={k: 5 for k in programs},
                                    warm=False)
    res = {k: dict(median_ms=1e3 * float(np.median(v)), min_ms=1e3 * min(v), calls=len(v),
                   first_call_s=first[k]) for k, v in times.items()}
    # The same numbers in every setting (bits of k_Im, sha1)
    res["engine_16_k_im_sha1"] = hashlib.sha1(np.asarray(outs["engine_16"][1]).tobytes()).hexdigest()
    return res


def run_child(setting: str, calls: int) -> dict:
    env_add, prefix = SETTINGS[setting]
    env = dict(os.environ, JAX_PLATFORMS="cpu")
    for name, value in env_add.items():
        env[name] = (f"{env.get(name, '')} {value}".strip() if name == "XLA_FLAGS" else value)
    cmd = prefix + [sys.executable, __file__, "--child", "--calls", str(calls)]
    t = time.perf_counter()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{setting}: the child process failed (rc {p.returncode}):\n{p.stderr[-2000:]}")
    return dict(json.loads(p.stdout.strip().splitlines()[-1]), process_s=time.perf_counter() - t)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=2, help="processes per setting (default 2)")
    ap.add_argument("--quick", action="store_true", help="fewer calls, one round, no JSON")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--calls", type=int, default=200, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child_settings(args.calls)))
        return 0
    if args.rounds < 1:
        ap.error("--rounds: at least 1")
    if shutil.which("taskset") is None:
        ap.error("taskset (util-linux) is needed for the one-core setting")
    sys.path.insert(0, str(Path(__file__).parent))
    from bench_common import machine

    t0 = time.perf_counter()
    calls, rounds = (40, 1) if args.quick else (args.calls, args.rounds)
    res = dict(machine=machine(NOTE), calls_per_process=calls,
               hbm=dict(n_time=list(HBM_NT), periods=HBM_PERIODS), settings={})
    for r in range(rounds):
        for s in SETTINGS:
            out = run_child(s, calls)
            res["settings"].setdefault(s, []).append(out)
            print(f"round {r} {s}: " + ", ".join(
                f"{k} {v['median_ms']:.3f} ms (min {v['min_ms']:.3f})"
                for k, v in out.items() if isinstance(v, dict)), flush=True)
    res["wall_time_s"] = time.perf_counter() - t0
    if not args.quick:
        OUT.write_text(json.dumps(res, indent=1) + "\n")
        print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
