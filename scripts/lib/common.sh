# Shared by scripts/demo and scripts/test: install missing Debian packages,
# configure and build. Sourced, not run.

# Debian 12 packages rigel builds with. Keep in sync with CMakeLists.txt.
RIGEL_PACKAGES=(
  g++ make cmake
  libeigen3-dev libtbb-dev nlohmann-json3-dev libcli11-dev
  libtinygltf-dev libpugixml-dev libgtest-dev libbenchmark-dev
  pybind11-dev python3-dev python3-pytest
  pkg-config libcpp-httplib-dev libspdlog-dev ccache
)
# What the Slurm path of `rigel batch` is tested with (tests/support/
# slurm_cluster.sh). Installed when it can be: where a package's setup
# cannot run (munge's post-install script in some chroots), the tests of
# that path say so and are skipped, and nothing else depends on it.
RIGEL_SLURM_PACKAGES=(slurm-wlm munge)

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

# rigel_ensure_packages, its failure reported and not fatal.
rigel_try_packages() {
  if ! (rigel_ensure_packages "$@"); then
    rigel_log "could not install $* (the tests that need them are skipped)"
    # A package whose setup failed stays half-configured; apt goes on
    # with the others next time.
    return 0
  fi
}

rigel_jobs() { nproc 2>/dev/null || echo 2; }

# Phase timings: rigel_phase NAME starts a phase (ending the one before);
# rigel_phase_report prints each phase's duration (scripts/test calls it on
# exit, so a failed run shows where its time went too).
RIGEL_PHASES=()
RIGEL_PHASE_NAME=""
RIGEL_PHASE_START=0
rigel_phase_end() {
  if [ -n "$RIGEL_PHASE_NAME" ]; then
    RIGEL_PHASES+=("$(( $(date +%s) - RIGEL_PHASE_START ))|$RIGEL_PHASE_NAME")
    RIGEL_PHASE_NAME=""
  fi
}
rigel_phase() {
  rigel_phase_end
  RIGEL_PHASE_NAME=$1
  RIGEL_PHASE_START=$(date +%s)
  rigel_log "$1"
}
rigel_phase_report() {
  rigel_phase_end
  local total=0 entry secs
  printf '\033[1m==> phase durations\033[0m\n' >&2
  for entry in "${RIGEL_PHASES[@]}"; do
    secs=${entry%%|*}
    total=$((total + secs))
    printf '  %4dm%02ds  %s\n' $((secs / 60)) $((secs % 60)) "${entry#*|}" >&2
  done
  printf '  %4dm%02ds  total\n' $((total / 60)) $((total % 60)) >&2
}

# Build output: on a terminal, cmake's "[ 42%] Building ..." lines are
# folded into one updating line; elsewhere (CI logs) they pass as they are.
# Warnings and errors always pass through whole.
rigel_progress() {
  if [ -t 2 ]; then
    awk '/^\[ *[0-9]+%\]|^(Consolidate compiler|Scanning dependencies)/ { printf "\r\033[K%s", substr($0, 1, 100) > "/dev/stderr"; fflush("/dev/stderr"); next }
         { printf "\r\033[K" > "/dev/stderr"; print > "/dev/stderr"; fflush("/dev/stderr") }
         END { printf "\r\033[K" > "/dev/stderr" }'
  else
    cat >&2
  fi
}

# rigel_build DIR [cmake options...]: configure (once) and build, showing
# progress (see rigel_progress).
rigel_build() {
  local dir=$1
  shift
  # ccache, when installed, makes a rebuild from a clean clone cheap.
  # The sloppiness lets ccache cache sources built with precompiled headers;
  # the base directory (the checkout) and no hashed working directory let a
  # clone in another folder (each CI run's) use what an earlier clone built:
  # its absolute paths are hashed as relative ones.
  if command -v ccache >/dev/null; then
    set -- -DCMAKE_CXX_COMPILER_LAUNCHER=ccache "$@"
    export CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
    export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
  fi
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S . -B "$dir" "$@" >/dev/null
  else
    cmake "$dir" "$@" >/dev/null
  fi
  cmake --build "$dir" -j "$(rigel_jobs)" 2>&1 | rigel_progress
  return "${PIPESTATUS[0]}"
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
