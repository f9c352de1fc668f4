#!/usr/bin/env bash
# Hydrodynamic bounds of a small grains-only channel flow (issue 13, scripts/check_debris_bounds.py):
# a polydisperse debris block slides down a 30-degree channel (gravity tilted, bed z = 0, side
# walls 0.2 m apart) into a rigid wall across it, named as the barrier's post. The peak force
# on the wall must lie between the hydrostatic load 1/2 k rho g h^2 w and the hydrodynamic load
# alpha rho v^2 h w + 1/2 k rho g h^2 w of the design guidance (rigid-barrier ranges), with h,
# v and rho measured at the upstream gauge. The check must also fail where it should: with half
# the barrier width, and with the force scaled by 3 and by 1/50.
# Grains of E = 1e8 Pa (softer than rock, for a step of 4e-5 s): a 1-rank run of a few seconds.
# usage: debris_bounds.sh RINGDEM_BINARY [SOURCE_DIR]
set -euo pipefail
ringdem=$1
src=${2:-$(cd "$(dirname "$0")/../.." && pwd)}
check=$src/scripts/check_debris_bounds.py
py=/usr/bin/python3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
# A folder that is not a finished run's is refused by the scripts with a message (exit 2), not a
# traceback from the first file they open.
mkdir "$work/not_a_run"
for script in check_debris_bounds plot_debris; do
  set +e
  "$py" "$src/scripts/$script.py" "$work/not_a_run" > "$work/refusal.log" 2>&1
  rc=$?
  set -e
  if [ "$rc" -ne 2 ] || ! grep -q "not_a_run: not a run's output folder, it lacks summary.json and series.csv" "$work/refusal.log" \
      || grep -q Traceback "$work/refusal.log"; then
    cat "$work/refusal.log"; echo "FAIL: $script.py on a folder without a run: exit $rc"; exit 1
  fi
done

cat > "$work/case.yaml" <<'YAML'
schema_version: 1
name: debris_bounds
simulation: {end_time: 0.4, dt: auto, gravity: [4.905, 0, -8.4957], skin: 0.003,
             series_interval: 0.001}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e8, poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}
  - {name: concrete, density: 2400, youngs_modulus: 1.0e8, poisson_ratio: 0.2, restitution: 0.3, friction: 0.4}
rigid_bodies:
  - {name: bed, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], material: concrete}
  - {name: left, shape: plane, position: [0, -0.1, 0], normal: [0, 1, 0], material: concrete}
  - {name: right, shape: plane, position: [0, 0.1, 0], normal: [0, -1, 0], material: concrete}
  - {name: wall, shape: plane, position: [0, 0, 0], normal: [-1, 0, 0], material: concrete}
particles:
  grains:
    - {group: debris, material: rock, box_min: [-1.0, -0.1, 0.0], box_max: [-0.4, 0.1, 0.1],
       solid_fraction: 0.3, velocity: [2, 0, 0],
       sizes: {distribution: uniform, min_radius: 0.005, max_radius: 0.008}}
scenario:
  type: free_run
  barrier: {direction: [1, 0, 0], position: [0, 0, 0], bed: bed, posts: [wall], grain_groups: [debris],
            gauge_distance: 0.1, gauge_length: 0.2, retention_length: 0.4, width: 0.2}
YAML
timeout 240 "$ringdem" run "$work/case.yaml" -o "$work/out" --quiet > "$work/run.log" 2>&1 \
  || { echo "FAIL: the run did not finish (rc $?)"; cat "$work/run.log"; exit 1; }

echo "--- the run against the bounds (rigid barrier, w = 0.2 m), interval-mean force over the"
echo "    coarsest grain's passage at the gauge (the default window):"
"$py" "$check" "$work/out" --width 0.2 --barrier rigid | tee "$work/grain.log" \
  || { echo "FAIL: the mean force is outside the hydrodynamic bounds"; exit 1; }
# The window's grain is the case's coarsest: diameters 10-16 mm, so d in (10, 16] mm.
"$py" - "$work/grain.log" <<'PY'
import re, sys
m = re.search(r"d / v = ([0-9.e+-]+) m / ([0-9.e+-]+) m/s", open(sys.argv[1]).read())
assert m, "no grain window printed"
d = float(m.group(1))
assert 0.010 < d <= 0.016, f"the window's grain diameter {d} m is not the case's coarsest"
print(f"--- window grain diameter {d} m: the case's coarsest (10-16 mm)")
PY
echo "--- the same over one series interval (--window 0), the mean and the sampled force:"
"$py" "$check" "$work/out" --width 0.2 --barrier rigid --window 0 \
  || { echo "FAIL: the peak mean force is outside the hydrodynamic bounds"; exit 1; }
"$py" "$check" "$work/out" --width 0.2 --barrier rigid --force sample --window 0 \
  || { echo "FAIL: the peak sampled force is outside the hydrodynamic bounds"; exit 1; }
echo "--- the same with the centroid depth (a saltating grain does not set h):"
"$py" "$check" "$work/out" --width 0.2 --barrier rigid --depth centroid \
  || { echo "FAIL: the peak mean force is outside the bounds of the centroid depth"; exit 1; }
"$py" - "$work/out/series.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if float(r["flow_depth_m"]) > 0]
# Twice the mean centre height never exceeds twice the highest centre, which lies r_min below
# the highest top: a bound independent of how the column is computed.
bad = [r for r in rows if float(r["flow_depth_centroid_m"]) > 2 * float(r["flow_depth_m"])]
assert rows and not bad, f"centroid depth above twice the top depth: {bad[:1]}"
print(f"--- centroid depth within twice the top depth in {len(rows)} rows")
PY

# The check must be able to fail: a wrong width and a force scaled up or down.
expect_fail() {  # label, check arguments...
  local label=$1
  shift
  if "$py" "$check" "$@" > "$work/neg.log" 2>&1; then
    cat "$work/neg.log"
    echo "FAIL: the check passed with $label"
    exit 1
  fi
  echo "--- fails as it should with $label: $(grep -E '^FAIL' "$work/neg.log" | head -1)"
}
expect_fail "half the width (0.1 m)" "$work/out" --width 0.1 --barrier rigid
for factor in 3 0.02; do
  "$py" - "$work/out" "$work/scaled$factor" "$factor" <<'PY'
import csv, json, os, sys
src, dst, factor = sys.argv[1], sys.argv[2], float(sys.argv[3])
os.makedirs(dst)
cols = ("barrier_force_N", "barrier_net_force_N", "barrier_posts_force_N",
        "barrier_mean_force_N", "barrier_mean_net_force_N", "barrier_mean_posts_force_N")
with open(os.path.join(src, "series.csv")) as f:
    rows = list(csv.DictReader(f))
with open(os.path.join(dst, "series.csv"), "w", newline="") as f:
    out = csv.DictWriter(f, fieldnames=list(rows[0]))
    out.writeheader()
    for r in rows:
        out.writerow({k: repr(float(v) * factor) if k in cols and v not in ("", "null", "nan")
                      else v for k, v in r.items()})
s = json.load(open(os.path.join(src, "summary.json")))
for k in ("peak_force_N", "peak_net_force_N", "peak_posts_force_N", "peak_mean_force_N",
          "peak_mean_net_force_N", "peak_mean_posts_force_N"):
    s["barrier"][k] *= factor
json.dump(s, open(os.path.join(dst, "summary.json"), "w"))
PY
  expect_fail "the force scaled by $factor" "$work/scaled$factor" --width 0.2 --barrier rigid
  expect_fail "the sampled force scaled by $factor" "$work/scaled$factor" --width 0.2 \
    --barrier rigid --force sample
done
echo "OK: the peak force lies within the bounds, and the check fails with a wrong width or force"
