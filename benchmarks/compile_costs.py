"""Benchmark (not a test): where a first call's time goes, per CLI command and per public function.

Each case runs in a fresh Python process with an empty compilation cache (first call), then once
more in another fresh process with the cache it left (repeat call). JAX reports the duration of
every tracing, lowering and XLA compilation through `jax.monitoring`'s event listeners, with the
program's name. For each
case the JSON has the wall time of the whole process, and per program: trace, lower and compile
seconds and the time spent reading the persistent cache. (StableHLO module sizes are not recorded:
the dump's file names did not match the programs' names; docs/performance-history.md gives the size of
the largest program, measured apart.) Python cases run without a persistent cache.

    PYTHONPATH=. python benchmarks/compile_costs.py [--only cycle,grad] [--out FILE]

Writes benchmarks/results/compile_costs.json (with the machine it ran on).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

OUT = Path(__file__).parent / "results"
ROOT = Path(__file__).resolve().parents[1]

# (name, kind, what): kind "cli" runs `jaxdamp <argv>`, kind "py" runs the snippet.
CASES = [
    ("statics", "cli", "statics --shape 60sym --mu 0.7"),
    ("cycle", "cli", "cycle --shape 74R --mu 0.5"),
    ("amplitude", "cli", "amplitude --shape 60sym --mu 0.5 --psi-a 0.5,1.2,3"),
    ("grad", "cli", "grad --shape 74R --mu 0.5"),
    ("response", "cli", "response --shape 60sym --mu 0.5 --force-n 5,20"),
    ("response_band", "cli", "response --shape 60sym --mu 0.5 --force-n 2,5,20 --band"),
    ("fit_loops", "cli", "fit-loops {tmp}/a.csv {tmp}/b.csv {tmp}/c.csv --shape 60sym "
                         "--out {tmp}/fit.json"),
    ("study", "cli", "study --out {tmp}/study"),
    ("design_peaks", "py", "import jaxdamp as jd\n"
                           "jd.design_peaks(jd.family_shape('60sym'), 0.5, force_n=[5.0, 20.0])"),
    ("peak_response_of_damper_stiffness", "py",
     "import jaxdamp as jd\n"
     "d = jd.damper_stiffness(jd.family_shape('60sym'), 0.5)\n"
     "jd.peak_response(d, jd.BladeMode(), 5.0)"),
]

# The snippet each process runs: listeners on JAX's compile events, then the case, then the
# durations per program as one JSON line on stdout's last line.
DRIVER = r"""
import collections, json, os, sys, time
t0 = time.perf_counter()
import jax
from jax import monitoring
events = collections.defaultdict(lambda: collections.defaultdict(float))
NAMES = {"/jax/core/compile/jaxpr_trace_duration": "trace_s",
         "/jax/core/compile/jaxpr_to_mlir_module_duration": "lower_s",
         "/jax/core/compile/backend_compile_duration": "compile_s",
         "/jax/compilation_cache/cache_retrieval_time_sec": "cache_read_s"}
def listen(event, duration, **kw):
    key = NAMES.get(event)
    if key:
        events[kw.get("fun_name", "?")][key] += duration
monitoring.register_event_duration_secs_listener(listen)
kind, what = sys.argv[1], sys.argv[2]
if kind == "cli":
    import shlex
    from jaxdamp.cli import main
    code = main(shlex.split(what))
else:
    jax.config.update("jax_enable_x64", True)
    exec(what)
    code = 0
print("\n" + json.dumps({"code": code, "in_process_s": time.perf_counter() - t0,
                         "programs": events}))
"""


def _loops(tmp: Path) -> None:
    """Three moment loops of 720 samples as CSV files (the issue's fit-loops case; the loops whose
    programs the package ships, scripts/export_programs.py)."""
    code = ("import sys, jax; jax.config.update('jax_enable_x64', True)\n"
            f"sys.path.insert(0, {str(ROOT / 'scripts')!r})\n"
            "from export_programs import write_sample_loops\n"
            f"write_sample_loops({str(tmp)!r})\n")
    subprocess.run([sys.executable, "-c", code], check=True, env=dict(
        os.environ, JAXDAMP_CACHE_DIR="off",
        PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"))


def run_once(kind, what, cache: Path, tmp: Path) -> dict:
    env = dict(os.environ, JAXDAMP_CACHE_DIR=str(cache),
               PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", DRIVER, kind, what.format(tmp=tmp)], env=env,
                       capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{what}: exit {p.returncode}\n{p.stderr[-2000:]}")
    data = json.loads(p.stdout.strip().splitlines()[-1])
    programs = [{"program": name, **{k: round(v, 3) for k, v in d.items()}}
                for name, d in data["programs"].items()]
    programs.sort(key=lambda r: -(r.get("trace_s", 0) + r.get("lower_s", 0)
                                 + r.get("compile_s", 0)))
    totals = {k: round(sum(r.get(k, 0.0) for r in programs), 3)
              for k in ("trace_s", "lower_s", "compile_s", "cache_read_s")}
    return {"wall_s": round(wall, 3), "exit_code": data["code"], "totals": totals,
            "programs": programs[:12], "n_programs": len(programs)}


def main() -> None:
    from bench_common import loadavg

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", default="", help="comma-separated case names")
    ap.add_argument("--out", default=str(OUT / "compile_costs.json"))
    args = ap.parse_args()
    only = {s for s in args.only.split(",") if s}
    results = {}
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        _loops(tmp)
        for name, kind, what in CASES:
            if only and name not in only:
                continue
            cache = Path(tempfile.mkdtemp(dir=tmp))
            first = run_once(kind, what, cache, tmp)
            repeat = run_once(kind, what, cache, tmp)
            results[name] = {"kind": kind, "what": what, "first": first, "repeat": repeat,
                             "load_average_1min_after": loadavg()[0]}
            _write(args.out, results)
            print(f"{name:36s} first {first['wall_s']:7.2f} s (trace {first['totals']['trace_s']:.1f}"
                  f", lower {first['totals']['lower_s']:.1f}, compile "
                  f"{first['totals']['compile_s']:.1f}), repeat {repeat['wall_s']:6.2f} s",
                  flush=True)
    _write(args.out, results)
    print(f"wrote {args.out}")


def _write(out, results) -> None:
    from bench_common import machine

    doc = {"machine": machine(), "cases": results,
           "note": "wall_s: the whole process (Python start, imports, the command); trace/lower/"
                   "compile: sums over programs of JAX's own compile events"}
    Path(out).write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
