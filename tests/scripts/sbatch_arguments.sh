#!/usr/bin/env bash
# scripts/slurm/ringdem.sbatch's command line, without a cluster: a stand-in srun on PATH records
# what the script launches. A case runs as `run ... --restart auto` into results/<name>, a sweep
# file as `sweep ... --restart`; an output folder the user names (-o DIR, --output DIR,
# --output=DIR) replaces the default instead of being refused by ringdem as a second -o; a
# missing binary or case file is refused before srun with exit 2 and a message.
# (tests/clients/slurm_cluster_test.sh runs the script on a real SLURM.)
# usage: sbatch_arguments.sh RINGDEM_BINARY SOURCE_DIR
set -euo pipefail
ringdem=$(realpath "$1")
src=$(realpath "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/bin" "$work/submit"
cat > "$work/bin/srun" <<'SH'
#!/usr/bin/env bash
# Records its arguments one to a line, then exits as the stand-in job should.
printf '%s\n' "$@" > "$SRUN_RECORD"
exit 0
SH
chmod +x "$work/bin/srun"
export PATH="$work/bin:$PATH" RINGDEM_BIN=$ringdem
cd "$work/submit"
printf 'schema_version: 1\nname: fall\n' > fall.yaml
printf 'schema_version: 1\ncase: fall.yaml\nparameters:\n  - {key: simulation.end_time, values: [0.01]}\n' > study.yaml

fail() { echo "FAIL: $*"; exit 1; }
launched() {  # the arguments srun got after the binary, on one line
  tail -n +3 "$work/record" | tr '\n' ' ' | sed 's/ $//'
}
expect() {  # expected launch, sbatch script arguments...
  local want=$1
  shift
  SRUN_RECORD=$work/record bash "$src/scripts/slurm/ringdem.sbatch" "$@" > "$work/log" 2>&1 ||
    { cat "$work/log"; fail "the script failed for: $*"; }
  [ "$(sed -n 2p "$work/record")" = "$ringdem" ] || fail "srun did not launch $ringdem"
  [ "$(launched)" = "$want" ] || fail "for '$*' srun launched '$(launched)', expected '$want'"
  echo "ok: $* -> $want"
}
expect "run fall.yaml -o results/fall --restart auto" fall.yaml
expect "run fall.yaml --restart auto -o /scratch/f -q" fall.yaml -o /scratch/f -q
expect "run fall.yaml --restart auto --output /scratch/f" fall.yaml --output /scratch/f
expect "run fall.yaml --restart auto --output=/scratch/f" fall.yaml --output=/scratch/f
expect "run fall.yaml --restart auto -o/scratch/f" fall.yaml -o/scratch/f
expect "sweep study.yaml -o results/study --restart" study.yaml
expect "sweep study.yaml --restart -o /scratch/s --ranks-per-case 2" study.yaml -o /scratch/s \
  --ranks-per-case 2

refused() {  # message, then the environment and arguments
  local message=$1
  shift
  set +e
  env SRUN_RECORD="$work/record" "$@" > "$work/log" 2>&1
  local rc=$?
  set -e
  [ "$rc" -eq 2 ] || { cat "$work/log"; fail "exit $rc, expected 2, for: $*"; }
  grep -q "$message" "$work/log" || { cat "$work/log"; fail "no '$message' for: $*"; }
  echo "refused: $(head -1 "$work/log")"
}
rm -f "$work/record"
refused "no ringdem binary at $work/none" RINGDEM_BIN="$work/none" \
  bash "$src/scripts/slurm/ringdem.sbatch" fall.yaml
refused "missing.yaml: no such case or sweep file" \
  bash "$src/scripts/slurm/ringdem.sbatch" missing.yaml
[ ! -e "$work/record" ] || fail "srun ran for a refused job"
echo "OK: the batch script launches the run or sweep it should, and refuses what it cannot run"
