#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The real-VIO table of bench/README.md: real estimators' outputs on real EuRoC flights (../shared/data/real_vio,
# its README says what each file is), through the recorded-flight mode: virtual gates placed on the ground-truth
# path, corners synthesised from the ground truth (clean detector profile, 2 px, seeds 1-3), the VIO kept as
# recorded; then `dualgraph run` with the default configuration. A last row per flight feeds the ground truth
# itself as the VIO (a perfect odometry must stay perfect).
# Usage: bench/real_vio_table.sh [BUILD_DIR] [OUT_DIR] [DATA_DIR]   (prints a Markdown table; keeps the runs)
# CONFIG=FILE in the environment runs with that configuration instead of the default.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$(mktemp -d)}"
data="${3:-$here/../shared/data/real_vio}"
dualgraph="$build/bin/dualgraph"
echo "| flight | VIO | seed | ATE [m] | VIO ATE [m] | reduction | frame found (after the first VIO stamp) | lost share | final state | exit |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for pair in MH_02_easy:vislam_rp V2_01_easy:vio_mono V2_01_easy:vio_stereo V2_01_easy:vislam_rp MH_02_easy:gt V2_01_easy:gt; do
  flight="${pair%%:*}"
  vio="${pair##*:}"
  seeds="1 2 3"
  [ "$vio" = gt ] && seeds=1
  for seed in $seeds; do
    dir="$out/$flight-$vio-$seed"
    rm -rf "$dir"
    "$dualgraph" simulate --flight "$data/$flight.gt.tum" --vio "$data/$flight.$vio.tum" --profile clean \
      --pixel-sigma 2 --seed "$seed" --no-plot --out "$dir/sequence" >/dev/null
    code=0
    "$dualgraph" run ${CONFIG:+--config "$CONFIG"} --sequence "$dir/sequence" --out "$dir/run" --quiet 2>"$dir/stderr.txt" || code=$?
    if [ ! -f "$dir/run/metrics.json" ]; then
      echo "| $flight | $vio | $seed | n/a | n/a | n/a | n/a | n/a | n/a | $code |"
      continue
    fi
    python3 - "$dir/run/metrics.json" "$flight" "$vio" "$seed" "$code" "$dir/sequence/vio.tum" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
flight, vio, seed, code = sys.argv[2:6]
first = next(float(l.split()[0]) for l in open(sys.argv[6]) if l.strip() and not l.startswith('#'))
def f(key, digits=3):
    value = m.get(key)
    return "n/a" if value is None else f"{value:.{digits}f}"
# A VIO that is the ground truth has no error to reduce: its reduction is n/a. Times from the VIO file's first stamp.
reduction = f('ate_reduction_pct', 1) + " %" if m.get('vio_ate_m', 0) > 1e-6 else "n/a"
found = "n/a" if m.get('initialized_at_s') is None else f"{m['initialized_at_s'] - first:.2f} s"
print(f"| {flight} | {vio} | {seed} | {f('ate_m')} | {f('vio_ate_m')} | {reduction} | "
      f"{found} | {f('lost_share_pct', 1)} % | {m['final_state']} | {code} |")
PY
  done
done
