#!/usr/bin/env bash
# Set up, run the test suite (including the notebooks and the documentation's code blocks; the
# slow tier by rotating shards, below), then build the documentation site with its API reference,
# where every warning is an error.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Two workers: one per core (the suite is mostly XLA compilation, one thread each), each compiling
# its own programs (no persistent compilation cache: tests/conftest.py says why), a whole test file
# at a time (--dist loadfile), so that a file's programs compile in one worker, not in both. No
# reruns: a worker that crashes fails the run (docs/performance.md, "Worker crashes").
# Every test not marked slow, and one shard of those marked slow (the heavy end-to-end tests,
# nearly all XLA compilation of long programs): the shard is the commit count of the checkout
# modulo the number of shards (`--slow-shard auto`; tests/conftest.py, tests/slow_shards.json), so
# consecutive landings rotate through the slow tier (README). `--shard K` picks shard K; `--full`
# runs every test and prints the time it took.
tier=(--slow-shard auto)
full=0
if [[ "${1:-}" == "--full" ]]; then tier=(); full=1; shift
elif [[ "${1:-}" == "--shard" ]]; then tier=(--slow-shard "${2:?--shard needs K}"); shift 2
fi
[[ $full == 1 ]] && echo "test.sh: every test, the slow tier whole"
start=$SECONDS
# --durations: every run lists its 25 slowest tests, where the next cut of the suite starts.
.venv/bin/python -m pytest -n 2 --dist loadfile --durations=25 "${tier[@]}" "$@"
[[ $full == 1 ]] && echo "test.sh --full: the tests took $(( (SECONDS - start) / 60 )) min $(( (SECONDS - start) % 60 )) s"
# Quiet: a passing build prints nothing, so pytest's summary stays the last line of the output.
NO_MKDOCS_2_WARNING=1 .venv/bin/mkdocs build --strict --quiet
