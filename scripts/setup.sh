#!/usr/bin/env bash
# Install the Debian packages perclod needs (only those missing; one
# `apt-get update` only if something is missing), then configure and build
# into build/. Idempotent: a second run installs nothing and rebuilds only
# what changed. Usage: scripts/setup.sh [--no-build]
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  cmake g++ ninja-build pkg-config
  libosmesa6-dev          # offscreen OpenGL (llvmpipe)
  libembree-dev           # reference ray tracer
  libopenimageio-dev      # image I/O (PNG, TIFF, EXR)
  libopenmesh-dev         # half-edge meshes for the simplifier
  libeigen3-dev           # linear algebra (camera, quadrics)
  libgtest-dev            # tests
  libtbb-dev              # threads
  libassimp-dev           # model formats (OBJ, PLY, glTF, STL, IFC)
  libtinygltf-dev         # GLB export (header-only)
  libyaml-cpp-dev         # configs
  nlohmann-json3-dev      # JSON reports
  libcli11-dev            # command line
  zlib1g-dev              # packs the views and ID buffers a run keeps
  libproj-dev proj-data   # PROJ: a model's CRS (crs:, CityJSON referenceSystem) into the tileset's ECEF transform
  proj-bin                # cs2cs: the tests' reference positions
  libmeshoptimizer-dev    # peer simplifier for benchmarks
  clang libclang-rt-dev   # ASan/UBSan and libFuzzer stages (build-asan/); the runtimes are only a Recommends of clang
  python3 python3-matplotlib  # charts in scripts/
  butteraugli             # independent image metric in scripts/bench.py
  time                    # /usr/bin/time for the run-time benchmarks
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  if [[ $(id -u) -ne 0 ]]; then
    echo "setup: error: packages missing and not root; run as root or install: ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#PACKAGES[@]} packages present"
fi

[[ "${1:-}" == "--no-build" ]] && exit 0

JOBS=${JOBS:-$(nproc)}
# Ninja: it compiles a program's files while the libraries it links are still
# compiling, where Make waits for whole targets (a clean build on 2 cores:
# 247 s with Make, 219 s with Ninja). A build/ made with Make keeps Make.
generator=(-G Ninja)
[[ -f build/CMakeCache.txt ]] && generator=()
cmake "${generator[@]}" -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$JOBS"
echo "setup: built build/perclod"
