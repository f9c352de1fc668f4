#!/usr/bin/env bash
# Runs the main job: installs missing Debian packages, configures, builds, then
#   scripts/run.sh [CASE.yaml] [ringdem run options...]
# RINGDEM_RANKS=N runs on N MPI ranks (default 1). Without CASE it runs the default case.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

case_file="$RINGDEM_ROOT/inputs/demo/ring_on_pin.yaml"
if [ $# -gt 0 ] && [[ "$1" != -* ]]; then
  case_file="$(realpath -m "$1")"  # relative to where the user stands
  shift
fi

ringdem_install_packages
ringdem_build "${RINGDEM_PRESET:-native}"
cd "$RINGDEM_ROOT"
ranks="${RINGDEM_RANKS:-1}"
ringdem_log "running $case_file on $ranks rank(s)"
exec mpirun -np "$ranks" "build/${RINGDEM_PRESET:-native}/ringdem" run "$case_file" "$@"
