#!/usr/bin/env bash
# Opens a perclod HTML page (OUT/<model>_report.html or a batch index.html)
# in headless Chromium and fails when the browser could not show it whole:
#  * a console error or warning, an uncaught JavaScript error, a resource
#    that did not load (a missing image: net::ERR_FILE_NOT_FOUND) or an
#    image that did not decode, lazy ones included (scripts/check_report.py);
#  * a blank screenshot (one colour, or too few colours to be the page).
# Usage: scripts/check_report.sh REPORT_HTML [SCREENSHOT.png]
#   SCREENSHOT defaults to <page>.png in a temporary directory; it is kept.
# Installs Debian's chromium when missing (apt-get, as root: it is large, so
# this is a script to run by hand, not a CI step). The screenshot check uses
# /usr/bin/python3 with PIL (python3-pil), not whatever python is first on PATH.
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 || "$1" == -h || "$1" == --help ]]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
page=$1
[[ -f "$page" ]] || { echo "check_report: $page: no such file" >&2; exit 2; }
page_abs=$(realpath "$page")
page_dir=$(dirname "$page_abs")
work=$(mktemp -d /tmp/check_report.XXXXXX)
shot=${2:-$work/$(basename "${page%.*}").png}
shot=$(realpath -m "$shot")
mkdir -p "$(dirname "$shot")"

# shellcheck source=install_packages.sh
source "$(dirname "${BASH_SOURCE[0]}")/install_packages.sh"
command -v chromium >/dev/null || install_packages check_report chromium
[[ -x /usr/bin/python3 ]] && /usr/bin/python3 -c 'import PIL' 2>/dev/null || install_packages check_report python3-pil

status=0
# 1. Load the page (scripts/check_report.py drives Chromium over the DevTools
#    pipe): console errors, uncaught exceptions, failed loads and images that
#    did not decode are reported as events; writes the screenshot.
/usr/bin/python3 "$(dirname "$0")/check_report.py" "$(command -v chromium)" "$page_abs" "$shot" "$work/profile" ||
  status=$?
if [[ $status -ge 2 ]]; then
  echo "check_report: could not drive chromium; its log:" >&2
  tail -20 "$work/profile.log" >&2
  exit 2
fi
[[ -s "$shot" ]] || { echo "check_report: no screenshot written" >&2; exit 1; }

# 2. A blank page screenshots as one colour (white) or nearly so.
/usr/bin/python3 - "$shot" <<'PY' || status=1
import sys
from PIL import Image
im = Image.open(sys.argv[1]).convert("RGB")
w, h = im.size
colours = im.getcolors(maxcolors=1 << 24) or []
distinct = len(colours)
background = max(colours)[0] / (w * h) if colours else 1.0
print(f"check_report: screenshot {sys.argv[1]}: {w}x{h}, {distinct} distinct colours, "
      f"{100 * (1 - background):.1f}% not background")
if distinct < 16 or background > 0.995:
    print("check_report: the screenshot looks blank", file=sys.stderr)
    sys.exit(1)
PY

rm -rf "$work/profile"
if [[ $status -eq 0 ]]; then
  echo "check_report: OK: $page (screenshot $shot)"
else
  echo "check_report: FAILED: $page (screenshot $shot, browser logs in $work)" >&2
fi
exit $status
