#!/usr/bin/env bash
# Runs the test suite: installs missing Debian packages, configures, builds, runs ctest.
#   scripts/test.sh            fast tests (unit + MPI at 1, 2, 3 ranks, clients); the CI set
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
# Real clients (ctest label clients): ParaView renders the frames (tests/clients/
# paraview_frames.sh; about 140 packages, 146 MB) and a one-node SLURM cluster runs the batch
# script (tests/clients/slurm_cluster_test.sh). Installed as root in one apt-get call;
# otherwise each of those tests skips itself with a message.
ringdem_install_optional clients paraview python3-paraview xvfb slurm-wlm munge || true
ringdem_build "$preset"
cd "$RINGDEM_ROOT"
ctest --test-dir "build/$preset" --output-on-failure -j "$(nproc)" "${label_args[@]}" "${ctest_extra[@]}"
