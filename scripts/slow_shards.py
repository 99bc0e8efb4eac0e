"""Write tests/slow_shards.json: every slow test assigned to one of the shards that CI rotates
through (tests/conftest.py), balanced by measured worker-seconds.

Usage (from the repository root, after runs that list their durations):
    .venv/bin/python -m pytest -n 2 --dist loadfile --junitxml=run.xml ...
    .venv/bin/python scripts/slow_shards.py [--shards N] run.xml [more.xml | durations.log ...]

Inputs: JUnit XML files (`--junitxml`) or pytest output with `--durations=0`; each test's setup,
call and teardown seconds are summed, the latest input winning. A slow test is one marked slow in
its file (`pytest --collect-only -m slow`), or one with no mark that an input measured over
tests/conftest.py's SLOW_SECONDS ("slow_by_measure", which conftest marks). A slow test no input
measured keeps the seconds the file last held for it (or, new, the median). A file's slow tests
are placed together (its module fixtures then cost one shard, not several), unless they sum to
more than an average shard; these units go longest first on the shard with the least work so far
(the greedy rule that keeps the largest shard within 4/3 of the best balance). The number of
shards stays what the file holds unless --shards says otherwise.
"""

from __future__ import annotations

import json
import re
import statistics
import subprocess
import sys
import xml.etree.ElementTree as ET
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TABLE = ROOT / "tests" / "slow_shards.json"
SLOW_SECONDS = 5.0  # tests/conftest.py's
LINE = re.compile(r"^\s*([0-9.]+)s (setup|call|teardown)\s+(.+?)\s*$")  # ids may hold spaces


def durations(path: Path) -> dict[str, float]:
    """{test id: seconds} of a JUnit XML file or of pytest's `--durations=0` output."""
    seconds: dict[str, float] = defaultdict(float)
    text = path.read_text()
    if text.lstrip().startswith("<"):
        for case in ET.fromstring(text).iter("testcase"):
            if case.find("skipped") is not None:
                continue
            file = case.get("classname").replace(".", "/") + ".py"
            seconds[f"{file}::{case.get('name')}"] += float(case.get("time"))
    else:
        for line in text.splitlines():
            m = LINE.match(line)
            if m:
                seconds[m.group(3)] += float(m.group(1))
    return dict(seconds)


def units(seconds: dict[str, float], n: int) -> dict[tuple[str, ...], float]:
    """The tests grouped into what is placed whole: a file's slow tests together (a module fixture
    is paid once per shard that runs any of its tests, and a run records its cost on one test
    only), each test alone in a file whose tests sum to more than an average shard."""
    files: dict[str, list[str]] = defaultdict(list)
    for nodeid in seconds:
        files[nodeid.split("::")[0]].append(nodeid)
    average = sum(seconds.values()) / n
    out = {}
    for ids in files.values():
        total = sum(seconds[i] for i in ids)
        groups = [[i] for i in ids] if total > average else [ids]
        out.update({tuple(sorted(g)): sum(seconds[i] for i in g) for g in groups})
    return out


def balance(seconds: dict[str, float], n: int) -> tuple[dict[str, int], list[float]]:
    load = [0.0] * n
    shards = {}
    for ids, s in sorted(units(seconds, n).items(), key=lambda kv: (-kv[1], kv[0])):
        k = min(range(n), key=lambda i: (load[i], i))
        shards.update({nodeid: k for nodeid in ids})
        load[k] += s
    return shards, load


def marked_slow(old_by_measure) -> set[str]:
    """The ids marked slow in their files (conftest's marks by measure taken out)."""
    out = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-o", "addopts=",
                          "-m", "slow", "-p", "no:cacheprovider"],
                         cwd=ROOT, capture_output=True, text=True)
    ids = {line for line in out.stdout.splitlines() if "::" in line}
    return ids - set(old_by_measure)


def main(argv) -> int:
    args = argv[1:]
    old = json.loads(TABLE.read_text()) if TABLE.exists() else {}
    n = int(old.get("n_shards", 4))
    if args[:1] == ["--shards"]:
        n, args = int(args[1]), args[2:]
    if not args:
        print(__doc__.strip().splitlines()[5], file=sys.stderr)  # the script's usage line
        return 2
    measured: dict[str, float] = {}
    for a in args:
        got = durations(Path(a))
        if not got:
            print(f"{a}: no durations (run pytest with --junitxml or --durations=0)", file=sys.stderr)
            return 2
        measured.update(got)
    old_by_measure = old.get("slow_by_measure", {})
    marked = marked_slow(old_by_measure)
    by_measure = {k: v for k, v in old_by_measure.items() if k not in measured}
    # Over the threshold as stored (rounded), so that the table says what conftest checks.
    by_measure.update({k: round(v, 1) for k, v in measured.items()
                       if k not in marked and round(v, 1) > SLOW_SECONDS})
    known = dict(old.get("seconds", {}))
    known.update({k: round(v, 1) for k, v in measured.items()})
    slow = marked | set(by_measure)
    fallback = statistics.median([known[k] for k in slow if k in known] or [60.0])
    seconds = {k: known.get(k, fallback) for k in slow}
    shards, load = balance(seconds, n)
    out = {"about": "tests marked slow -> the CI shard that runs them (scripts/slow_shards.py)",
           "n_shards": n,
           "worker_seconds_per_shard": [round(v, 1) for v in load],
           "shards": dict(sorted(shards.items())),
           "slow_by_measure": dict(sorted(by_measure.items())),
           "seconds": dict(sorted(seconds.items()))}
    TABLE.write_text(json.dumps(out, indent=1) + "\n")
    print(f"{len(slow)} slow tests ({len(by_measure)} by measure) in {n} shards; worker-seconds "
          "per shard:", ", ".join(f"{v:.0f}" for v in load))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
