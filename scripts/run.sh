#!/usr/bin/env bash
# Set up what is missing, build, and run the demo job (configs/demo.yaml) on
# the bundled Ingolstadt building. Results go to out/ (see docs/usage.md#output-files).
# Usage: scripts/run.sh [CONFIG]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/perclod run "${1:-configs/demo.yaml}"
