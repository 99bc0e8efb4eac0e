"""In-phase speed of this checkout against an earlier commit, in alternating processes.

The VM's speed moves by a factor of two from day to day, so a figure measured today cannot be set
beside one committed last week (benchmarks/results/jobs.json). This runs `benchmarks/jobs.py`'s
raw floor on both sides, each side with its own jaxdamp and its own jobs.py: Base-Cycles/s of
`evaluate_designs` on 32 768 random designs (best of 5), XLA's flop count of one design in the
batched first stage, and the warm latency of one `cycle_numbers` call (median of 500), in
alternating fresh processes (base, this, base, this, ...), so that the machine's load hits both.

    python scripts/commit_ab.py                  # base: f2b97d2, before issue 34's engine
    python scripts/commit_ab.py --base REV --rounds 4

Writes benchmarks/results/commit_ab.json. The base is checked out with `git worktree` into a temporary folder
and removed afterwards. Where there is no git (a machine that gets a copy of the working tree):
`--base-tree DIR` names a folder that already holds the base's jaxdamp/ and benchmarks/ (e.g.
`git archive f2b97d2 jaxdamp benchmarks | tar -x -C DIR`), `--out FILE` the result.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results"
sys.path.insert(0, str(ROOT / "benchmarks"))  # bench_common: the machine record

from bench_common import machine  # noqa: E402
# The last commit before issue 34's one tract engine (2026-11-26 03:56): the in-phase speed the
# issue says must not get worse.
DEFAULT_BASE = "f2b97d2"

CHILD = """
import json, sys
import jobs, jaxdamp
tp = jobs.base_cycles_per_s(32768, 5)
lat = jobs.single_latency_us(500)
print(json.dumps({"jaxdamp": jaxdamp.__file__, "base_cycles_per_s": tp["per_s"],
                  "flops_per_design": tp.get("flops_per_design"), "latency_us": lat["us"],
                  "load_average_1min": tp["load_average_1min"]}))
"""


def run_side(tree: Path) -> dict:
    """One fresh process on `tree`'s jaxdamp and benchmarks/jobs.py (run from an empty folder, so
    that nothing else is importable as jaxdamp; the environment otherwise as this process's, so
    that JAX_PLATFORMS and an accelerator's libraries reach it)."""
    env = dict(os.environ, PYTHONPATH=f"{tree}:{tree / 'benchmarks'}")
    with tempfile.TemporaryDirectory() as cwd:
        out = subprocess.run([sys.executable, "-c", CHILD], cwd=cwd, env=env, check=True,
                             capture_output=True, text=True).stdout
    row = json.loads(out.strip().splitlines()[-1])
    if not row["jaxdamp"].startswith(str(tree)):
        raise RuntimeError(f"imported {row['jaxdamp']}, not the tree {tree}")
    return row


@contextlib.contextmanager
def _worktree(rev: str):
    """The commit checked out into a temporary folder (removed afterwards)."""
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "base"
        subprocess.run(["git", "worktree", "add", "--detach", "-q", str(tree), rev], cwd=ROOT,
                       check=True)
        try:
            yield tree
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT,
                           check=True)


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--base", default=DEFAULT_BASE, help="commit to compare against")
    p.add_argument("--rounds", type=int, default=4, help="alternating pairs of processes")
    p.add_argument("--base-tree", type=Path, default=None,
                   help="a folder holding the base's jaxdamp/ and benchmarks/ (no git needed)")
    p.add_argument("--this", default=None, help="the name of this checkout (default: git HEAD)")
    p.add_argument("--out", type=Path, default=OUT / "commit_ab.json")
    args = p.parse_args(argv)
    head = args.this or subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                                       check=True, capture_output=True, text=True).stdout.strip()
    t0 = time.perf_counter()
    info = machine()
    rows = []
    with contextlib.ExitStack() as stack:
        base_tree = (args.base_tree.resolve() if args.base_tree
                     else stack.enter_context(_worktree(args.base)))
        for k in range(args.rounds):
            for side, tree in (("base", base_tree), ("this", ROOT)):
                row = dict(run_side(tree), side=side, round=k)
                print(json.dumps(row), flush=True)
                rows.append(row)

    def summary(side):
        own = [r for r in rows if r["side"] == side]
        per_s = [r["base_cycles_per_s"] for r in own]
        lat = [r["latency_us"] for r in own]
        return {"base_cycles_per_s_median": statistics.median(per_s),
                "base_cycles_per_s_range": [min(per_s), max(per_s)],
                "latency_us_median": statistics.median(lat), "latency_us_range": [min(lat), max(lat)],
                "flops_per_design": own[0]["flops_per_design"]}

    result = {"machine": info, "base": args.base, "this": head, "rounds": args.rounds,
              "summary": {"base": summary("base"), "this": summary("this")}, "rows": rows,
              "seconds": time.perf_counter() - t0}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps(result["summary"], indent=1))
    return result


if __name__ == "__main__":
    main()
