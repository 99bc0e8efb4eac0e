"""One design at a time (issue 15): the warm single call, and a second CLI call.

Single call, warm, synchronous CPU dispatch, median of repeats in interleaved blocks of 50 calls
of one form (the forms take turns, so machine load hits them alike):
  * `jaxdamp.cycle_numbers(shape, mu)`: the single-design entry point (one packed input, one
    output vector, loops that stop when done);
  * `five_numbers(base_cycle(shape, mu))`: the whole cycle back to Python, then its numbers;
  * the kernel alone with loop="scan" and loop="while" (five numbers in the same program).
Second CLI call: `jaxdamp cycle --shape 60sym --mu 0.5` as a subprocess with a fresh persistent
compilation cache, once cold (fills the cache), then warm repeats (median).
Response CLI call (issue 27): `jaxdamp response --shape 60sym --mu 0.5 --force-n 2,5,20
--diagram` the same way: cold (traces, exports and compiles every program) and warm repeats (the
saved exports and the compiled code are reused: no tracing, no compilation).

    python benchmarks/bench_single.py            # writes results/single.json
    python benchmarks/bench_single.py --quick    # fewer repeats, prints the JSON
    python benchmarks/bench_single.py --only response  # the response part, merged into single.json
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_enable_async_dispatch", False)

import jaxdamp as jd  # noqa: E402
from jaxdamp import five_numbers_kernel  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import call_time, interleaved_times, loadavg, machine  # noqa: E402

OUT = Path(__file__).parent / "results"
SHAPES = ("60sym", "74R", "90R")


BLOCK = 50  # calls of one form in a row: a user's loop of calls keeps its program in the caches


def _interleaved_us(programs: dict, repeats: int) -> dict:
    times, _ = interleaved_times(programs, repeats=max(repeats // BLOCK, 1),
                                 calls={k: BLOCK for k in programs})
    return {k: {"median_us": 1e6 * float(np.median(v)), "p10_us": 1e6 * float(np.percentile(v, 10)),
                "p90_us": 1e6 * float(np.percentile(v, 90))} for k, v in times.items()}


def single_call(repeats: int) -> dict:
    out = {}
    for name in SHAPES:
        shape = jd.family_shape(name)
        design = jd.params.prepare_inputs(shape, 0.5, jd.Contacts(), jd.LoadCase())
        kernels = {loop: jax.jit(lambda *d, loop=loop: jnp.stack(five_numbers_kernel(
            jd.base_cycle_kernel(*d, loop=loop)).numbers())) for loop in ("scan", "while")}
        programs = {
            "cycle_numbers": lambda: jd.cycle_numbers(shape, 0.5),
            "five_numbers(base_cycle)": lambda: jd.five_numbers(jd.base_cycle(shape, 0.5)),
            "kernel_scan": lambda: kernels["scan"](*design),
            "kernel_while": lambda: kernels["while"](*design),
        }
        got = np.array(jd.cycle_numbers(shape, 0.5)[:5])
        ref = np.array(jd.five_numbers(jd.base_cycle(shape, 0.5)).numbers())
        out[name] = {"load_average_1min": loadavg()[0], **_interleaved_us(programs, repeats),
                     "max_abs_diff_vs_five_numbers_base_cycle": float(np.max(np.abs(got - ref)))}
    return out


RESPONSE_ARGS = ["response", "--shape", "60sym", "--mu", "0.5", "--force-n", "2,5,20", "--diagram"]


def second_cli_call(repeats: int, args=("cycle", "--shape", "60sym", "--mu", "0.5")) -> dict:
    exe = shutil.which("jaxdamp") or str(Path(sys.executable).with_name("jaxdamp"))
    argv = [exe, *args]
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, JAXDAMP_CACHE_DIR=cache)
        times = []
        for _ in range(repeats + 1):
            times.append(call_time(lambda: subprocess.run(argv, env=env, check=True,
                                                      capture_output=True))[0])
        n_files = len(os.listdir(cache))
        if os.path.isdir(os.path.join(cache, "exported")):
            n_files += len(os.listdir(os.path.join(cache, "exported")))
    return {"command": " ".join(["jaxdamp"] + argv[1:]), "cold_s": times[0],
            "warm_median_s": float(np.median(times[1:])), "warm_min_max_s": [min(times[1:]),
                                                                              max(times[1:])],
            "cache_files": n_files, "load_average_1min": loadavg()[0]}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="fewer repeats; print instead of write")
    p.add_argument("--only", choices=("response",),
                   help="run this part only and merge it into the committed single.json")
    args = p.parse_args(argv)
    repeats = 3 if args.quick else 5
    response = {**second_cli_call(repeats, RESPONSE_ARGS),
                "targets_s": {"cold": 20.0, "warm": 3.0}}
    if args.only == "response":
        res = json.loads((OUT / "single.json").read_text())
        res["response_cli_call"] = response
        res["response_machine"] = machine("2 CPU cores shared with other jobs")
    else:
        res = {"machine": machine("2 CPU cores shared with other jobs; synchronous dispatch"),
               "single_call_us": single_call(300 if args.quick else 2000),
               "second_cli_call": second_cli_call(3 if args.quick else 7),
               "response_cli_call": response,
               "targets": {"single_call_us": 50.0, "second_cli_call_s": 1.5}}
        res["targets_met"] = {
            "single_call": all(v["cycle_numbers"]["median_us"] <= 50.0
                               for v in res["single_call_us"].values()),
            "second_cli_call": res["second_cli_call"]["warm_median_s"] <= 1.5}
    res.setdefault("targets_met", {})
    res["targets_met"]["response_cold"] = response["cold_s"] <= 20.0
    res["targets_met"]["response_warm"] = response["warm_median_s"] <= 3.0
    text = json.dumps(res, indent=1)
    if args.quick:
        print(text)
    else:
        OUT.mkdir(exist_ok=True)
        (OUT / "single.json").write_text(text + "\n")
        print(json.dumps({k: res[k] for k in ("response_cli_call", "targets_met")}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
