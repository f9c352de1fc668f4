#!/usr/bin/env bash
# A small debris flow through the command line (issue 13 item 4): polydisperse grains and an
# inlet flow along a bed between side walls against a post, an outflow box takes what passes.
# - Rank independence: the run on 2 and on 3 ranks writes the same frames, bit for bit, as on
#   1 rank (every frame, with inflow and outflow active), the same series.csv and summary.
# - Restart: a run stopped mid-flow with a checkpoint on 3 ranks and continued on 2 ends with
#   the same series.csv, barrier and momentum summary and last frame as the uninterrupted run.
# - The momentum balance closes: its residual stays below 1e-11 of the booked impulse.
# - The energy ledger closes: its balance column is the ledger summed here from the other
#   columns, and it stays within 1 % of the energy the flow turned over (dissipated, carried
#   out and brought in).
# - Without the ledger (simulation.energy_ledger: false, 2 ranks) the flow is the same bits: the
#   ledger only watches. Its columns are then null, the others the same.
# With a third argument, every run takes it as one more override (--set KEY=VALUE), such as
# simulation.substeps=3 (multi-rate stepping: every interaction of this flow is then slow).
# usage: debris_ranks_restart.sh RINGDEM_BINARY SOURCE_DIR [KEY=VALUE]
set -euo pipefail
ringdem=$1
src=$2
extra=()
[ -z "${3:-}" ] || extra=(--set "$3")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
py=/usr/bin/python3
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
cat > "$work/case.yaml" <<'YAML'
schema_version: 1
name: debris_ranks_restart
simulation: {end_time: 0.1, dt: 2.0e-5, gravity: [2.0, 0, -9.6], series_interval: 0.01}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e8, poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}
rigid_bodies:
  - {name: bed, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], material: rock}
  - {name: left, shape: plane, position: [0, -0.1, 0], normal: [0, 1, 0], material: rock}
  - {name: right, shape: plane, position: [0, 0.1, 0], normal: [0, -1, 0], material: rock}
  - {name: post, shape: cylinder, position: [0.05, 0, 0.1], axis: [0, 0, 1], radius: 0.02, length: 0.2, material: rock}
particles:
  grains:
    - {group: debris, material: rock, box_min: [-0.2, -0.1, 0.0], box_max: [0.0, 0.1, 0.08],
       solid_fraction: 0.3, velocity: [1.5, 0, 0], seed: 7,
       sizes: {distribution: uniform, min_radius: 0.004, max_radius: 0.008}}
inflow:
  - {name: inlet, group: debris, material: rock, box_min: [-0.3, -0.1, 0.0], box_max: [-0.22, 0.1, 0.06],
     velocity: [1.5, 0, 0], discharge: 0.004, start_time: 0.02,
     sizes: {distribution: uniform, min_radius: 0.004, max_radius: 0.008}}
outflow:
  - {name: end, box_min: [-1, -1, -1], box_max: [0.12, 1, 1]}
scenario:
  type: free_run
  barrier: {direction: [1, 0, 0], position: [0.05, 0, 0], bed: bed, posts: [post],
            grain_groups: [debris], gauge_distance: 0.05, gauge_length: 0.1,
            retention_length: 0.1, width: 0.2}
output: {frame_interval: 0.025, checkpoint_interval: 0.05}
YAML
run() {  # run RANKS OUTDIR [ARGS...]
  local n=$1 out=$2
  shift 2
  timeout 120 mpirun -np "$n" "$ringdem" run "$work/case.yaml" -o "$work/$out" --quiet \
    ${extra[@]+"${extra[@]}"} "$@" \
    > "$work/$out.log" 2>&1 || { echo "FAIL: $out (rc $?)"; cat "$work/$out.log"; exit 1; }
}
run 1 np1
run 2 np2
run 3 np3
# Mid-flow on 3 ranks (the checkpoint at t = 0.05 s), then on to the end on 2.
run 3 split --set simulation.end_time=0.05
run 2 split --restart auto
run 2 noledger --set simulation.energy_ledger=false
for n in 2 3; do
  $py "$src/scripts/compare_h5.py" "$work/np1/frames_0000.h5" "$work/np$n/frames_0000.h5" \
    --groups particles --skip particles/rank
  cmp "$work/np1/series.csv" "$work/np$n/series.csv"
done
echo "frames and series.csv: 1, 2 and 3 ranks the same bits"
$py "$src/scripts/compare_h5.py" "$work/np1/frames_0000.h5" "$work/noledger/frames_0000.h5" \
  --groups particles --skip particles/rank
echo "frames without the energy ledger: the same bits"
cmp "$work/np1/series.csv" "$work/split/series.csv"
$py "$src/scripts/compare_h5.py" "$work/np1/frames_0000.h5" "$work/split/frames_0001.h5" \
  --groups particles --frame -1 --skip particles/rank
$py - "$work" <<'PY'
import csv, json, sys
w = sys.argv[1]
s = {k: json.load(open(f"{w}/{k}/summary.json")) for k in ("np1", "np2", "np3", "split")}
for k in ("np2", "np3", "split"):
    for part in ("barrier", "momentum_balance", "outflow", "inflow", "energy_ledger"):
        assert s[k][part] == s["np1"][part], (k, part, s[k][part], s["np1"][part])
one = s["np1"]
assert one["outflow"]["grains"] > 0 and one["inflow"]["grains"] > 0, "inflow and outflow must act"
assert one["barrier"]["peak_posts_force_N"] > 0, "the flow must load the post"
rows = list(csv.DictReader(open(f"{w}/np1/series.csv")))
for r in rows:
    impulse = sum(abs(float(r[f"impulse_{c}_N_s"])) for c in "xyz")
    residual = float(r["momentum_residual_N_s"])
    assert residual <= 1e-11 * max(impulse, 1e-300), (r["time_s"], residual, impulse)
# The energy ledger (docs/physics.md "Energy ledger"), summed from the printed columns.
terms = ("kinetic_energy_J", "potential_energy_J", "bond_energy_J", "contact_energy_J",
         "contact_damping_J", "friction_J", "global_damping_J", "broken_bonds_J", "plastic_work_J",
         "outflow_energy_J")
def ledger(r):
    return (sum(float(r[c]) for c in terms) - float(r["boundary_work_J"]) -
            float(r["inflow_energy_J"]))
last = rows[-1]
turnover = (float(last["contact_damping_J"]) + float(last["friction_J"]) +
            float(last["outflow_energy_J"]) + float(last["inflow_energy_J"]))
assert float(last["friction_J"]) > 0 and float(last["contact_damping_J"]) > 0, last
scale = max(abs(float(r[c])) for r in rows for c in terms)
for r in rows:
    balance = float(r["energy_balance_error_J"])
    assert abs(ledger(r) - ledger(rows[0]) - balance) <= 1e-9 * scale, (r["time_s"], balance)
    assert abs(balance) <= 0.01 * turnover, (r["time_s"], balance, turnover)
e = one["energy_ledger"]
assert e["balance_error_J"] == float(last["energy_balance_error_J"]), e
assert e["largest_balance_error_J"] == max(abs(float(r["energy_balance_error_J"])) for r in rows), e
# Without the ledger: the same rows, its columns (and the contacts' elastic energy, which it
# books, also in what the outflow carried out) null.
unbooked = {"contact_energy_J", "outflow_energy_J", "contact_damping_J", "friction_J", "global_damping_J",
            "broken_bonds_J", "boundary_work_J", "energy_balance_error_J"}
bare = list(csv.DictReader(open(f"{w}/noledger/series.csv")))
assert len(bare) == len(rows) and list(bare[0]) == list(rows[0])
for r, b in zip(rows, bare):
    for c in r:
        assert b[c] == ("null" if c in unbooked else r[c]), (c, r["time_s"], r[c], b[c])
n = json.load(open(f"{w}/noledger/summary.json"))
assert n["energy_ledger"] == {"booked": False} and n["barrier"] == one["barrier"], n["energy_ledger"]
print(f"energy ledger: largest balance error {e['largest_balance_error_J']:.3g} J of "
      f"{turnover:.4g} J turned over (friction {e['friction_J']:.4g} J, contact damping "
      f"{e['contact_damping_J']:.4g} J)")
print(f"OK: restart 3 -> 2 ranks the same bits; {one['outflow']['grains']} grains out, "
      f"{one['inflow']['grains']} in, peak post force {one['barrier']['peak_posts_force_N']:.3g} N, "
      f"momentum residual {residual:.2g} of {impulse:.3g} N s")
PY
