#!/usr/bin/env bash
# A free run with scenario.barrier through the command line, on 1 and 2 ranks: both must end
# (the barrier's sample is collective, so every rank must take it) and write the same
# series.csv and summary.json barrier object, value for value (docs/debris.md: exact sums and
# rank maxima). Grains flow along a bed against a wall named as the barrier's post.
# usage: barrier_ranks.sh RINGDEM_BINARY
set -euo pipefail
ringdem=$1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/case.yaml" <<'YAML'
schema_version: 1
name: barrier_ranks
simulation: {end_time: 0.08, dt: 2.0e-6, gravity: [0, 0, -9.81], series_interval: 0.01}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e8, poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}
rigid_bodies:
  - {name: bed, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], material: rock}
  - {name: wall, shape: plane, position: [0.03, 0, 0], normal: [-1, 0, 0], material: rock}
particles:
  lattices:
    - {group: debris, origin: [-0.1, -0.05, 0.012], count: [6, 10, 3], spacing: 0.021,
       particle_radius: 0.01, material: rock, velocity: [2, 0, 0], jitter: 0.2}
scenario:
  type: free_run
  barrier: {direction: [1, 0, 0], position: [0.03, 0, 0], bed: bed, posts: [wall],
            grain_groups: [debris], gauge_distance: 0.02, gauge_length: 0.1,
            retention_length: 0.1, width: 0.21}
YAML
for n in 1 2; do
  timeout 120 mpirun -np "$n" "$ringdem" run "$work/case.yaml" -o "$work/np$n" --quiet \
    > "$work/np$n.log" 2>&1 || { echo "FAIL: $n rank(s) did not finish (rc $?)"; cat "$work/np$n.log"; exit 1; }
done
/usr/bin/python3 - "$work" <<'PY'
import csv, json, sys
w = sys.argv[1]
rows = [list(csv.reader(open(f"{w}/np{n}/series.csv"))) for n in (1, 2)]
header = rows[0][0]
assert "barrier_posts_force_N" in header and "flow_depth_m" in header, header
assert rows[0] == rows[1], "series.csv differs between 1 and 2 ranks"
force = [float(r[header.index("barrier_posts_force_N")]) for r in rows[0][1:]]
assert max(force) > 0.0, "the grains should have loaded the wall"
b = [json.load(open(f"{w}/np{n}/summary.json"))["barrier"] for n in (1, 2)]
assert b[0] == b[1], (b[0], b[1])
print(f"OK: {len(rows[0]) - 1} rows equal on 1 and 2 ranks, peak post force {max(force):.3g} N")
PY
