#!/usr/bin/env bash
# Strong and weak scaling of whole runs (issue 4, issue 13 item 5). Builds the native preset,
# generates the workloads and runs them at several rank counts.
#   scripts/bench/scaling.sh [MAX_RANKS] [GRAINS_PER_RANK]   (default: the number of cores, 0)
# Strong: 200 rings (20 000 particles) at 1..MAX_RANKS ranks. Weak: 100 rings per rank.
# With GRAINS_PER_RANK > 0 also weak scaling of a flowing packing (the `flow` bed of
# scripts/bench/peer_granular.py: 5 mm grains sliding down a 35 degree incline, rebuilding
# every ~35 steps) of about that many grains per rank, at 1, 2, 4, ... MAX_RANKS ranks, with
# the loop's time per particle-step and the largest rank's peak memory.
# Ranks beyond the core count are oversubscribed and say so.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
ringdem_install_packages
ringdem_build native
cd "$RINGDEM_ROOT"
cores=$(nproc)
max_ranks="${1:-$cores}"
grains_per_rank="${2:-0}"
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

[ "$grains_per_rank" -gt 0 ] || exit 0
echo "weak scaling, flowing packing of about $grains_per_rank grains per rank:"
ranks=1
while [ "$ranks" -le "$max_ranks" ]; do
  case=$($py - "$work" "$((grains_per_rank * ranks))" <<'PY'
import os, sys
sys.path.insert(0, os.path.join(os.getcwd(), "scripts", "bench"))
import peer_granular
print(peer_granular.write_ringdem(sys.argv[1], "flow", int(sys.argv[2])))
PY
)
  peak=$( { /usr/bin/time -f "%M" mpirun -np "$ranks" build/native/ringdem run "$case" -q \
            -o "$work/flow_np$ranks" --force-size >/dev/null; } 2>&1 | tail -1)
  $py - "$work/flow_np$ranks/summary.json" "$ranks" "$cores" "$peak" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); ranks = int(sys.argv[2]); cores = int(sys.argv[3])
peak_mib = int(sys.argv[4]) / 1024
note = " (oversubscribed)" if ranks > cores else ""
per_rank = s["particles"] / ranks
print(f"flow         ranks {ranks:>2}  grains {s['particles']:>8}  "
      f"{1e9 * ranks / s['particle_steps_per_s']:6.1f} ns/particle-step/rank  "
      f"largest rank {peak_mib:7.1f} MiB = {peak_mib * 2**20 / per_rank:5.0f} B/grain{note}")
PY
  ranks=$((ranks * 2))
done
