#!/usr/bin/env bash
# scripts/check_frames.py on the frames of cases without rigid bodies (a free ring) and without
# bonds (a lattice of spheres): such files must check clean (issue 15: it reported the empty
# body datasets as problems).
# usage: frames_without_bodies.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$1
src=$2
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
py=/usr/bin/python3

cat > "$work/ring.yaml" <<'YAML'
schema_version: 1
simulation: {end_time: 2.0e-4, gravity: [0, 0, -9.81]}
materials:
  - {name: steel, density: 7800, youngs_modulus: 200.0e9, poisson_ratio: 0.3}
bonds:
  - {name: ring, youngs_modulus: 292.0e9, radius_multiplier: 0.43}
particles:
  rings:
    - {centre: [0, 0, 0.5], normal: [0, 0, 1], internal_diameter: 0.3, n_particles: 40,
       particle_radius: 0.0045, material: steel, bond: ring}
output: {frame_interval: 5.0e-5}
YAML
cat > "$work/lattice.yaml" <<'YAML'
schema_version: 1
simulation: {end_time: 2.0e-4, gravity: [0, 0, -9.81]}
materials:
  - {name: rock, density: 2600, youngs_modulus: 30.0e9}
particles:
  lattices:
    - {origin: [0, 0, 1], count: [3, 3, 3], spacing: 0.02, particle_radius: 0.005, material: rock}
output: {frame_interval: 5.0e-5}
YAML

for c in ring lattice; do
  "$ringdem" run "$work/$c.yaml" -o "$work/$c" -q
  out=$($py "$src/scripts/check_frames.py" "$work/$c/frames_0000.xdmf") || {
    echo "$out"
    echo "FAIL: check_frames.py reports problems on the $c case"
    exit 1
  }
  echo "$out"
  # 5 frames: t = 0 and every 5e-5 s up to 2e-4 s.
  echo "$out" | grep -q ": 5 frames," || { echo "FAIL: expected 5 frames"; exit 1; }
done
echo "PASS"
