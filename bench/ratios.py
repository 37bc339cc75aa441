#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Prints the issue-6 targets from the JSON bench/run.sh writes (medians when repetitions were run).

    bench/ratios.py OUTDIR        reads OUTDIR/dualgraph_bench.json and OUTDIR/dualgraph_localizer_bench.json

Each row: the measured figure, the target, and whether it is met. Missing benchmarks are skipped.
Standard library only.
"""
import json
import os
import sys

UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def load(path):
    """run_name -> the median row (or the only row) of each benchmark."""
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for row in data.get("benchmarks", []):
        if row.get("error_occurred"):
            continue
        name = row.get("run_name", row["name"])
        if row.get("run_type") == "aggregate" and row.get("aggregate_name") != "median":
            continue
        if name in rows and row.get("run_type") != "aggregate":
            continue  # keep the median over single repetitions
        rows[name] = row
    return rows


def ms(row):
    return row["real_time"] * UNIT_MS[row.get("time_unit", "ns")]


def find(rows, prefix):
    for name, row in rows.items():
        if name.startswith(prefix):
            return row
    return None


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    engine = load(os.path.join(sys.argv[1], "dualgraph_bench.json"))
    dual = load(os.path.join(sys.argv[1], "dualgraph_localizer_bench.json"))
    out = []

    def ratio_row(what, ours, theirs, target, ok):
        if ours is None or theirs is None:
            return
        r = ms(ours) / ms(theirs)
        out.append((what, f"{ms(ours):.4g} / {ms(theirs):.4g} ms = {r:.2f}", target, "yes" if ok(r) else "NO"))

    for dataset in ["sphere2500", "parking-garage", "smallGrid3D", "intel"]:
        ratio_row(f"LM iteration / bare factor+solve, {dataset}",
                  engine.get(f"BM_PoseGraph_LmIteration/{dataset}"),
                  engine.get(f"BM_PoseGraph_BareCholmodFactorSolve/{dataset}"), "<= 1.2", lambda r: r <= 1.2)
    # Ours with g2o's damping (the engine's default) and with diagonal damping (Ceres' kind; the Localizer's).
    for dataset in ["sphere2500", "parking-garage", "smallGrid3D", "intel"]:
        for suffix, label in [("", "identity"), ("_diagonal", "diagonal")]:
            ratio_row(f"dualgraph ({label}) / Ceres full solve, {dataset}",
                      find(engine, f"BM_SideBySide_Dualgraph/{dataset}{suffix}/"),
                      find(engine, f"BM_SideBySide_Ceres/{dataset}/"), "<= 1 (3-D)", lambda r: r <= 1.0)
    for case in ["kf250_cap10", "kf1800_cap10", "kf250_cap100", "kf1800_cap100"]:
        for suffix, label in [("_diagonal", "Localizer's diagonal"), ("", "identity")]:
            ratio_row(f"dualgraph ({label}) / Ceres racing main graph, {case}",
                      find(dual, f"BM_RacingMainGraph_Dualgraph/{case}{suffix}/"),
                      find(dual, f"BM_RacingMainGraph_Ceres/{case}/"), "<= 0.5", lambda r: r <= 0.5)
    for case, limit in [("kf250", 1.0), ("kf1000", None), ("kf1800", 5.0)]:
        for mode in ["fixed_lag", "full_batch"]:
            row = find(dual, f"BM_MainGraph_KeyframeUpdate/{case}_{mode}/")
            if row is None:
                continue
            p95 = row["opt_ms_p95"]
            size = f"{row['keyframes']:.0f} kf / {row['main_edges']:.0f} edges"
            target = f"<= {limit} ms" if limit else "-"
            met = "-" if limit is None else ("yes" if p95 <= limit else "NO")
            out.append((f"keyframe update P95, {case} {mode} ({size})", f"{p95:.3g} ms", target, met))
    row = find(dual, "BM_TemporaryGraph_Distil/gates:11/poses:50/per_pose:4/graph:0/")
    if row is not None:
        out.append(("distil 11 gates / 50 poses", f"{ms(row) * 1e3:.0f} us", "<= 200 us",
                    "yes" if ms(row) <= 0.2 else "NO"))

    width = max(len(r[0]) for r in out) if out else 0
    for what, value, target, met in out:
        print(f"{what:<{width}}  {value:<32} {target:<12} {met}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
