#!/usr/bin/env bash
# Set up what is missing, build, and run the whole test suite (what CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd build
ctest --output-on-failure -j"${JOBS:-$(nproc)}" --timeout 600
