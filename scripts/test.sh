#!/usr/bin/env bash
# Set up, run the whole test suite (including the notebooks and the documentation's code blocks),
# then build the documentation site with its API reference, where every warning is an error.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Two workers: one per core (the suite is mostly XLA compilation, one thread each), each compiling
# its own programs (no persistent compilation cache: tests/conftest.py says why), a whole test file
# at a time (--dist loadfile), so that a file's programs compile in one worker, not in both. No
# reruns: a worker that crashes fails the run (docs/performance.md, "Worker crashes").
# The default tier leaves out the tests marked slow (over 10 worker-seconds each, nearly all XLA
# compilation of long end-to-end programs): `--full` runs them too (README gives both times).
tier=(-m "not slow")
if [[ "${1:-}" == "--full" ]]; then tier=(); shift; fi
# --durations: every run lists its 25 slowest tests, where the next cut of the suite starts.
.venv/bin/python -m pytest -n 2 --dist loadfile --durations=25 "${tier[@]}" "$@"
# Quiet: a passing build prints nothing, so pytest's summary stays the last line of the output.
NO_MKDOCS_2_WARNING=1 .venv/bin/mkdocs build --strict --quiet
