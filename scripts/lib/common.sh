# Shared by scripts/demo and scripts/test: install missing Debian packages,
# configure and build. Sourced, not run.

# Debian 12 packages rigel builds with. Keep in sync with CMakeLists.txt.
RIGEL_PACKAGES=(
  g++ make cmake
  libeigen3-dev libtbb-dev nlohmann-json3-dev libcli11-dev
  libtinygltf-dev libpugixml-dev libgtest-dev libbenchmark-dev
  pybind11-dev python3-dev python3-pytest
  pkg-config libcpp-httplib-dev
)

rigel_log() { printf '\033[1m==> %s\033[0m\n' "$*" >&2; }

# Installs whichever of the given packages are missing (apt-get, as root or
# through sudo). Quick when everything is there: one dpkg-query.
rigel_ensure_packages() {
  local missing=() pkg
  for pkg in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$pkg")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  rigel_log "installing ${missing[*]}"
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null; then sudo=(sudo); else
      echo "rigel: missing packages: ${missing[*]}; run as root or install them with apt-get" >&2
      return 1
    fi
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -q
  "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
}

rigel_jobs() { nproc 2>/dev/null || echo 2; }

# rigel_build DIR [cmake options...]: configure (once) and build.
rigel_build() {
  local dir=$1
  shift
  # ccache, when installed, makes a rebuild from a clean clone cheap.
  if command -v ccache >/dev/null; then
    set -- -DCMAKE_CXX_COMPILER_LAUNCHER=ccache "$@"
  fi
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S . -B "$dir" "$@" >/dev/null
  else
    cmake "$dir" "$@" >/dev/null
  fi
  cmake --build "$dir" -j "$(rigel_jobs)"
}

# Node.js and npm for the web app: the machine's own when it has them (a
# NodeSource install ships npm inside its nodejs package), else Debian's.
rigel_ensure_node() {
  if command -v node >/dev/null && command -v npm >/dev/null; then return 0; fi
  rigel_ensure_packages nodejs npm
}

# Builds the web app (TypeScript + three.js, bundled by esbuild) into
# web/dist, which `rigel serve` serves. npm ci runs when node_modules is
# missing or older than the lock file.
rigel_build_web() {
  rigel_ensure_node
  (
    cd web
    if [ ! -f node_modules/.package-lock.json ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
      rigel_log "npm ci (web app)"
      npm ci --no-audit --no-fund --loglevel=error
    fi
    rigel_log "building the web app"
    npm run --silent build
  )
}
