# Sourced by the check scripts: install_packages TOOL PACKAGE... installs the
# Debian packages among PACKAGE that are missing (apt-get, as root; one
# `apt-get update` only then), or exits 2 naming them when not root.
# Progress goes to stderr, so a script's stdout stays its own.
install_packages() {
  local tool=$1 missing=()
  shift
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0
  if [[ $(id -u) -ne 0 ]]; then
    echo "$tool: needs ${missing[*]}: run as root or: sudo apt-get install ${missing[*]}" >&2
    exit 2
  fi
  echo "$tool: installing ${missing[*]} (apt-get)" >&2
  apt-get update -qq >&2
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends "${missing[@]}" >&2
}
