#!/usr/bin/env bash
# Strong and weak scaling of whole runs (issue 4). Builds the native preset, generates the
# workloads with make_ring_grid.py and runs them at several rank counts.
#   scripts/bench/scaling.sh [MAX_RANKS]     (default: the number of cores)
# Strong: 200 rings (20 000 particles) at 1..MAX_RANKS ranks. Weak: 100 rings per rank.
# Ranks beyond the core count are oversubscribed and say so.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
ringdem_install_packages
ringdem_build native
cd "$RINGDEM_ROOT"
cores=$(nproc)
max_ranks="${1:-$cores}"
work=build/native/scaling
mkdir -p "$work"
py=/usr/bin/python3

run() {  # ranks case label
  local ranks=$1 case=$2 label=$3
  mpirun -np "$ranks" build/native/ringdem run "$case" -q -o "$work/$label" >/dev/null
  $py - "$work/$label/summary.json" "$ranks" "$cores" "$label" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); ranks = int(sys.argv[2]); cores = int(sys.argv[3])
rate = s["particle_steps_per_s"]
note = " (oversubscribed)" if ranks > cores else ""
print(f"{sys.argv[4]:<12} ranks {ranks:>2}  particles {s['particles']:>7}  "
      f"{rate:10.4g} particle-steps/s  {rate / ranks:10.4g} per rank  "
      f"{1e9 * ranks / rate:6.1f} ns/particle-step/rank{note}")
PY
}

$py scripts/bench/make_ring_grid.py --linked 20 10 "$work/strong.yaml"
echo "strong scaling, linked net of 200 rings = 20 000 particles, 2.5k steps:"
for ranks in $(seq 1 "$max_ranks"); do run "$ranks" "$work/strong.yaml" "strong_np$ranks"; done

echo "weak scaling, 100 rings = 10 000 particles per rank:"
for ranks in $(seq 1 "$max_ranks"); do
  $py scripts/bench/make_ring_grid.py --linked 10 $((10 * ranks)) "$work/weak_np$ranks.yaml"
  run "$ranks" "$work/weak_np$ranks.yaml" "weak_np$ranks"
done
