#!/usr/bin/env bash
# Peak resident memory per rank of a bed of free grains built and stepped once (issue 11):
# a jittered lattice of NX x NY x NZ spheres of 5 mm above a floor, rock, Hertz-Mindlin.
#   scripts/bench/startup_memory.sh [NX NY NZ] [RANKS...]   (default 100 100 100, ranks 1 2 3)
#   RINGDEM_BINARY=path/to/ringdem  to measure another build (before/after comparisons)
# Prints each rank's peak RSS, the largest, and its ratio to the 1-rank figure.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nx=${1:-100} ny=${2:-100} nz=${3:-100}
shift $(( $# >= 3 ? 3 : $# ))
ranks_list=("${@:-1 2 3}")
[ ${#ranks_list[@]} -eq 1 ] && read -r -a ranks_list <<< "${ranks_list[0]}"
binary="${RINGDEM_BINARY:-}"
if [ -z "$binary" ]; then
  ringdem_install_packages
  ringdem_build native
  binary="$RINGDEM_ROOT/build/native/ringdem"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/bed.yaml" <<YAML
schema_version: 1
name: bed
simulation: {dt: 1.31e-5, end_time: 1.31e-5, gravity: [0, 0, -9.81], skin: 0.001}
output: {frame_interval: 0, checkpoint_interval: 0}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e9, poisson_ratio: 0.25, restitution: 0.3,
     friction: 0.5}
particles:
  lattices:
    - {material: rock, origin: [0, 0, 0.006], count: [$nx, $ny, $nz], spacing: 0.0105,
       particle_radius: 0.005, jitter: 0.5, seed: 3}
rigid_bodies:
  - {name: floor, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], material: rock,
     motion: fixed}
YAML
n=$(( nx * ny * nz ))
echo "bed of $n grains, built and stepped once; binary $binary"
one_rank=""
for ranks in "${ranks_list[@]}"; do
  mpirun -np "$ranks" /usr/bin/time -f "rss_kb %M" "$binary" run "$work/bed.yaml" -q \
    -o "$work/out_$ranks" 2> "$work/time_$ranks" > /dev/null
  largest=$(grep -o 'rss_kb [0-9]*' "$work/time_$ranks" | awk '{print $2}' | sort -n | tail -1)
  all=$(grep -o 'rss_kb [0-9]*' "$work/time_$ranks" | awk '{printf "%.0f ", $2/1024}')
  [ -z "$one_rank" ] && [ "$ranks" = 1 ] && one_rank=$largest
  ratio=""
  [ -n "$one_rank" ] && ratio=$(awk -v a="$largest" -v b="$one_rank" 'BEGIN{printf "%.3f", a/b}')
  printf "%2d ranks: per rank %s MiB; largest %.0f MiB = %.0f B/particle x ranks; vs 1 rank %s\n" \
    "$ranks" "$all" "$(awk -v a="$largest" 'BEGIN{print a/1024}')" \
    "$(awk -v a="$largest" -v n="$n" -v r="$ranks" 'BEGIN{print a*1024*r/n}')" "${ratio:--}"
done
