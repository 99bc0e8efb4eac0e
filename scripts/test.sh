#!/usr/bin/env bash
# Set up, run the whole test suite (including the notebooks and the documentation's code blocks),
# then build the documentation site with its API reference, where every warning is an error.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Two workers: one per core (the suite is mostly XLA compilation, one thread each). No reruns: a
# worker that crashes fails the run (docs/performance.md, "Worker crashes", says what they were).
.venv/bin/python -m pytest -n 2 "$@"
# Quiet: a passing build prints nothing, so pytest's summary stays the last line of the output.
NO_MKDOCS_2_WARNING=1 .venv/bin/mkdocs build --strict --quiet
