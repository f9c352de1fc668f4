#!/usr/bin/env bash
# The start-up size estimate (io/SizeEstimate.hpp), against which `ringdem run` refuses cases
# too large for the machine, must bound the memory runs really take, and not by so much that
# it refuses cases that fit: for a bed of 64 000 grains on 1 and 2 ranks, for 1 000 grains
# writing 1 000 frames on 2 ranks (the frame file's HDF5 metadata cache grows with the frames)
# and for the paper's 180-ring net (18 504 particles, 18 000 bonds) on 1 rank, the largest
# rank's measured peak (summary.json) must lie between 0.4 times the estimate and the estimate
# (the fixed costs weigh most in cases this small).
# Native builds only: the sanitizers multiply the memory.
# usage: size_estimate_bounds.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$1
source_dir=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/bed.yaml" <<'YAML'
schema_version: 1
name: bed
simulation: {dt: 1.31e-5, end_time: 6.55e-4, gravity: [0, 0, -9.81], skin: 0.001}
output: {frame_interval: 0, checkpoint_interval: 0}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e9, poisson_ratio: 0.25, restitution: 0.3,
     friction: 0.5}
particles:
  lattices:
    - {material: rock, origin: [0, 0, 0.006], count: [40, 40, 40], spacing: 0.0105,
       particle_radius: 0.005, jitter: 0.5, seed: 3}
rigid_bodies:
  - {name: floor, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], material: rock,
     motion: fixed}
YAML

failed=0
check() {  # check NAME SUMMARY
  /usr/bin/python3 - "$1" "$2" <<'PY' || failed=1
import json, sys
name, path = sys.argv[1], sys.argv[2]
s = json.load(open(path))
peak = s["peak_memory_largest_rank_bytes"]
estimate = s["estimated_memory_per_rank_bytes"]
mib = 1024.0 * 1024.0
print(f"{name}: peak {peak / mib:.1f} MiB on the largest rank, estimate {estimate / mib:.1f} MiB "
      f"({estimate / peak:.2f} times the peak)")
if not peak > 0:
    sys.exit(f"FAIL: {name}: no peak memory measured")
if peak > estimate:
    sys.exit(f"FAIL: {name}: the run took more than the estimate")
if estimate > 2.5 * peak:
    sys.exit(f"FAIL: {name}: the estimate is more than 2.5 times what the run took")
PY
}

for ranks in 1 2; do
  mpirun -np "$ranks" "$ringdem" run "$work/bed.yaml" -q -o "$work/bed_$ranks" > /dev/null
  check "bed of 64000 grains, $ranks rank(s)" "$work/bed_$ranks/summary.json"
done
sed -e 's/count: \[40, 40, 40\]/count: [10, 10, 10]/' \
    -e 's/frame_interval: 0,/frame_interval_steps: 1,/' "$work/bed.yaml" > "$work/frames.yaml"
grep -q "frame_interval_steps: 1" "$work/frames.yaml"
mpirun -np 2 "$ringdem" run "$work/frames.yaml" -q -o "$work/frames" \
  --set simulation.end_time=0.0131 > /dev/null
check "1000 grains, 1000 frames, 2 ranks" "$work/frames/summary.json"
"$ringdem" run "$source_dir/inputs/rockfall/r12.yaml" -q -o "$work/net" \
  --set simulation.end_time=0.0002 --set output.frame_interval=0 > /dev/null
check "r12 net, 1 rank" "$work/net/summary.json"

[ "$failed" = 0 ] && echo PASS
exit "$failed"
