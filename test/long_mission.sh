#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The long mission (issue 7, part 5; ctest label "slow", run in CI by the README's test command): simulate
# LAPS laps (default 100) of the RATM ellipse, localise them with `dualgraph run` as onboard, and report the peak
# memory of both steps (/usr/bin/time -v), the main-graph optimisation time per keyframe from
# stats.csv as P50 / P95 / max per block of 10 laps, and whether every output number is finite.
#
#   bash test/long_mission.sh [BUILD_DIR]        # BUILD_DIR defaults to build; needs bin/dualgraph
#   LAPS=20 SEED=3 OUT=/tmp/mission bash test/long_mission.sh build
#
# Laps are assigned by time: lap = floor(t / (duration / LAPS)), duration the last odometry stamp
# (the simulator flies the laps at a steady pace, so this is within a keyframe of the true boundary).
# Exit code 0 when both steps succeed and the outputs are finite, 1 otherwise.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${1:-$ROOT/build}"
LAPS="${LAPS:-100}"
SEED="${SEED:-1}"
OUT="${OUT:-$BUILD/long_mission}"
BIN="$BUILD/bin/dualgraph"
[[ -x "$BIN" ]] || { echo "long_mission: $BIN not found (build the dualgraph target first)" >&2; exit 1; }
if [[ ! -x /usr/bin/time ]]; then
  if [[ $(id -u) -eq 0 ]]; then apt-get install -y -qq time >/dev/null; else
    echo "long_mission: /usr/bin/time missing (apt-get install time)" >&2; exit 1
  fi
fi
rm -rf "$OUT"
mkdir -p "$OUT"

peak_mib() { awk -F': ' '/Maximum resident set size/ {printf "%.1f", $2 / 1024}' "$1"; }
wall() { awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$1"; }

echo "long mission: $LAPS laps of ratm_ellipse, seed $SEED, into $OUT ($(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?'))"
/usr/bin/time -v "$BIN" simulate --profile clean --track "$ROOT/data/tracks/ratm_ellipse.yaml" --seed "$SEED" --laps "$LAPS" \
  --no-plot --out "$OUT/sequence" >"$OUT/simulate.out" 2>"$OUT/simulate.time" ||
  { cat "$OUT/simulate.time" >&2; exit 1; }
echo "simulate: wall $(wall "$OUT/simulate.time"), peak RSS $(peak_mib "$OUT/simulate.time") MiB"
/usr/bin/time -v "$BIN" run --sequence "$OUT/sequence" --out "$OUT/run" --quiet \
  >"$OUT/run.out" 2>"$OUT/run.time" || { cat "$OUT/run.time" >&2; exit 1; }
echo "run:      wall $(wall "$OUT/run.time"), peak RSS $(peak_mib "$OUT/run.time") MiB"

DURATION=$(awk '!/^#/ && NF {t = $1} END {print t}' "$OUT/sequence/vio.tum")
# Per block of 10 laps: keyframes, main-graph size at the block's end, optimisation ms P50/P95/max
# (nearest rank) over the block's keyframes (keyframe 0, with no optimisation, excluded).
awk -F, -v laps="$LAPS" -v duration="$DURATION" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  $col["termination"] == "initial" { next }
  {
    lap = int($col["t"] / (duration / laps)); if (lap >= laps) lap = laps - 1
    block = int(lap / 10); n[block]++; ms[block, n[block]] = $col["optimization_ms"]
    nodes[block] = $col["nodes"]; edges[block] = $col["edges"]; if (block > last) last = block
  }
  END {
    printf "%-9s %9s %7s %7s %8s %8s %8s\n", "laps", "keyframes", "nodes", "edges", "P50 ms", "P95 ms", "max ms"
    for (b = 0; b <= last; ++b) {
      if (n[b] == 0) continue
      for (i = 1; i <= n[b]; ++i) v[i] = ms[b, i]
      # insertion sort: at most a few hundred keyframes per block
      for (i = 2; i <= n[b]; ++i) { x = v[i]; j = i - 1; while (j > 0 && v[j] > x) { v[j + 1] = v[j]; --j }; v[j + 1] = x }
      p50 = v[int(0.50 * n[b] + 0.999999)]; p95 = v[int(0.95 * n[b] + 0.999999)]
      printf "%3d-%-5d %9d %7d %7d %8.2f %8.2f %8.2f\n", 10 * b + 1, 10 * b + 10, n[b], nodes[b], edges[b], p50, p95, v[n[b]]
    }
  }' "$OUT/run/stats.csv" | tee "$OUT/opt_ms_by_laps.txt"

# Finite outputs: every number in the trajectories and stats, every value in metrics.json.
bad=0
for f in "$OUT/run/estimate.tum" "$OUT/run/keyframes.tum" "$OUT/run/stats.csv" "$OUT/run/metrics.json"; do
  if grep -Eiq '(^|[^a-z_])(nan|inf|infinity)([^a-z_]|$)' "$f"; then echo "long_mission: non-finite value in $f" >&2; bad=1; fi
done
poses=$(grep -vc '^#' "$OUT/run/estimate.tum")
echo "estimate: $poses poses; metrics: $(grep -o '"ate_m": [^,]*\|"vio_ate_m": [^,]*\|"keyframes": [^,]*\|"opt_ms_p95": [^,]*' "$OUT/run/metrics.json" | tr '\n' ' ')"
[[ $bad -eq 0 ]] && echo "outputs finite: yes" || { echo "outputs finite: NO"; exit 1; }
