#!/usr/bin/env bash
# Set up, run the whole test suite (including the notebooks and the documentation's code blocks),
# then build the documentation site with its API reference, where every warning is an error.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Two workers: one per core (the suite is mostly XLA compilation, one thread each). A test whose
# worker process crashes runs once more in a fresh worker; an ordinary failure is never rerun.
# Crashes seen on 2026-11-24 (1-2 per run, each in a different test): segfaults inside jaxlib, in
# reading a persistent-cache entry, in compiling, and in serialising an executable for the cache.
# A cache folder per worker (no shared entries) still crashed twice, and its fresh-clone run had
# not finished after 24 min (13 min shared), so the workers share one cache.
.venv/bin/python -m pytest -n 2 --reruns 1 --only-rerun "crashed while running" "$@"
# Quiet: a passing build prints nothing, so pytest's summary stays the last line of the output.
NO_MKDOCS_2_WARNING=1 .venv/bin/mkdocs build --strict --quiet
