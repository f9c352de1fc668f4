#!/usr/bin/env bash
# SIGUSR1 sent to mpirun mid-run (what SLURM --signal does) makes every rank agree on a step,
# write a checkpoint and exit with code 3; `--restart auto` then finishes the run, and the final
# state equals, bit for bit, that of a run never interrupted (issue 5).
# usage: signal_restart.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$1
src=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
case_file=$src/tests/data/restart_net.yaml
py=/usr/bin/python3

mpirun -np 2 "$ringdem" run "$case_file" -o "$work/straight" -q
echo "uninterrupted run done"

mpirun -np 2 "$ringdem" run "$case_file" -o "$work/split" -q &
pid=$!
# Signal once the run is stepping (series.csv has rows past t = 0).
for _ in $(seq 1 600); do
  if [ -f "$work/split/series.csv" ] && [ "$(wc -l < "$work/split/series.csv")" -ge 4 ]; then break; fi
  sleep 0.05
done
kill -USR1 "$pid"
set +e
wait "$pid"
rc=$?
set -e
if [ "$rc" -ne 3 ]; then
  echo "FAIL: the signalled run exited with $rc, expected 3 (checkpoint and stop)"
  exit 1
fi
ls "$work/split/checkpoints"/checkpoint_*.h5 > /dev/null
"$ringdem" info "$work/split/checkpoints"/checkpoint_*.h5 | head -3
# Restart on another rank count.
mpirun -np 3 "$ringdem" run "$case_file" -o "$work/split" -q --restart auto

final=$(basename "$(ls "$work/straight/checkpoints"/checkpoint_*.h5 | tail -1)")
$py "$src/scripts/compare_h5.py" "$work/straight/checkpoints/$final" "$work/split/checkpoints/$final" \
  --groups particles bonds bodies
cmp "$work/straight/series.csv" "$work/split/series.csv"
echo "series.csv identical"
# The last frame of the restarted segment equals the uninterrupted run's last frame.
$py "$src/scripts/compare_h5.py" "$work/straight/frames_0000.h5" "$work/split/frames_0001.h5" \
  --groups particles bonds --frame -1 --skip particles/rank
$py "$src/scripts/check_frames.py" "$work/split/frames_0001.xdmf"
echo "PASS"
