#!/usr/bin/env bash
# Side-by-side granular benchmark (issue 12): ringdem against Debian's LAMMPS (GRANULAR,
# pair_style granular hertz/material + mindlin + tsuji damping) and LIGGGHTS (gran model hertz
# tangential history) on the same beds, one rank each, runs interleaved, medians printed.
#   scripts/bench/peer_granular.sh [--sizes 1e5,1e6] [--variants bed,poly,flow,dense,mixed]
#                                  [--codes ringdem,lammps,liggghts] [--repeats 3] [--json F]
#   (code ringdem_noledger: ringdem with simulation.energy_ledger: false, as the peers book none)
#   RINGDEM_BINARY=path/to/ringdem  to measure another build (before/after comparisons)
# Variants and what each figure means: scripts/bench/peer_granular.py and docs/performance.md.
# At 1e6 grains a bed needs about 2 GB per code and minutes per run: quiet machines only.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
RINGDEM_PACKAGES+=(lammps liggghts time)
ringdem_install_packages
binary="${RINGDEM_BINARY:-}"
if [ -z "$binary" ]; then
  ringdem_build native >/dev/null
  binary="$RINGDEM_ROOT/build/native/ringdem"
fi
ringdem_log "$(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
binary=$(realpath "$binary")
ringdem_log "ringdem: $binary"
ringdem_log "$(dpkg-query -W -f='lammps ${Version}, ' lammps)$(dpkg-query -W -f='liggghts ${Version}' liggghts)"
exec /usr/bin/python3 "$RINGDEM_ROOT/scripts/bench/peer_granular.py" --ringdem "$binary" "$@"
