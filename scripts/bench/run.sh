#!/usr/bin/env bash
# Builds the "native" preset (-O3 -march=native) and runs the micro-benchmarks.
#   scripts/bench/run.sh [google-benchmark options, e.g. --benchmark_filter=Step]
# Goal (foundation issue): whole step of 100 rings (10 000 particles) <= 40 ns per
# particle-step on one core. Results also go to build/native/bench.json.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
ringdem_install_packages
ringdem_build native
cd "$RINGDEM_ROOT"
build/native/scripts/bench/ringdem_bench --benchmark_out=build/native/bench.json \
  --benchmark_out_format=json "$@"
