#!/usr/bin/env bash
# Configure and build the sanitized clang build in build-asan/: every perclod
# library and test with ASan + UBSan (-fno-sanitize-recover, so UBSan findings
# fail), plus the libFuzzer targets (tests/fuzz/), which need the same build.
# -O1 -gline-tables-only: ASan's recommended level, and line numbers in every
# report at a fraction of -g's compile and link time (2-core CI).
# Usage: scripts/build-asan.sh [TARGET...]   (default: everything but benchmarks)
set -euo pipefail
cd "$(dirname "$0")/.."
generator=(-G Ninja)  # as scripts/setup.sh; a build-asan/ made with Make keeps Make
[[ -f build-asan/CMakeCache.txt ]] && generator=()
cmake "${generator[@]}" -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  -DPERCLOD_SANITIZE=ON -DPERCLOD_BUILD_FUZZ=ON -DPERCLOD_BUILD_BENCH=OFF >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build-asan -j"${JOBS:-$(nproc)}" "${targets[@]}"
