#!/usr/bin/env bash
# Strong and weak scaling of whole runs (issue 4, issue 12, issue 13 item 5). Builds the native
# preset, generates the workloads and runs them at several rank counts.
#   scripts/bench/scaling.sh [MAX_RANKS] [GRAINS_PER_RANK]   (default: the number of cores, 0)
# Strong: 200 rings (20 000 particles) at 1..MAX_RANKS ranks. Weak: 100 rings per rank.
# With GRAINS_PER_RANK > 0 also weak scaling of a bed of grains (SCALING_BED, a variant of
# scripts/bench/peer_granular.py: `flow`, the default, 5 mm grains sliding down a 35 degree
# incline without touching, rebuilding every ~35 steps; or `dense`, the same block in contact,
# every grain pressed into its six neighbours) of about that many grains per rank, at 1, 2, 4,
# ... MAX_RANKS ranks, with the loop's time per particle-step, the largest rank's peak memory
# and the phases over the ranks (mean and most: a most well above the mean is waiting). The
# part `copies` then runs the same numbers of independent 1-rank copies at once: the node's own
# limit (memory bandwidth) without any MPI traffic, to tell the code's loss from the machine's.
# The part `peer` (not run unless named in SCALING_PARTS) runs LAMMPS (GRANULAR) on the weak
# sweep's 1-rank and MAX_RANKS cases of the bed, the same input as the peer script's, and prints
# both codes' loop time per particle-step and rank.
# Ranks beyond the core count are oversubscribed and say so.
# Environment: RINGDEM_BINARY (a built ringdem: no package install, no build), MPIRUN (the
# launcher, default mpirun), MPIRUN_FLAGS (e.g. "--bind-to core"), PYTHON (default
# /usr/bin/python3), SCALING_PARTS (of strong weak flow peer copies, run in that order; default
# "strong weak flow copies"; "flow" is the grains' sweep whatever the bed), SCALING_BED
# (default flow), LAMMPS (default lmp).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
cd "$RINGDEM_ROOT"
binary="${RINGDEM_BINARY:-}"
if [ -z "$binary" ]; then
  ringdem_install_packages
  ringdem_build native
  binary=build/native/ringdem
fi
mpirun_cmd="${MPIRUN:-mpirun}"
read -r -a mpirun_flags <<<"${MPIRUN_FLAGS:-}"
parts="${SCALING_PARTS:-strong weak flow copies}"
bed="${SCALING_BED:-flow}"
cores=$(nproc)
max_ranks="${1:-$cores}"
grains_per_rank="${2:-0}"
work="${SCALING_WORK:-build/native/scaling}"
mkdir -p "$work"
py="${PYTHON:-/usr/bin/python3}"

report() {  # summary.json ranks label
  "$py" - "$1" "$2" "$cores" "$3" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); ranks = int(sys.argv[2]); cores = int(sys.argv[3])
rate = s["particle_steps_per_s"]
note = " (oversubscribed)" if ranks > cores else ""
peak = s.get("peak_memory_largest_rank_bytes", 0) / 2**20
shared = s.get("shared_memory_largest_rank_bytes", 0) / 2**20
phases = s.get("time_per_phase_s", {})
spread = "  ".join(f"{k} {v['mean']:.2f}/{v['max']:.2f}" for k, v in phases.items()
                   if v["max"] > 0.005)
print(f"{sys.argv[4]:<12} ranks {ranks:>2}  particles {s['particles']:>8}  "
      f"{1e9 * ranks / rate:6.1f} ns/particle-step/rank  largest rank {peak:7.1f} MiB "
      f"= {peak * 2**20 * ranks / s['particles']:5.0f} B/particle{note}")
if shared >= 1:
    # MPI's on-node segments, counted by every rank that maps them (docs/scaling.md).
    print(f"{'':<12} of the peak, shared (MPI's on-node buffers): at most {shared:.1f} MiB a rank, "
          f"{peak - shared:.1f} MiB without")
print(f"{'':<12} phases, mean/most over the ranks (s): {spread}")
PY
}

run() {  # ranks case label
  local ranks=$1 case=$2 label=$3
  "$mpirun_cmd" -np "$ranks" "${mpirun_flags[@]}" "$binary" run "$case" -q -o "$work/$label" \
    --force-size >/dev/null
  report "$work/$label/summary.json" "$ranks" "$label"
}

if [[ " $parts " == *" strong "* ]]; then
  $py scripts/bench/make_ring_grid.py --linked 20 10 "$work/strong.yaml"
  echo "strong scaling, linked net of 200 rings = 20 000 particles, 2.5k steps:"
  for ranks in $(seq 1 "$max_ranks"); do run "$ranks" "$work/strong.yaml" "strong_np$ranks"; done
fi

if [[ " $parts " == *" weak "* ]]; then
  echo "weak scaling, 100 rings = 10 000 particles per rank:"
  for ranks in $(seq 1 "$max_ranks"); do
    $py scripts/bench/make_ring_grid.py --linked 10 $((10 * ranks)) "$work/weak_np$ranks.yaml"
    run "$ranks" "$work/weak_np$ranks.yaml" "weak_np$ranks"
  done
fi

[ "$grains_per_rank" -gt 0 ] || exit 0
case "$bed" in flow | dense) ;; *) echo "SCALING_BED must be flow or dense, not '$bed'" >&2; exit 2 ;; esac
bed_case() {  # grains [code] -> path of the case file (code: ringdem or lammps)
  $py - "$work" "$bed" "$1" "${2:-ringdem}" <<'PY'
import os, sys
sys.path.insert(0, os.path.join(os.getcwd(), "scripts", "bench"))
import peer_granular
work, variant, n, code = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
write = peer_granular.write_ringdem if code == "ringdem" else peer_granular.write_lammps
print(write(work, variant, n))
PY
}
if [[ " $parts " == *" flow "* ]]; then
  echo "weak scaling, $bed bed of about $grains_per_rank grains per rank:"
  ranks=1
  while [ "$ranks" -le "$max_ranks" ]; do
    run "$ranks" "$(bed_case $((grains_per_rank * ranks)))" "${bed}_np$ranks"
    ranks=$((ranks * 2))
  done
fi

if [[ " $parts " == *" peer "* ]]; then
  lammps="${LAMMPS:-lmp}"
  echo "LAMMPS on the $bed bed, the same input as the peer script's (loop time, as ringdem's):"
  for ranks in 1 "$max_ranks"; do
    input=$(bed_case $((grains_per_rank * ranks)) lammps)
    log="$work/lammps_${bed}_np$ranks.log"
    "$mpirun_cmd" -np "$ranks" "${mpirun_flags[@]}" "$lammps" -in "$input" \
      -log none >"$log" 2>&1 || { echo "LAMMPS failed at $ranks ranks: $log" >&2; exit 1; }
    "$py" - "$log" "$ranks" "$work/${bed}_np$ranks/summary.json" <<'PY'
import json, os, re, sys
text = open(sys.argv[1]).read()
ranks = int(sys.argv[2])
m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
mem = re.search(r"Per MPI rank memory allocation \(min/avg/max\) = [0-9.]+ \| [0-9.]+ \| ([0-9.]+) Mbytes", text)
ns = 1e9 * float(m.group(1)) * ranks / (int(m.group(3)) * int(m.group(4)))
line = f"lammps       ranks {ranks:>2}  particles {int(m.group(4)):>8}  {ns:6.1f} ns/particle-step/rank"
if mem:
    line += f"  its own estimate, largest rank {float(mem.group(1)):7.1f} MiB"
if os.path.exists(sys.argv[3]):
    s = json.load(open(sys.argv[3]))
    ours = 1e9 * ranks / s["particle_steps_per_s"]
    line += f"\n{'':<12} ringdem's {ours:6.1f} ns on the same case: {ours / ns:.2f} of LAMMPS's time"
print(line)
PY
  done
fi

[[ " $parts " == *" copies "* ]] || exit 0
echo "control: N independent 1-rank copies of the 1-rank $bed bed at once (no MPI traffic):"
one=$(bed_case "$grains_per_rank")
copies=1
while [ "$copies" -le "$max_ranks" ] && [ "$copies" -le "$cores" ]; do
  pids=()
  for i in $(seq 0 $((copies - 1))); do
    # Each launcher would bind its one rank to the same first core: pin the copies instead.
    pin=(); command -v taskset >/dev/null && pin=(taskset -c "$i")
    "${pin[@]}" "$mpirun_cmd" -np 1 --bind-to none "$binary" run "$one" -q \
      -o "$work/copy${copies}_$i" --force-size >/dev/null &
    pids+=($!)
  done
  wait "${pids[@]}"
  "$py" - "$work" "$copies" <<'PY'
import json, sys
w, n = sys.argv[1], int(sys.argv[2])
ns = sorted(1e9 / json.load(open(f"{w}/copy{n}_{i}/summary.json"))["particle_steps_per_s"]
            for i in range(n))
print(f"copies {n:>2}  ns/particle-step: least {ns[0]:6.1f}  median {ns[len(ns) // 2]:6.1f}  "
      f"most {ns[-1]:6.1f}")
PY
  copies=$((copies * 2))
done
