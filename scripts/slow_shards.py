"""Write tests/slow_shards.json: every test marked slow assigned to one of the SLOW_SHARDS shards
that CI rotates through (tests/conftest.py), balanced by measured worker-seconds.

Usage (from the repository root, after a run of the slow tier that lists every duration):
    .venv/bin/python -m pytest -n 2 --dist loadfile -m slow --durations=0 > slow.log
    .venv/bin/python scripts/slow_shards.py slow.log

Each test's setup, call and teardown seconds are summed; the tests are placed longest first on
the shard with the least work so far (the greedy rule that keeps the largest shard within 4/3 of
the best balance). Under `--dist loadfile` a file's tests of one shard run on one worker, so the
file each test belongs to is kept in the listing beside its seconds.
"""

from __future__ import annotations

import json
import re
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SLOW_SHARDS = 4  # tests/conftest.py's
LINE = re.compile(r"^\s*([0-9.]+)s (setup|call|teardown)\s+(\S+)")


def durations(log_text: str) -> dict[str, float]:
    seconds: dict[str, float] = defaultdict(float)
    for line in log_text.splitlines():
        m = LINE.match(line)
        if m:
            seconds[m.group(3)] += float(m.group(1))
    return dict(seconds)


def balance(seconds: dict[str, float], n: int = SLOW_SHARDS) -> tuple[dict[str, int], list[float]]:
    load = [0.0] * n
    shards = {}
    for nodeid, s in sorted(seconds.items(), key=lambda kv: (-kv[1], kv[0])):
        k = min(range(n), key=lambda i: (load[i], i))
        shards[nodeid] = k
        load[k] += s
    return shards, load


def main(argv) -> int:
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[3], file=sys.stderr)
        return 2
    seconds = durations(Path(argv[1]).read_text())
    if not seconds:
        print(f"{argv[1]}: no durations (run pytest with --durations=0)", file=sys.stderr)
        return 2
    shards, load = balance(seconds)
    out = {"about": "tests marked slow -> the CI shard that runs them (scripts/slow_shards.py)",
           "worker_seconds_per_shard": [round(v, 1) for v in load],
           "shards": dict(sorted(shards.items()))}
    (ROOT / "tests" / "slow_shards.json").write_text(json.dumps(out, indent=1) + "\n")
    print("worker-seconds per shard:", ", ".join(f"{v:.0f}" for v in load))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
