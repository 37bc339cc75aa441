#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The field table of README.md and bench/README.md: whole races (the tracks' 12 laps) simulated on the
# realistic and harsh profiles, seeds 1-3 of each bundled track, run with the default configuration.
# Usage: bench/field_table.sh [BUILD_DIR] [OUT_DIR] [calibrated]   (prints a Markdown table; keeps the runs)
# With `calibrated`, each flight's camera is first calibrated on the flight itself (`dualgraph calibrate`: clock
# offset and mount rotation, offline, as a team would after a first flight) and the run uses that camera.
# CONFIG=FILE in the environment runs with that configuration instead of the default; REGIME=a,b simulates the
# flights with those regimes of real estimators over the profile (frontend/simulation/README.md); SEEDS="4 5 6"
# runs other seeds (the held-out ones).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$(mktemp -d)}"
mode="${3:-}"
dualgraph="$build/bin/dualgraph"
echo "| profile | track | seed | ATE [m] | VIO [m] | reduction | frame found | lost share | losses / relocalisations | final state | exit |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for profile in realistic harsh; do
  for track in ratm_ellipse ratm_lemniscate; do
    for seed in ${SEEDS:-1 2 3}; do
      dir="$out/$profile-$track-$seed"
      "$dualgraph" simulate --track "$here/data/tracks/$track.yaml" --profile "$profile" --seed "$seed" \
        ${REGIME:+--regime "$REGIME"} --out "$dir/sequence" >/dev/null
      sequence="$dir/sequence"
      if [ "$mode" = calibrated ]; then
        "$dualgraph" calibrate --sequence "$sequence" --out "$dir/camera.yaml" --quiet
        rm -rf "$dir/calibrated" && cp -r "$sequence" "$dir/calibrated" && cp "$dir/camera.yaml" "$dir/calibrated/camera.yaml"
        sequence="$dir/calibrated"
      fi
      code=0
      "$dualgraph" run ${CONFIG:+--config "$CONFIG"} --sequence "$sequence" --out "$dir/run" --quiet 2>"$dir/stderr.txt" || code=$?
      python3 - "$dir/run/metrics.json" "$profile" "$track" "$seed" "$code" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
profile, track, seed, code = sys.argv[2:6]
def f(key, digits=3):
    value = m.get(key)
    return "n/a" if value is None else f"{value:.{digits}f}"
print(f"| {profile} | {track.replace('ratm_', '')} | {seed} | {f('ate_m')} | {f('vio_ate_m')} | {f('ate_reduction_pct', 1)} % | "
      f"{f('initialized_at_s', 2)} s | {f('lost_share_pct', 1)} % | {m['losses']} / {m['relocalizations']} | "
      f"{m['final_state']} | {code} |")
PY
    done
  done
done
