#!/usr/bin/env bash
# Runs the main job: installs missing Debian packages, configures, builds, then
#   scripts/run.sh [CASE.yaml | debris] [ringdem run options...]
#   scripts/run.sh --help      this text (`ringdem run --help` lists the run options)
# Without CASE it runs the rockfall demo (inputs/rockfall/demo.yaml: a 200 kg boulder from
# 2 m onto a reduced net of 40 rings, about a minute and a half on 2 cores), draws its figures
# and says where the ParaView file is: results/rockfall_demo, or the folder that -o names.
# `debris` runs the debris-flow demo (inputs/debris/demo.yaml: about 10^5 grains into a meshed
# 10-ring net, about 4-5 minutes on 2 cores), draws its figures and checks its peak barrier
# force against the design guidance's hydrodynamic bounds. RINGDEM_RANKS=N runs on N MPI ranks (default: 1
# for a given case, up to 2 for the demos).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

if [ "${1:-}" = -h ] || [ "${1:-}" = --help ]; then
  sed -n '2,/^set -euo/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0"
  exit 0
fi

demo=1
demo_name=rockfall
case_file="$RINGDEM_ROOT/inputs/rockfall/demo.yaml"
if [ "${1:-}" = debris ]; then
  demo_name=debris
  case_file="$RINGDEM_ROOT/inputs/debris/demo.yaml"
  shift
elif [ $# -gt 0 ] && [[ "$1" != -* ]]; then
  case_file="$(realpath -m "$1")"  # relative to where the user stands
  demo=0
  shift
fi

ringdem_install_packages
ringdem_build "${RINGDEM_PRESET:-native}"
cd "$RINGDEM_ROOT"
binary="build/${RINGDEM_PRESET:-native}/ringdem"
if [ "$demo" -eq 0 ]; then
  ranks="${RINGDEM_RANKS:-1}"
  ringdem_log "running $case_file on $ranks rank(s)"
  exec mpirun -np "$ranks" "$binary" run "$case_file" "$@"
fi

cores=$(nproc)
ranks="${RINGDEM_RANKS:-$(( cores < 2 ? cores : 2 ))}"
# The demo's output folder, unless the user names one (-o DIR, --output DIR, --output=DIR).
out=results/${demo_name}_demo
args=("$@")
output_args=(-o "$out")
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[i]}" in
    -o|--output) [ $((i + 1)) -lt ${#args[@]} ] && out="${args[i + 1]}" && output_args=() ;;
    --output=*) out="${args[i]#--output=}"; output_args=() ;;
    -o?*) out="${args[i]#-o}"; output_args=() ;;
  esac
done
ringdem_log "running the $demo_name demo ($case_file) on $ranks rank(s), output in $out"
mpirun -np "$ranks" "$binary" run "$case_file" "${output_args[@]}" "$@"
if [ "$demo_name" = debris ]; then
  /usr/bin/python3 scripts/plot_debris.py "$out"
  /usr/bin/python3 scripts/check_debris_bounds.py "$out" --case "$case_file" || true
  ringdem_log "figures: $out/debris_force.png, debris_mass.png, debris_flow.png, debris_deposit.png"
  ringdem_log "ParaView: open $out/frames_0000.xdmf (XDMF Reader); the full case: docs/debris.md"
  exit 0
fi
/usr/bin/python3 scripts/plot_rockfall.py "$out" -o "$out"
ringdem_log "figures: $out/rockfall_acceleration.png, $out/rockfall_energy.png, $out/rockfall_snapshot_*.png"
ringdem_log "ParaView: open $out/frames_0000.xdmf (XDMF Reader); the paper's full net: docs/rockfall.md"
