# Shared set-up for scripts/run.sh and scripts/test.sh: Debian packages, MPI environment,
# configure and build. Sourced, not run.

RINGDEM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
RINGDEM_PACKAGES=(
  cmake make g++ pkg-config
  libopenmpi-dev openmpi-bin libhdf5-openmpi-dev libmetis-dev libeigen3-dev
  libyaml-cpp-dev libcli11-dev libfmt-dev libnlopt-dev nlohmann-json3-dev libgtest-dev
  libbenchmark-dev
  python3-numpy python3-h5py python3-matplotlib python3-yaml
)

# Open MPI refuses root and more ranks than cores unless told; CI and containers run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# Keep Open MPI quiet about missing high-speed fabrics on a workstation.
export OMPI_MCA_btl_base_warn_component_unused=0
# Messages between ranks of one node through Open MPI's shared-memory fragments instead of its
# single-copy path (a process_vm_readv system call for each message above 4 KB, costly on a
# virtual machine): on the project's 2-core instance the coarse debris demo ran 15 % faster with
# the same results, r12 and the full debris case as fast (docs/performance.md, thirty-first
# round).
# A value set before is kept.
export OMPI_MCA_btl_vader_single_copy_mechanism="${OMPI_MCA_btl_vader_single_copy_mechanism:-none}"

ringdem_log() { printf '[ringdem] %s\n' "$*" >&2; }

# ringdem_missing_packages PACKAGE...: the ones not installed, one per line.
ringdem_missing_packages() {
  local p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}

# ringdem_apt_install PACKAGE...: apt-get without questions (root only).
ringdem_apt_install() {
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq </dev/null
  apt-get install -y -qq --no-install-recommends "$@" </dev/null
}

# ringdem_install_packages: what the build and the tests need (RINGDEM_PACKAGES); as root it
# installs the missing ones, otherwise it says how and stops.
ringdem_install_packages() {
  local missing
  mapfile -t missing < <(ringdem_missing_packages "${RINGDEM_PACKAGES[@]}")
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -eq 0 ]; then
    ringdem_log "installing missing Debian packages: ${missing[*]}"
    ringdem_apt_install "${missing[@]}"
  else
    ringdem_log "missing Debian packages: ${missing[*]}"
    ringdem_log "install them with: sudo apt-get install ${missing[*]}"
    exit 1
  fi
}

# ringdem_install_optional WHAT PACKAGE...: installs packages an optional test needs (ctest
# label clients) when root; otherwise says how, and returns 1 (the test then skips itself).
ringdem_install_optional() {
  local what="$1" missing
  shift
  mapfile -t missing < <(ringdem_missing_packages "$@")
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -eq 0 ]; then
    ringdem_log "installing for the $what test: ${missing[*]}"
    ringdem_apt_install "${missing[@]}"
  else
    ringdem_log "the $what test is skipped: it needs ${missing[*]}" \
      "(sudo apt-get install --no-install-recommends ${missing[*]})"
    return 1
  fi
}

# ringdem_build PRESET: configure (once) and build with all cores.
ringdem_build() {
  local preset="$1"
  cd "$RINGDEM_ROOT"
  if [ ! -f "build/$preset/CMakeCache.txt" ]; then
    ringdem_log "configuring ($preset)"
    cmake --preset "$preset" >/dev/null
  fi
  ringdem_log "building ($preset)"
  cmake --build --preset "$preset" -j "$(nproc)"
}
