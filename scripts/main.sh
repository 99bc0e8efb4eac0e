#!/usr/bin/env bash
# The main job: set up, then reproduce the paper's study of the 60sym family into ./study_out.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
exec .venv/bin/jaxdamp study --out study_out "$@"
