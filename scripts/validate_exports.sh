#!/usr/bin/env bash
# Validates perclod's viewer exports in output folders (docs/validation.md):
#  * every .glb under the folders with the Khronos glTF-Validator (npm
#    gltf-validator, pinned in scripts/validators/package-lock.json);
#  * every *tileset*.json with perclod's structural 3D Tiles check (content
#    files exist, volumes hold their content, errors shrink down the tree,
#    placement on the globe) and, when given, CesiumGS's 3d-tiles-validator.
# Prints per file errors/warnings/infos/hints and every message; exits 1 when
# any file has an error or a warning, 2 on a usage or setup error.
#
# Usage: scripts/validate_exports.sh [--json SUMMARY.json]
#                                    [--tiles-validator MAIN_JS] OUTPUT_FOLDER...
#   --json FILE          also write a JSON summary (counts and messages per file)
#   --tiles-validator F  the 3d-tiles-validator's entry point (build/main.js of
#                        a local build; default: $TILES_VALIDATOR). It is not on
#                        npm: without it that step is skipped with a note.
# Needs node >= 18: installs Debian's nodejs and npm when `node` is missing
# (apt-get, as root), and runs `npm ci` in scripts/validators when its
# node_modules is missing.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
validators=$here/validators

if [[ $# -lt 1 || "$1" == -h || "$1" == --help ]]; then
  sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi

args=()
tiles_validator=${TILES_VALIDATOR:-}
while [[ $# -gt 0 ]]; do
  case $1 in
    --json)
      [[ $# -ge 2 ]] || { echo "validate_exports: --json needs a file" >&2; exit 2; }
      args+=(--json "$2"); shift 2 ;;
    --tiles-validator)
      [[ $# -ge 2 ]] || { echo "validate_exports: --tiles-validator needs a file" >&2; exit 2; }
      tiles_validator=$2; shift 2 ;;
    -*) echo "validate_exports: unknown option $1" >&2; exit 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
if [[ -n "$tiles_validator" ]]; then
  [[ -f "$tiles_validator" ]] || { echo "validate_exports: 3d-tiles-validator $tiles_validator: no such file" >&2; exit 2; }
  args+=(--tiles-validator "$(realpath "$tiles_validator")")
fi

# shellcheck source=install_packages.sh
source "$(dirname "${BASH_SOURCE[0]}")/install_packages.sh"
command -v node > /dev/null || install_packages validate_exports nodejs npm
if ! node -e 'process.exit(+process.versions.node.split(".")[0] >= 18 ? 0 : 1)'; then
  echo "validate_exports: node $(node --version) is older than 18" >&2
  exit 2
fi
if [[ ! -d "$validators/node_modules/gltf-validator" ]]; then
  command -v npm > /dev/null || { echo "validate_exports: npm is missing (apt-get install npm)" >&2; exit 2; }
  echo "validate_exports: npm ci in $validators" >&2
  (cd "$validators" && npm ci --no-audit --no-fund >&2)
fi

exec node "$validators/validate.js" "${args[@]}"
