#!/usr/bin/env bash
# Set up, then run the whole test suite (including the notebooks).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Two workers: one per core (the suite is mostly XLA compilation, one thread each).
exec .venv/bin/python -m pytest -n 2 "$@"
