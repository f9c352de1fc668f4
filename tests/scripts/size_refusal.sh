#!/usr/bin/env bash
# A case far beyond the machine's memory (a lattice of 10^12 spheres) is refused before
# anything is built: exit 2 with the estimate, within seconds; `check` prints the estimate.
# usage: size_refusal.sh RINGDEM_BINARY
set -euo pipefail
ringdem=$1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/huge.yaml" <<'YAML'
schema_version: 1
name: huge
simulation: {dt: 1.0e-5, end_time: 1.0e-5}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e9, poisson_ratio: 0.25, restitution: 0.3}
particles:
  lattices:
    - {material: rock, count: [10000, 10000, 10000], spacing: 0.011, particle_radius: 0.005}
YAML
"$ringdem" check "$work/huge.yaml" > "$work/check.txt"
grep -q "size estimate: 1000000000000 particles" "$work/check.txt" || {
  echo "FAIL: check does not print the estimate"; cat "$work/check.txt"; exit 1; }
set +e
timeout 60 mpirun -np 2 "$ringdem" run "$work/huge.yaml" -o "$work/out" -q 2> "$work/err.txt"
rc=$?
set -e
if [ "$rc" -ne 2 ]; then
  echo "FAIL: exit $rc, expected 2 (refused up front)"; cat "$work/err.txt"; exit 1
fi
grep -q "more than the" "$work/err.txt" || { echo "FAIL: no estimate in the message"; cat "$work/err.txt"; exit 1; }
grep -q -- "--force-size" "$work/err.txt" || { echo "FAIL: the way out is not named"; exit 1; }
echo PASS
