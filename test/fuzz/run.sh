#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs every libFuzzer target (test/fuzz/README.md) for SECONDS each, one after the other by default:
#   bash test/fuzz/run.sh SECONDS [TARGET...]      e.g. bash test/fuzz/run.sh 30, or ... 600 fuzz_g2o
# Configures and builds ./build_fuzz with clang (FUZZ_BUILD_DIR=..., FUZZ_CXX=... override) or reuses
# it. Seeds: test/fuzz/corpus/<target> (committed, read only) and, when ../shared exists, the heads of
# its matching files; new inputs go to $FUZZ_BUILD_DIR/corpus/<target>, crashes to
# $FUZZ_BUILD_DIR/artifacts/<target>/. Fixed -seed (FUZZ_SEED, default 1). Prints per target the
# executions, exec/s, cov/ft and corpus size from libFuzzer's final stats; exits 1 if any target
# crashed, leaked, timed out or ran out of memory (logs in $FUZZ_BUILD_DIR/logs/<target>.log).
# FUZZ_JOBS=N runs N targets at a time (CI: 2).
set -euo pipefail
seconds=${1:-}
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "usage: bash test/fuzz/run.sh SECONDS [TARGET...]" >&2
  exit 2
fi
shift
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${FUZZ_BUILD_DIR:-$root/build_fuzz}
shared=${DUALGRAPH_SHARED_DIR:-$root/../shared}
cxx=${FUZZ_CXX:-$(command -v clang++-14 || command -v clang++ || true)}
[ -n "$cxx" ] || { echo "run.sh: clang++ not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 1; }
all_targets=(fuzz_g2o fuzz_tum fuzz_euroc fuzz_corner_detections fuzz_pose_detections fuzz_track_yaml
             fuzz_camera_yaml fuzz_localizer_params_yaml fuzz_run_config fuzz_ratm_json fuzz_live_stream)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")

if [ ! -f "$build/CMakeCache.txt" ]; then
  # -O1 -g with assertions on (no NDEBUG): Eigen's bounds checks stay armed. Tests and benchmarks off.
  cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DDUALGRAPH_BUILD_FUZZ=ON \
        -DDUALGRAPH_BUILD_TESTS=OFF -DDUALGRAPH_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target "${targets[@]}" >/dev/null

# The shared files each target is seeded with (their first 8 KB, cut at a line end).
shared_seeds() {
  case "$1" in
    fuzz_g2o) ls "$shared"/data/posegraph/*.g2o ;;
    fuzz_corner_detections|fuzz_pose_detections|fuzz_tum|fuzz_euroc) ls "$shared"/data/ratm/*.csv ;;
    fuzz_track_yaml|fuzz_camera_yaml|fuzz_localizer_params_yaml|fuzz_run_config)
      ls "$shared"/data/ratm/flight_metadata/*.yaml ;;
    fuzz_ratm_json) ls "$shared"/data/ratm/tii_camera_calibration/*.json "$shared"/data/ratm/openvins_online_calib/*.json ;;
  esac 2>/dev/null || true
}
dictionary() {
  case "$1" in
    fuzz_g2o) echo g2o ;;
    fuzz_tum|fuzz_euroc|fuzz_corner_detections|fuzz_pose_detections) echo csv ;;
    fuzz_ratm_json) echo json ;;
    *) echo yaml ;;
  esac
}

# One target: fuzz it, then write its row of the table to logs/<target>.row; non-zero when it failed.
fuzz_one() {
  local target=$1 work="$build/corpus/$1" seeds="$build/shared_seeds/$1" artifacts="$build/artifacts/$1"
  local log="$build/logs/$1.log" file status execs rate last cov ft corpus result
  mkdir -p "$work" "$seeds" "$artifacts" "$(dirname "$log")"
  while read -r file; do
    [ -n "$file" ] || continue
    if [ "$(wc -c <"$file")" -le 8192 ]; then cp "$file" "$seeds/"
    else head -c 8192 "$file" | sed '$d' > "$seeds/$(basename "$file")"; fi
  done < <(shared_seeds "$target")
  set +e
  "$build/fuzz/$target" "$work" "$root/test/fuzz/corpus/$target" "$seeds" \
    -dict="$root/test/fuzz/dict/$(dictionary "$target").dict" -seed="${FUZZ_SEED:-1}" \
    -max_total_time="$seconds" -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$artifacts/" -print_final_stats=1 >"$log" 2>&1
  status=$?
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corpus=$(find "$work" -type f | wc -l)
  if [ "$status" -eq 0 ]; then result=ok; else result="FAILED (exit $status, see $log)"; fi
  printf '%-28s %12s %9s %7s %8s %7s  %s\n' "$target" "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" \
    "$corpus" "$result" >"$build/logs/$target.row"
  return "$status"
}

# FUZZ_JOBS targets at a time (default 1: the figures of one target are not shared with another).
jobs=${FUZZ_JOBS:-1}
running=0
for target in "${targets[@]}"; do
  rm -f "$build/logs/$target.row"
  fuzz_one "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
done
wait || true

failed=()
printf '%-28s %12s %9s %7s %8s %7s  %s\n' target execs exec/s cov ft corpus result
for target in "${targets[@]}"; do
  row="$build/logs/$target.row"
  if [ -f "$row" ]; then cat "$row"; else echo "$target: no result (see $build/logs/$target.log)"; fi
  grep -q '  ok$' "$row" 2>/dev/null || failed+=("$target")
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "run.sh: ${failed[*]} failed; the crashing inputs are in $build/artifacts/" >&2
  exit 1
fi
