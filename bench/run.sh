#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the benchmarks (Release, in their own build folder) and runs them with the repetitions the
# README's tables use, writing Google Benchmark's JSON to OUTDIR/<executable>.json (console output to
# OUTDIR/<executable>.txt, load averages to OUTDIR/uptime.txt).
#
#   bench/run.sh OUTDIR [FILTER]     FILTER: a --benchmark_filter regex applied to both executables
#
# Environment: BUILD_DIR (default: <repository>/build-bench), JOBS (default 2), REPETITIONS (default 3).
# OPENBLAS_NUM_THREADS is passed through (unset: OpenBLAS uses every core). Needs libbenchmark-dev;
# libceres-dev is optional (without it the side-by-side benchmarks are not built and the executables
# say "Ceres: not found").
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
  echo "usage: bench/run.sh OUTDIR [FILTER]" >&2
  exit 2
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=$1
filter=${2:-.}
build=${BUILD_DIR:-$root/build-bench}
repetitions=${REPETITIONS:-3}
mkdir -p "$out"
out=$(cd "$out" && pwd)

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DDUALGRAPH_BUILD_TESTS=OFF -DDUALGRAPH_BUILD_PYTHON=OFF >/dev/null
cmake --build "$build" -j "${JOBS:-2}" --target dualgraph_bench dualgraph_localizer_bench

{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "commit: $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)"
  echo "before: $(uptime)"
} >"$out/uptime.txt"
for exe in dualgraph_bench dualgraph_localizer_bench; do
  "$build/bin/$exe" --benchmark_filter="$filter" --benchmark_repetitions="$repetitions" \
    --benchmark_report_aggregates_only=true \
    --benchmark_out="$out/$exe.json" --benchmark_out_format=json | tee "$out/$exe.txt"
  echo "after $exe: $(uptime)" >>"$out/uptime.txt"
done
echo "bench/run.sh: results in $out"
