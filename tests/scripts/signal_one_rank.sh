#!/usr/bin/env bash
# A SIGTERM that reaches one rank of a 2-rank run (a `kill` of one process) stops the whole job
# as if sent to all: every rank agrees on the step, writes the checkpoint, and exits with
# 128 + 15, the message names SIGTERM, the lock is released; `--restart auto` on 3 ranks then
# ends with the series.csv bytes of a run never stopped (app/StopSignals, docs/output.md).
# usage: signal_one_rank.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$1
src=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
case_file=$src/tests/data/restart_net.yaml
fail() { echo "FAIL: $*"; cat "$work/log"; exit 1; }

mpirun -np 2 "$ringdem" run "$case_file" -o "$work/split" -q --set simulation.end_time=1 \
  > "$work/log" 2>&1 &
launcher=$!
# Once the run steps (series.csv has rows), the rank that does not hold the lock (rank 0 does).
for _ in $(seq 1 1200); do
  if [ -f "$work/split/series.csv" ] && [ "$(wc -l < "$work/split/series.csv")" -ge 3 ]; then break; fi
  sleep 0.05
done
root=$(sed -n 's/^pid: //p' "$work/split/ringdem.lock")
other=$(pgrep -f -- "-o $work/split" | grep -vx "$launcher" | grep -vx "$root" | head -1)
[ -n "$root" ] && [ -n "$other" ] || fail "ranks not found (rank 0: '$root', other: '$other')"
kill -TERM "$other"
set +e
wait "$launcher"
rc=$?
set -e
[ "$rc" -eq 143 ] || fail "the job exited with $rc, expected 143 (128 + SIGTERM)"
grep -q "stop requested (SIGTERM): checkpoint" "$work/log" || fail "rank 0 does not name SIGTERM"
[ ! -e "$work/split/ringdem.lock" ] || fail "the lock was left"
ls "$work/split/checkpoints"/checkpoint_*.h5 > /dev/null || fail "no checkpoint"

# The continuation, on 3 ranks, to shortly after the stop; and a run to that time never stopped.
t=$(sed -n 's/.*checkpoint .* at t = \([^ ]*\) s.*/\1/p' "$work/log")
end=$(/usr/bin/python3 -c "print(f'{$t + 1.5e-3:.6g}')")
mpirun -np 3 "$ringdem" run "$case_file" -o "$work/split" -q --set simulation.end_time="$end" \
  --restart auto
mpirun -np 2 "$ringdem" run "$case_file" -o "$work/straight" -q --set simulation.end_time="$end"
cmp "$work/straight/series.csv" "$work/split/series.csv" || fail "series.csv differs after the restart"
echo "PASS: one rank's SIGTERM stopped the job with a checkpoint at t = $t s; the restart to $end s matches"
