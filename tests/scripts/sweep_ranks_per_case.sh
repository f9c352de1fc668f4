#!/usr/bin/env bash
# `ringdem sweep --ranks-per-case K`: each case of a study runs on a group of K ranks. A case's
# numbers do not depend on its rank count (bitwise rank independence), so the study's table on
# 2 ranks with 2 to a case must be the 1-rank table, cell for cell, all but the machine's own
# columns (wall time, rate, memory, frame-writing time), for a debris flow (grains, inlet,
# outflow, post, barrier measures) and for a tensile test. Its `ranks` column must say 2: the
# cases did run on both ranks. A job whose rank count K does not divide is refused (exit 2).
# usage: sweep_ranks_per_case.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$1
src=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
# The debris flow of debris_ranks_restart.sh, shorter.
sed -n '/^cat > "\$work\/case.yaml" <<.YAML./,/^YAML$/p' "$src/tests/scripts/debris_ranks_restart.sh" |
  sed '1d;$d' | sed 's/end_time: 0.1,/end_time: 0.04,/' > "$work/debris.yaml"
grep -q "end_time: 0.04," "$work/debris.yaml" || { echo "FAIL: no debris case"; exit 1; }
cat > "$work/debris_study.yaml" <<'YAML'
schema_version: 1
case: debris.yaml
parameters:
  - {key: inflow.0.discharge, values: [0.002, 0.004]}
YAML
cat > "$work/ring_study.yaml" <<YAML
schema_version: 1
case: $src/inputs/tensile/ring4_derived.yaml
set:
  - scenario.tensile_test.loading_rate=0.5
  - scenario.tensile_test.max_displacement=0.02
parameters:
  - {key: bonds.0.radius_multiplier, values: [0.4, 0.5]}
YAML
cd "$work"
for study in debris_study ring_study; do
  timeout 120 "$ringdem" sweep "$study.yaml" -o "$study.1" -q > "$study.1.log" 2>&1 ||
    { echo "FAIL: $study on 1 rank"; cat "$study.1.log"; exit 1; }
  timeout 120 mpirun -np 2 "$ringdem" sweep "$study.yaml" -o "$study.2" --ranks-per-case 2 \
    > "$study.2.log" 2>&1 || { echo "FAIL: $study on 2 ranks"; cat "$study.2.log"; exit 1; }
  grep -q "(2 to a case)" "$study.2.log" || { echo "FAIL: $study: no groups"; cat "$study.2.log"; exit 1; }
  /usr/bin/python3 - "$study.1/sweep.csv" "$study.2/sweep.csv" <<'PY'
import csv, sys
one = list(csv.DictReader(open(sys.argv[1])))
two = list(csv.DictReader(open(sys.argv[2])))
machine = {"wall_time_s", "particle_steps_per_s", "peak_memory_largest_rank_bytes",
           "shared_memory_largest_rank_bytes",
           "estimated_memory_per_rank_bytes", "frame_output_s", "ranks"}
assert len(one) == len(two) == 2, (len(one), len(two))
compared = 0
for a, b in zip(one, two):
    assert a.keys() == b.keys(), (sorted(a.keys() ^ b.keys()))
    if "ranks" in a:  # a free run's row says on how many ranks it ran
        assert (a["ranks"], b["ranks"]) == ("1", "2"), (a["ranks"], b["ranks"])
    for column in a:
        if column in machine:
            continue
        assert a[column] == b[column], f"{a['folder']} {column}: {a[column]} vs {b[column]}"
        compared += 1
print(f"{sys.argv[2]}: {compared} cells the same as on 1 rank")
PY
done
# 2 to a case on 3 ranks: refused before anything runs.
set +e
timeout 60 mpirun -np 3 "$ringdem" sweep debris_study.yaml -o refused --ranks-per-case 2 > refused.log 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] || { echo "FAIL: 3 ranks, 2 to a case: exit $rc"; cat refused.log; exit 1; }
grep -q "does not divide the 3 ranks" refused.log || { echo "FAIL: no message"; cat refused.log; exit 1; }
[ ! -e refused/case_000 ] || { echo "FAIL: a case ran"; exit 1; }
echo "PASS"
