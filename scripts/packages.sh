# sourced by scripts/setup.sh and scripts/fuzz.sh: install the Debian 12 packages that are
# missing (apt only when something is missing; as root or through sudo), and the npm packages
# of package-lock.json
ensure_packages() {
  command -v dpkg-query >/dev/null 2>&1 ||
    die "dpkg-query not found: this script supports Debian 12; install by hand: $*"
  local missing=() pkg status
  for pkg in "$@"; do
    status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
    [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
  done
  if ((${#missing[@]} == 0)); then
    echo "== packages: nothing missing ($# installed)"
    return 0
  fi
  local as_root=()
  if ((EUID != 0)); then
    command -v sudo >/dev/null 2>&1 || die "missing packages and not root, no sudo to install them; as root run:
  apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
    as_root=(sudo)
  fi
  echo "== installing: ${missing[*]}"
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
}

# `npm ci --ignore-scripts` in the repository root when node_modules is missing, or older than
# package-lock.json, or left incomplete by an interrupted run (npm ci writes
# node_modules/.package-lock.json last); otherwise nothing
ensure_node_modules() {
  local repo="$1"
  local stamp="$repo/node_modules/.package-lock.json"
  if [[ -f "$stamp" && -f "$repo/node_modules/uplot/dist/uPlot.iife.min.js" && ! "$repo/package-lock.json" -nt "$stamp" ]]; then
    echo "== npm packages: up to date (node_modules)"
    return 0
  fi
  command -v npm >/dev/null 2>&1 || die "npm not found: install the Debian package npm"
  echo "== installing the npm packages of package-lock.json (npm ci --ignore-scripts)"
  (cd "$repo" && npm ci --ignore-scripts --no-audit --no-fund)
}
