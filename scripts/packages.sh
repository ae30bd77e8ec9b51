# sourced by scripts/setup.sh and scripts/fuzz.sh: the package lists, installing the Debian 12
# packages that are missing (apt only then; as root or through sudo), and installing the npm
# packages of package-lock.json

# Debian 12 packages needed to build and test; nodejs and npm install the report page's
# charting library (package-lock.json), libcairo2-dev draws the static figures, pybind11-dev,
# python3-dev and python3-numpy build the Python module (docs/python.md); python3-scipy (Sobol
# and Latin-hypercube sampling), python3-nlopt (geometry optimisation) and python3-distributed
# (Dask) run design studies (docs/studies.md)
PACKAGES=(build-essential cmake ninja-build pkg-config libeigen3-dev libnlopt-cxx-dev coinor-libipopt-dev
          libsundials-dev libcli11-dev catch2 libtomlplusplus-dev nlohmann-json3-dev nodejs libcairo2-dev
          pybind11-dev python3-dev python3-numpy python3-scipy python3-nlopt python3-distributed)
# Debian's npm, unless an npm is already there: a nodejs from another source (NodeSource's
# packages bring their own npm and conflict with Debian's)
command -v npm >/dev/null 2>&1 || PACKAGES+=(npm)
# only for the tests: the headless browser that opens the reports, and pytest for the Python
# module's tests
TEST_PACKAGES=(chromium python3-pytest)
# clang, its sanitizer and libFuzzer runtimes, and its OpenMP runtime (SUNDIALSConfig.cmake asks
# for OpenMP_CXX): the sanitizer build (setup.sh --sanitize) and the fuzz build (fuzz.sh)
CLANG_PACKAGES=(clang libclang-rt-14-dev libomp-14-dev)

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
