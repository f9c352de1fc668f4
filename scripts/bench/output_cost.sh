#!/usr/bin/env bash
# Cost of frame output (issue 5): a linked net of 200 rings (20 000 particles) falling onto a
# plane, run twice on RANKS ranks for END_TIME simulated seconds: without frames, then with a
# frame every 1 ms (optionally compressed). Prints the loop times and the overhead.
#   scripts/bench/output_cost.sh [RANKS=2] [END_TIME=0.05] [COMPRESSION=0]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
ringdem_install_packages
ringdem_build native
cd "$RINGDEM_ROOT"
ranks="${1:-2}"
end_time="${2:-0.05}"
compression="${3:-0}"
work=build/native/output_cost
rm -rf "$work"
mkdir -p "$work"
py=/usr/bin/python3
$py scripts/bench/make_ring_grid.py --linked 20 10 "$work/net.yaml" "$end_time"
mpirun -np "$ranks" build/native/ringdem run "$work/net.yaml" -q -o "$work/none"
mpirun -np "$ranks" build/native/ringdem run "$work/net.yaml" -q -o "$work/frames" \
  --set output.frame_interval=1.0e-3 --set output.compression="$compression"
$py - "$work" "$ranks" <<'PY'
import json, os, sys
work, ranks = sys.argv[1], int(sys.argv[2])
a = json.load(open(f"{work}/none/summary.json"))
b = json.load(open(f"{work}/frames/summary.json"))
size = os.path.getsize(f"{work}/frames/frames_0000.h5") / 1e6
print(f"20 000-particle net, {a['steps']} steps on {ranks} ranks, frames every 1 ms: {b['frames']} frames, {size:.1f} MB")
print(f"  wall without frames {a['wall_time_s']:.2f} s, with frames {b['wall_time_s']:.2f} s")
print(f"  time spent writing frames (rank 0): {b['frame_output_s']:.2f} s = "
      f"{100 * b['frame_output_s'] / b['wall_time_s']:.2f} % of the run")
print(f"  wall-time overhead: {100 * (b['wall_time_s'] / a['wall_time_s'] - 1):+.2f} %")
PY
