#!/usr/bin/env bash
# scripts/slurm/ringdem.sbatch against a real SLURM (issue 15, "Real clients in the tests"):
# starts a one-node cluster of its own on this machine (munged, slurmctld, slurmd; everything
# in a temporary folder, on free ports), submits the batch script for a short case with a
# one-minute time limit and --signal, and checks that
#   - SLURM sent SIGUSR1 before the limit: the job wrote a checkpoint, exited and resubmitted
#     itself (no job ends in TIMEOUT);
#   - the chain of jobs ends with one that finished the run (COMPLETED, exit 0);
#   - the final state equals, bit for bit, that of the same case run uninterrupted (the last
#     checkpoint, series.csv, the rebuild count in summary.json, the last frame);
#   - a sweep file submitted with the same script runs as `ringdem sweep`: a study of two falling
#     spheres on 2 tasks completes, each case's final kinetic energy m (g t)^2 / 2 in sweep.csv.
# It stops every daemon it started (by pid, on exit). Exit 77 (ctest: skipped) when SLURM or
# munge is not installed or this is not root (slurmd starts the job steps as their user).
# usage: slurm_cluster_test.sh RINGDEM_BINARY SOURCE_DIR
#   RINGDEM_SLURM_SECONDS  wall time the uninterrupted run should take (default 40, from a
#                          short calibration run): longer than SLURM's 30 s time-limit check
#                          period, so the first job is always signalled before it ends
#   KEEP=1                 keep the temporary folder (printed)
set -euo pipefail
ringdem=$(realpath "$1")
src=$(realpath "$2")
py=/usr/bin/python3

skip() {
  echo "SKIP: $*"
  exit 77
}
for cmd in munged munge slurmctld slurmd sbatch squeue scontrol scancel srun; do
  command -v "$cmd" > /dev/null || skip "$cmd not found (Debian: apt-get install slurm-wlm munge)"
done
[ "$(id -u)" -eq 0 ] || skip "needs root: slurmd starts the job steps as the submitting user"

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d /tmp/ringdem_slurm_XXXXXX)
# munged wants every folder above its socket searchable by all, and its key folder private.
chmod 711 "$work"
mkdir -p "$work"/{munge,key,state,spool,log,submit}
chmod 755 "$work/munge"
chmod 700 "$work/key"
pids=()

cleanup() {
  local rc=$?
  set +e
  if [ -f "$work/slurm.conf" ] && [ -n "${SLURM_CONF:-}" ]; then
    scancel --full --quiet $(squeue -h -o %i 2> /dev/null) 2> /dev/null
    # Job steps end before slurmd does (slurmstepd outlives a killed slurmd).
    for _ in $(seq 1 30); do
      [ -z "$(squeue -h -o %i 2> /dev/null)" ] && break
      sleep 1
    done
  fi
  for f in slurmd slurmctld; do
    [ -f "$work/$f.pid" ] && pids+=("$(cat "$work/$f.pid")")
  done
  [ -f "$work/munge/munged.pid" ] && pids+=("$(cat "$work/munge/munged.pid")")
  for pid in "${pids[@]}"; do
    kill "$pid" 2> /dev/null
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 1 50); do
      kill -0 "$pid" 2> /dev/null || break
      sleep 0.1
    done
    kill -9 "$pid" 2> /dev/null
  done
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    echo "--- logs (failure) ---"
    tail -n 30 "$work"/log/*.log "$work"/submit/ringdem-*.out 2> /dev/null
  fi
  if [ -n "${KEEP:-}" ]; then echo "kept $work"; else rm -rf "$work"; fi
  exit "$rc"
}
trap cleanup EXIT

free_port() { $py -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

# --- munge: a key of our own, a socket in the temporary folder ---
head -c 1024 /dev/urandom > "$work/key/munge.key"
chmod 400 "$work/key/munge.key"
munged --socket="$work/munge/munge.sock" --key-file="$work/key/munge.key" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/log/munged.log" \
  --seed-file="$work/key/munged.seed"
munge -S "$work/munge/munge.sock" -n | unmunge -S "$work/munge/munge.sock" > /dev/null
echo "munged up"

# --- slurm.conf: one node, this host, no cgroups, no accounting ---
host=$(hostname -s)
ctld_port=$(free_port)
slurmd_port=$(free_port)
while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done
cat > "$work/slurm.conf" << EOF
ClusterName=ringdemtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/munge.sock
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
KillWait=10
MinJobAge=3600
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 1 60); do
  [ "$(sinfo -h -o %t 2> /dev/null)" = "idle" ] && break
  sleep 0.5
done
[ "$(sinfo -h -o %t)" = "idle" ] || {
  echo "FAIL: the node did not come up idle: $(sinfo -h -o '%t %E' 2>&1)"
  exit 1
}
echo "slurmctld and slurmd up: $(sinfo -h -o '%P %D %t %c')"
srun --mpi=list 2>&1 | grep -qw pmix || {
  echo "FAIL: srun has no pmix plugin (srun --mpi=list): ringdem.sbatch launches with --mpi=pmix"
  exit 1
}

# --- the case: the SIGUSR1 test's net, long enough to outlast the first time-limit check ---
case_file=$src/tests/data/restart_net.yaml
seconds=${RINGDEM_SLURM_SECONDS:-40}
calibrate=0.01
mpirun -np 2 "$ringdem" run "$case_file" -o "$work/calibrate" -q \
  --set simulation.end_time=$calibrate --set output.frame_interval=1 --set output.checkpoint_interval=1
end_time=$($py -c "import json, sys; s = json.load(open(sys.argv[1]))
print(f'{max(0.02, round(s[\"end_time_s\"] / s[\"wall_time_s\"] * $seconds, 3)):.3f}')" \
  "$work/calibrate/summary.json")
# The last checkpoint at the end, for the comparison.
options=(--set simulation.end_time="$end_time" --set output.frame_interval=0.005
  --set output.checkpoint_interval="$end_time")
echo "case: $case_file to t = $end_time s (~${seconds} s on 2 ranks)"

# --- the batch script: 2 tasks, one minute, SIGUSR1 at most 59 s before the limit ---
# SLURM checks time limits every 30 s: the signal comes 1-31 s into each job. The signal
# travels to the resubmissions in SBATCH_SIGNAL (inherited), task count and time limit are
# forwarded by the script.
export SBATCH_SIGNAL=B:USR1@59
export RINGDEM_BIN=$ringdem
cd "$work/submit"
t0=$(date +%s)
first=$(sbatch --parsable --ntasks=2 --time=1 "$src/scripts/slurm/ringdem.sbatch" "$case_file" \
  "${options[@]}")
echo "submitted job $first"
deadline=$((t0 + 12 * seconds + 240))
while [ -n "$(squeue -h -o %i)" ]; do
  if [ "$(date +%s)" -gt "$deadline" ]; then
    echo "FAIL: jobs still queued after $((deadline - t0)) s:"
    squeue
    exit 1
  fi
  sleep 2
done
t_slurm=$(($(date +%s) - t0))

# --- what the jobs did ---
jobs=("$first")
while :; do
  out="ringdem-${jobs[-1]}.out"
  [ -f "$out" ] || {
    echo "FAIL: no output $out of job ${jobs[-1]}"
    exit 1
  }
  next=$(sed -n 's/^Submitted batch job \([0-9]*\)$/\1/p' "$out")
  [ -n "$next" ] || break
  jobs+=("$next")
done
echo "jobs: ${jobs[*]} (${t_slurm} s)"
last=${jobs[-1]}
for j in "${jobs[@]}"; do
  state=$(scontrol show job "$j" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
  exit_code=$(scontrol show job "$j" | sed -n 's/.* ExitCode=\([0-9:]*\).*/\1/p')
  echo "job $j: $state, exit $exit_code"
  [ "$state" = COMPLETED ] && [ "$exit_code" = "0:0" ] || {
    echo "FAIL: job $j ended $state with exit $exit_code (a time-limit kill is TIMEOUT)"
    exit 1
  }
  if [ "$j" != "$last" ]; then
    grep -q "stop requested (SIGUSR1 or wall-time limit): checkpoint" "ringdem-$j.out" || {
      echo "FAIL: job $j did not checkpoint on the signal"
      exit 1
    }
    grep -q "checkpointed before the time limit: resubmitting" "ringdem-$j.out"
  fi
  if [ "$j" != "$first" ]; then
    grep -q "^restart from .*checkpoint_" "ringdem-$j.out" || {
      echo "FAIL: job $j did not restart from a checkpoint"
      exit 1
    }
  fi
done
[ "${#jobs[@]}" -ge 2 ] || {
  echo "FAIL: job $first ran to the end without a signal; raise RINGDEM_SLURM_SECONDS"
  exit 1
}
grep -q "^done: " "ringdem-$last.out" || {
  echo "FAIL: the last job $last did not finish the run"
  exit 1
}
slurm_out=$work/submit/results/restart_net

# --- the same case uninterrupted, and the comparison ---
mpirun -np 2 "$ringdem" run "$case_file" -o "$work/straight" -q "${options[@]}"
final=$(basename "$(ls "$work/straight/checkpoints"/checkpoint_*.h5 | tail -1)")
$py "$src/scripts/compare_h5.py" "$work/straight/checkpoints/$final" "$slurm_out/checkpoints/$final" \
  --groups particles bonds bodies
cmp "$work/straight/series.csv" "$slurm_out/series.csv"
echo "series.csv identical"
rebuilds() { $py -c "import json, sys; print(json.load(open(sys.argv[1]))['neighbour_rebuilds'])" "$1"; }
[ "$(rebuilds "$work/straight/summary.json")" = "$(rebuilds "$slurm_out/summary.json")" ] || {
  echo "FAIL: neighbour rebuilds $(rebuilds "$slurm_out/summary.json") after the restarts," \
    "$(rebuilds "$work/straight/summary.json") uninterrupted"
  exit 1
}
echo "neighbour rebuilds: $(rebuilds "$slurm_out/summary.json") in both"
segment=$(ls "$slurm_out"/frames_*.h5 | tail -1)
$py "$src/scripts/compare_h5.py" "$work/straight/frames_0000.h5" "$segment" \
  --groups particles bonds --frame -1 --skip particles/rank

# --- a sweep file through the same script: ringdem sweep, a case on each task ---
cat > "$work/submit/fall.yaml" << 'EOF'
schema_version: 1
simulation: {dt: 1.0e-4, end_time: 0.01, gravity: [0, 0, -9.81]}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e8}
particles:
  spheres:
    - {position: [0, 0, 1], radius: 0.01, material: rock}
EOF
cat > "$work/submit/fall_study.yaml" << 'EOF'
schema_version: 1
case: fall.yaml
parameters:
  - {key: simulation.end_time, values: [0.01, 0.02]}
EOF
study=$(sbatch --parsable --ntasks=2 --time=1 "$src/scripts/slurm/ringdem.sbatch" fall_study.yaml)
deadline=$(($(date +%s) + 120))
while [ -n "$(squeue -h -o %i)" ]; do
  [ "$(date +%s)" -le "$deadline" ] || {
    echo "FAIL: the sweep job $study still queued after 120 s"
    exit 1
  }
  sleep 1
done
state=$(scontrol show job "$study" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
exit_code=$(scontrol show job "$study" | sed -n 's/.* ExitCode=\([0-9:]*\).*/\1/p')
[ "$state" = COMPLETED ] && [ "$exit_code" = "0:0" ] || {
  echo "FAIL: the sweep job $study ended $state with exit $exit_code"
  cat "ringdem-$study.out"
  exit 1
}
grep -q "^\[rank 1\] case_001" "ringdem-$study.out" || {
  echo "FAIL: the sweep's second case did not run on the second task"
  cat "ringdem-$study.out"
  exit 1
}
# Velocity Verlet is exact under gravity alone: each case ends with m (g t)^2 / 2, t = steps dt.
$py - "$work/submit/results/fall_study/sweep.csv" << 'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 2, rows
for r in rows:
    assert r["exit_code"] == "0", r
    t = float(r["steps"]) * float(r["dt_s"])
    assert abs(t - float(r["simulation.end_time"])) < 1e-12, r
    expected = 0.5 * 2600 * 4 / 3 * math.pi * 1e-6 * (9.81 * t) ** 2
    assert abs(float(r["final_kinetic_energy_J"]) - expected) <= 1e-9 * expected, (r, expected)
print("sweep job: 2 cases, each at m (g t)^2 / 2")
EOF
echo "PASS (${#jobs[@]} jobs in ${t_slurm} s; a sweep job)"
