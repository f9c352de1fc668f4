#!/usr/bin/env bash
# scripts/bench/pack_runtime.sh, the packed runtime for a machine without MPI or HDF5
# (docs/parallel.md): the packed ringdem resolves every shared library inside the pack, and a
# 2-rank run through the pack's mpirun.sh, in an environment emptied of the machine's paths,
# writes the same series.csv bytes as the same binary through the machine's own mpirun.
# usage: pack_runtime.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$1
src=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

bash "$src/scripts/bench/pack_runtime.sh" "$work/pack" "$ringdem" > "$work/pack.log" 2>&1 ||
  { cat "$work/pack.log"; fail "pack_runtime.sh exited with an error"; }
pack=$work/pack
for f in bin/ringdem bin/orterun lib/ld-linux-x86-64.so.2 mpirun.sh; do
  [ -e "$pack/$f" ] || fail "the pack has no $f"
done

# Every library the packed loader resolves for the program and for Open MPI's launcher lies in
# the pack (a library left out would resolve to the machine's own, which the other machine
# lacks). The loader lists them without running the program.
for program in bin/ringdem bin/orterun; do
  listing=$("$pack/lib/ld-linux-x86-64.so.2" --library-path "$pack/lib" --list "$pack/$program")
  resolved=$(echo "$listing" | awk '/=> \//{print $3}')
  [ -n "$resolved" ] || fail "no library listed for $program: $listing"
  outside=$(echo "$resolved" | grep -v "^$pack/lib/" || true)
  [ -z "$outside" ] || fail "$program resolves libraries outside the pack: $outside"
  echo "$program: $(echo "$resolved" | wc -l) libraries, all in the pack"
done

cat > "$work/case.yaml" <<'YAML'
schema_version: 1
name: packed_runtime
simulation: {end_time: 0.02, dt: 2.0e-6, gravity: [0, 0, -9.81], series_interval: 0.002}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e8, poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}
rigid_bodies:
  - {name: bed, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], material: rock}
particles:
  lattices:
    - {group: debris, origin: [-0.1, -0.05, 0.012], count: [10, 6, 3], spacing: 0.021,
       particle_radius: 0.01, material: rock, velocity: [2, 0, 0], jitter: 0.2}
YAML

mpirun -np 2 "$ringdem" run "$work/case.yaml" -o "$work/system" -q
# The machine's paths emptied: no LD_LIBRARY_PATH, no OPAL_PREFIX, a PATH without Open MPI.
env -i HOME="$work" PATH=/usr/bin:/bin \
  bash "$pack/mpirun.sh" -np 2 "$pack/bin/ringdem" run "$work/case.yaml" -o "$work/packed" -q
[ -s "$work/packed/series.csv" ] || fail "the packed run wrote no series.csv"
rows=$(wc -l < "$work/packed/series.csv")
[ "$rows" -ge 11 ] || fail "the packed run's series.csv has $rows lines, 11 or more expected"
cmp "$work/system/series.csv" "$work/packed/series.csv" ||
  fail "the packed run's series.csv differs from the machine's own run"
ranks=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['ranks'])" \
  "$work/packed/summary.json")
[ "$ranks" = 2 ] || fail "the packed run ran on $ranks ranks, not 2"
echo "PASS: the packed runtime ran on 2 ranks and wrote the same $rows series lines"
