#!/usr/bin/env bash
# Opens perclod's 3D Tiles exports in a real client, CesiumJS in headless
# Chromium (WebGL through SwiftShader), and checks that each LOD is drawn at
# the distances its manifest says it serves, lit and where its tiles are:
#  * for every <model>_tileset.json (with its <model>_manifest.json) in the
#    folders: the camera inside each LOD's serving range and at 0.9x and 1.1x
#    of each switch distance, from the south facade and from the south-west;
#  * passes when the drawn tile is the manifest's LOD, the picture is not
#    blank, the model's pixels lie in its bounding box, faces of different
#    orientation are shaded differently, and the console has no error.
# Usage: scripts/check_cesium.sh [--json FILE] [--shots DIR] [--timeout S]
#                                [--force-unlit] OUTPUT_FOLDER [more folders]
# Installs what is missing: Debian's chromium, nodejs and npm (only if there
# is no node), then the pinned npm packages in scripts/cesium (npm ci).
# Serves only on 127.0.0.1; the page is kept from every other host.
# Exit status 0 passed, 1 a check failed, 2 the check could not run.
# docs/clients.md: what is checked, how, and the results on the demo.
set -euo pipefail

if [[ $# -lt 1 || "$1" == -h || "$1" == --help ]]; then
  sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
dir="$(cd "$(dirname "$0")" && pwd)/cesium"

# shellcheck source=install_packages.sh
source "$(dirname "${BASH_SOURCE[0]}")/install_packages.sh"

[[ -x /usr/lib/chromium/chromium ]] || command -v chromium >/dev/null || install_packages check_cesium chromium
command -v node >/dev/null || install_packages check_cesium nodejs npm
command -v npm >/dev/null || install_packages check_cesium npm
node_major=$(node -p 'process.versions.node.split(".")[0]')
if ((node_major < 18)); then
  echo "check_cesium: node $(node --version) is too old: puppeteer-core needs 18 or newer (Debian 12 has 18)" >&2
  exit 2
fi

# The pinned packages (package-lock.json), again when the lock file changed.
if [[ ! -f "$dir/node_modules/.package-lock.json" || "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]]; then
  echo "check_cesium: npm ci in $dir" >&2
  (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error >&2)
fi

exec node "$dir/check.mjs" "$@"
