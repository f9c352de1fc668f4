#!/usr/bin/env bash
# Runs the test suite: installs missing Debian packages, configures, builds, runs ctest.
#   scripts/test.sh            fast tests (unit + MPI at 1, 2, 3 ranks); the CI set
#   scripts/test.sh --all      also the long validation runs (ctest label "long")
#   scripts/test.sh --preset asan   under AddressSanitizer + UBSan: the fast tests but the
#                                   5-minute rockfall run, MPI tests at 2 ranks (.ci/run does it)
#   extra arguments after -- go to ctest (e.g. -- -R Bond)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

preset="${RINGDEM_PRESET:-native}"
label_args=(-LE long)
ctest_extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --all) label_args=(); shift ;;
    --preset) preset="$2"; shift 2 ;;
    --) shift; ctest_extra=("$@"); break ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) ringdem_log "unknown option $1"; exit 2 ;;
  esac
done

ringdem_install_packages
# --- ParaView for the test labelled "clients" (tests/clients/paraview_frames.sh) ---
# Installed as root (about 140 packages, 146 MB; 50 s here); otherwise that test skips.
paraview_packages=(paraview python3-paraview xvfb)
if ! command -v pvpython >/dev/null || ! command -v Xvfb >/dev/null; then
  if [ "$(id -u)" -eq 0 ]; then
    ringdem_log "installing ParaView for the clients test: ${paraview_packages[*]}"
    { DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        "${paraview_packages[@]}"; } </dev/null >/dev/null ||
      ringdem_log "could not install ParaView: the clients test (paraview_frames) will skip"
  else
    ringdem_log "no pvpython/Xvfb and not root: the ParaView clients test will skip" \
      "(sudo apt-get install --no-install-recommends ${paraview_packages[*]})"
  fi
fi
ringdem_build "$preset"
cd "$RINGDEM_ROOT"
ctest --test-dir "build/$preset" --output-on-failure -j "$(nproc)" "${label_args[@]}" "${ctest_extra[@]}"
