"""Stress reproducer (not a test) for the worker crashes of the test suite (issue 32).

The crashes seen under jax/jaxlib 0.10.2 were aborts and segfaults inside jaxlib while compiling,
reading a persistent-cache entry or serialising an executable, in programs that apply a `scan` or
`while_loop` eagerly under `jvp` (tests/test_loops.py, tests/test_sequence.py). This script compiles
those programs again and again, the way the suite does:

- `--processes P` processes at once, sharing one persistent compilation cache (as pytest-xdist
  workers do), each running the same programs, so that one writes entries the others read;
- `--rounds R` rounds; the cache is emptied before every odd round, so that rounds alternate
  between compiling and writing (cold) and reading what the others wrote (warm).

Every process is a fresh interpreter; a process killed by a signal is a crash and is counted with
its signal and the last lines of its stderr (faulthandler's stack).

    python scripts/crash_repro.py --processes 2 --rounds 10 [--json out.json]

Run it with the interpreter of the JAX version to test; it records jax.__version__.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# The programs of the two crashing tests, applied as the tests apply them (eagerly, no outer jit).
WORKLOAD = r"""
import faulthandler, sys
faulthandler.enable()
import jax, jax.numpy as jnp, numpy as np
jax.config.update("jax_enable_x64", True)
jax.config.update("jax_compilation_cache_dir", sys.argv[1])
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
import jaxdamp as jd
from jaxdamp.amplitude import amplitude_kernel

def design(name, mu):
    return jd.params.prepare_inputs(jd.family_shape(name), mu, jd.Contacts(), jd.LoadCase())

s, m, c, ld = design("74R", 0.5)
psi = jnp.asarray(np.geomspace(0.2, 12.0, 24)[8:20:3])

def total_k_im(theta_l, loop):
    run = lambda p: amplitude_kernel(s._replace(theta_l=theta_l), m, c, ld, p, loop=loop).k_im
    return jnp.sum(jax.vmap(run)(psi))

ref = jax.grad(total_k_im)(s.theta_l, "scan")
for loop in ("auto", "while"):
    assert abs(float(jax.jacfwd(total_k_im)(s.theta_l, loop)) - float(ref)) <= 1e-8 * abs(float(ref))

s2, m2, c2, ld2 = design("60sym", 0.5)
def k_im_of(mu):
    return amplitude_kernel(s2, mu, c2, ld2, jnp.asarray(1.2)).k_im
print(float(jax.jacfwd(k_im_of)(m2)), float(jax.grad(k_im_of)(m2)))
"""


def one_round(processes: int, cache: Path) -> list[dict]:
    env = dict(os.environ, PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    procs = [subprocess.Popen([sys.executable, "-c", WORKLOAD, str(cache)], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for _ in range(processes)]
    out = []
    for p in procs:
        stdout, stderr = p.communicate()
        code = p.returncode
        crashed = code < 0 or code in (134, 139)
        out.append({"returncode": code,
                    "signal": signal.Signals(-code).name if code < 0 else None,
                    "crashed": crashed, "failed": code != 0,
                    "stderr_tail": stderr[-1500:] if code != 0 else ""})
    return out


def main() -> None:
    import jax

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    cache = Path(tempfile.mkdtemp(prefix="jaxdamp-crash-cache-"))
    rounds = []
    t0 = time.perf_counter()
    for r in range(args.rounds):
        if r % 2 == 0:
            shutil.rmtree(cache, ignore_errors=True)
            cache.mkdir()
        res = one_round(args.processes, cache)
        rounds.append({"round": r, "cache": "cold" if r % 2 == 0 else "warm", "processes": res})
        n_crash = sum(p["crashed"] for p in res)
        print(f"round {r} ({rounds[-1]['cache']}): {n_crash} crashed, "
              f"{sum(p['failed'] for p in res)} failed, {time.perf_counter() - t0:.0f} s", flush=True)
    shutil.rmtree(cache, ignore_errors=True)
    doc = {"jax": jax.__version__, "processes": args.processes, "rounds": args.rounds,
           "process_runs": args.processes * args.rounds,
           "crashes": sum(p["crashed"] for r in rounds for p in r["processes"]),
           "failures": sum(p["failed"] for r in rounds for p in r["processes"]),
           "wall_s": round(time.perf_counter() - t0, 1), "cpu_count": os.cpu_count(),
           "rounds_detail": rounds}
    print(json.dumps({k: v for k, v in doc.items() if k != "rounds_detail"}))
    if args.json:
        Path(args.json).write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
