#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""What the gates of a sequence can give at best: a causal fusion with perfect gate fixes.

At every detection's stamp the reference pose is the ground truth's (a perfect fix: position and attitude); between
detections it follows the VIO's own motion from the last one. No causal estimator does better while no gate is seen,
short of predicting the VIO's drift, so its ATE is the floor the gate coverage allows, and 1 − floor / VIO ATE the
largest ATE reduction a run can reach on it. Prints, over the span of the run's estimate.tum (or from the first
detection): the VIO's ATE, the floor's, the run's, and the share of the span more than 1 s after the last detection.
Every ATE is the position RMSE after an SE(3) alignment (Umeyama, no scale), as in a run's metrics.json.

Usage: bench/gate_coverage_bound.py SEQUENCE_DIR [RUN_DIR] [--markdown LABEL | --json]
SEQUENCE_DIR holds vio.tum and gt.tum (TUM rows: t x y z qx qy qz qw) and corners.csv or detections.csv.
"""
import csv
import os
import sys

import numpy as np


def read_tum(path):
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith('#'):
                continue
            fields = line.replace(',', ' ').split()
            if len(fields) < 8:
                sys.exit(f"{path}:{number}: expected t x y z qx qy qz qw, got {len(fields)} fields")
            rows.append([float(v) for v in fields[:8]])
    if len(rows) < 2:
        sys.exit(f"{path}: fewer than two poses")
    return np.array(rows)


def detection_stamps(sequence):
    for name in ('corners.csv', 'detections.csv'):
        path = os.path.join(sequence, name)
        if os.path.exists(path):
            with open(path) as f:
                stamps = sorted(float(row['t']) for row in csv.DictReader(f))
            if not stamps:
                sys.exit(f"{path}: no detection rows")
            return np.array(stamps)
    sys.exit(f"{sequence}: neither corners.csv nor detections.csv")


def rotation(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pose_at(trajectory, t):
    """Position interpolated linearly, rotation of the nearest sample (both trajectories are ≥ 20 Hz)."""
    p = np.array([np.interp(t, trajectory[:, 0], trajectory[:, k]) for k in (1, 2, 3)])
    i = int(np.clip(np.searchsorted(trajectory[:, 0], t), 1, len(trajectory) - 1))
    i = i if abs(trajectory[i, 0] - t) < abs(trajectory[i - 1, 0] - t) else i - 1
    return p, rotation(trajectory[i, 4:8])


def positions_at(trajectory, stamps):
    """pose_at's positions at many stamps at once (N x 3)."""
    return np.stack([np.interp(stamps, trajectory[:, 0], trajectory[:, k]) for k in (1, 2, 3)], axis=1)


def follow_vio_from_fixes(vio, vio_positions, last_fix, fix_pose):
    """The positions at the stamps whose last fix is `last_fix`, each following the VIO's motion since that fix;
    fix_pose(t) gives the fix's (position, rotation) in the map."""
    positions = np.empty_like(vio_positions)
    for fix in np.unique(last_fix):
        rows = last_fix == fix
        p_fix, r_fix = fix_pose(fix)
        v_p, v_r = pose_at(vio, fix)
        positions[rows] = p_fix + (r_fix @ v_r.T @ (vio_positions[rows] - v_p).T).T
    return positions


def aligned_ate(positions, truth):
    mu_e, mu_g = positions.mean(0), truth.mean(0)
    u, _, vt = np.linalg.svd((truth - mu_g).T @ (positions - mu_e) / len(positions))
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    r = u @ d @ vt
    error = (r @ positions.T).T + (mu_g - r @ mu_e) - truth
    return float(np.sqrt((error ** 2).sum(1).mean()))


def main(argv):
    args = [a for a in argv if not a.startswith('--')]
    label = argv[argv.index('--markdown') + 1] if '--markdown' in argv else None
    if label is not None:
        args.remove(label)
    if not 1 <= len(args) <= 2:
        sys.exit(__doc__)
    sequence = args[0]
    vio = read_tum(os.path.join(sequence, 'vio.tum'))
    truth = read_tum(os.path.join(sequence, 'gt.tum'))
    fixes = detection_stamps(sequence)
    estimate = read_tum(os.path.join(args[1], 'estimate.tum')) if len(args) == 2 else None
    begin = max(vio[0, 0], truth[0, 0], fixes[0])
    end = min(vio[-1, 0], truth[-1, 0])
    stamps = vio[:, 0][(vio[:, 0] >= begin) & (vio[:, 0] <= end)]
    if estimate is not None:
        stamps = estimate[:, 0][(estimate[:, 0] >= begin) & (estimate[:, 0] <= end)]
    if len(stamps) < 3:
        sys.exit(f"{sequence}: fewer than three stamps where the VIO, the ground truth and a detection overlap")
    last_fix = fixes[np.searchsorted(fixes, stamps, side='right') - 1]
    gap = int(((stamps - last_fix) > 1.0).sum())
    vio_positions = positions_at(vio, stamps)
    truth_positions = positions_at(truth, stamps)
    # world_T_body at each fix, perfect; the poses after it follow the VIO's motion since it
    floor = follow_vio_from_fixes(vio, vio_positions, last_fix, lambda fix: pose_at(truth, fix))
    vio_ate = aligned_ate(vio_positions, truth_positions)
    floor_ate = aligned_ate(floor, truth_positions)
    run_ate = None
    if estimate is not None:
        run_ate = aligned_ate(positions_at(estimate, stamps), truth_positions)
    gap_share = 100.0 * gap / len(stamps)
    # A VIO without error (the ground truth as VIO) has nothing to reduce.
    best = 'n/a' if vio_ate <= 1e-9 else f"{100.0 * (1.0 - floor_ate / vio_ate):.0f} %"
    run_text = 'n/a' if run_ate is None else f"{run_ate:.3f}"
    if '--json' in argv:
        import json
        print(json.dumps({'span_begin': float(stamps[0]), 'span_end': float(stamps[-1]), 'poses': len(stamps),
                          'vio_ate_m': vio_ate, 'floor_ate_m': floor_ate, 'run_ate_m': run_ate,
                          'first_detection': float(fixes[0]), 'share_after_1s_pct': gap_share}))
    elif label is not None:
        print(f"| {label} | {vio_ate:.3f} | {floor_ate:.3f} | {best} | {run_text} | {gap_share:.0f} % |")
    else:
        print(f"span {stamps[0]:.3f}–{stamps[-1]:.3f} s ({len(stamps)} poses): VIO ATE {vio_ate:.4f} m, "
              f"floor with perfect gate fixes {floor_ate:.4f} m (largest reduction {best}), run "
              f"{run_text} m; {gap_share:.0f} % of the span more than 1 s after the last detection")


if __name__ == '__main__':
    main(sys.argv[1:])
