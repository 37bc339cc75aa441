#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The real-VIO table of bench/README.md: every real estimator's output on every real EuRoC flight in
# ../shared/data/real_vio (its README says what each file is; FLIGHT.gt.tum beside FLIGHT.NAME.tum), through the
# recorded-flight mode: virtual gates where the ground truth flies through them and the camera sees them on the
# approach, corners synthesised from the ground truth (clean detector profile at 2 px, or PROFILE=realistic for the
# mode's default), seeds 1-3, the VIO kept as recorded; then `dualgraph run` with the default configuration. A last
# row per flight feeds the ground truth itself as the VIO (a perfect odometry must stay perfect).
# Per run: the placed gates, the VIO's ATE, the causal floor over the run's span (bench/gate_coverage_bound.py:
# perfect fixes at every detection, the VIO in between), the run's ATE, the share of the floor's reduction kept
# = (VIO - run) / (VIO - floor) where the floor is at least 10 % below the VIO (else the run against the VIO),
# the lock after the first detection against the earliest time the detections could tell the frame
# (bench/frame_identifiability.py) and the share of time lost. Beside the floor, the floors whose fixes are what each
# instant's detections measure (bench/detection_fix_floor.py: their PnP pose, and its position with the true
# attitude), and the VIO taken as exact in the frame those fixes fit so far (needs BUILD_DIR/python).
# Usage: bench/real_vio_table.sh [BUILD_DIR] [OUT_DIR] [DATA_DIR]   (prints a Markdown table; keeps the runs)
# CONFIG=FILE runs with that configuration instead of the default; SEEDS="1 2 3" and FLIGHTS="V1_03_difficult ..."
# select rows; PROFILE=clean (default, 2 px) or realistic.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$(mktemp -d)}"
data="${3:-$here/../shared/data/real_vio}"
dualgraph="$build/bin/dualgraph"
profile="${PROFILE:-clean}"
profile_args=(--profile "$profile")
[ "$profile" = clean ] && profile_args+=(--pixel-sigma 2)
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3   # numpy is Debian's
echo "| flight | VIO | seed | gates | VIO ATE [m] | floor [m] | floors from the detections: PnP / position, true attitude / VIO as exact in the frame they fit [m] | run ATE [m] | kept of the floor's reduction | lock / earliest identification, after the first detection [s] | lost | exit |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"
for gt in "$data"/*.gt.tum; do
  flight="$(basename "$gt" .gt.tum)"
  if [ -n "${FLIGHTS:-}" ] && [[ " $FLIGHTS " != *" $flight "* ]]; then continue; fi
  vios=()
  for file in "$data/$flight".*.tum; do
    name="$(basename "$file" .tum)"; name="${name#"$flight".}"
    [ "$name" = gt ] || vios+=("$name")
  done
  vios+=(gt)
  for vio in "${vios[@]}"; do
    seeds="${SEEDS:-1 2 3}"
    [ "$vio" = gt ] && seeds="${seeds%% *}"
    for seed in $seeds; do
      dir="$out/$flight-$vio-$profile-$seed"
      rm -rf "$dir"
      mkdir -p "$dir"
      if ! "$dualgraph" simulate --flight "$gt" --vio "$data/$flight.$vio.tum" "${profile_args[@]}" --seed "$seed" \
          --no-plot --out "$dir/sequence" >"$dir/simulate.txt" 2>&1; then
        echo "| $flight | $vio | $seed | $(grep -o 'only [0-9]* place' "$dir/simulate.txt" | head -1 || echo '?') | | | | | | | | simulate refused |"
        continue
      fi
      code=0
      "$dualgraph" run ${CONFIG:+--config "$CONFIG"} --sequence "$dir/sequence" --out "$dir/run" --quiet \
        2>"$dir/stderr.txt" || code=$?
      floor="{}"
      if [ -s "$dir/run/estimate.tum" ]; then
        floor="$("$python" "$here/bench/gate_coverage_bound.py" "$dir/sequence" "$dir/run" --json 2>/dev/null || echo '{}')"
      fi
      told="$("$python" "$here/bench/frame_identifiability.py" "$dir/sequence" "$dir/run" --json 2>/dev/null || echo '{}')"
      run_dir=()
      [ -s "$dir/run/estimate.tum" ] && run_dir=("$dir/run")  # over the run's span, as the other columns
      fixes="$(PYTHONPATH="$build/python" "$python" "$here/bench/detection_fix_floor.py" "$dir/sequence" "${run_dir[@]}" --json 2>/dev/null || echo '{}')"
      "$python" - "$dir" "$flight" "$vio" "$seed" "$code" "$floor" "$told" "$fixes" <<'PY'
import json, re, sys
d, flight, vio, seed, code, floor, told, fixes = sys.argv[1:]
floor = json.loads(floor)
told = json.loads(told)
fixes = json.loads(fixes)
gates = re.search(r'gates: (\d+)', open(d + '/sequence/sequence.yaml').read().split('summary:')[1]).group(1)
try:
    m = json.load(open(d + '/run/metrics.json'))
except (OSError, ValueError):
    print(f"| {flight} | {vio} | {seed} | {gates} | | | | | | | | {code} (no metrics) |")
    sys.exit()
vio_ate, run_ate, floor_ate = floor.get('vio_ate_m'), floor.get('run_ate_m'), floor.get('floor_ate_m')
def f(v, digits=3):
    return "n/a" if v is None else f"{v:.{digits}f}"
if vio_ate is None or run_ate is None:
    kept = "n/a"
elif vio_ate < 1e-6:
    kept = "(truth as VIO)"
elif floor_ate <= 0.9 * vio_ate:
    kept = f"{100 * (vio_ate - run_ate) / (vio_ate - floor_ate):.0f} %"
else:
    kept = f"floor not 10 % below; run {100 * (run_ate / vio_ate - 1):+.0f} % of the VIO"
earliest = told.get('identified_after_s')
lock = "never" if m.get('initialized_at_s') is None or 'first_detection' not in told else \
    f"{m['initialized_at_s'] - told['first_detection']:.1f}"
lock += " / " + ("never" if earliest is None else f"{earliest:.1f}")
lost_s = (m.get('time_lost_s') or 0.0)
second = f"{f(fixes.get('detection_floor_ate_m'))} / {f(fixes.get('detection_floor_given_attitude_ate_m'))} / " \
    f"{f(fixes.get('frame_fit_ate_m'))}"
print(f"| {flight} | {vio} | {seed} | {gates} | {f(vio_ate)} | {f(floor_ate)} | {second} | {f(run_ate)} | {kept} | {lock} | "
      f"{f(m.get('lost_share_pct'), 1)} % ({lost_s:.1f} s) | {code} |")
PY
    done
  done
done
