#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-detection gate PnP consistency by range on a sequence with ground truth (bench/README.md, "Far gates").

Every image's corners go through the run's frontend (dualgraph.GateFrontend, default configuration) at the true
body pose; each pose observation is compared with the true body_T_gate (the sequence's gates.yaml must be the true
map: map_position_sigma 0). Prints, per 3 m of range: the count, the mean and median NEES (6 dof: 6 and 5.35 when
consistent), the mean error along the line of sight (a range bias), the median translation error beside the median
stated sigma, and the median rotation error.
Usage: PYTHONPATH=build/python python3 bench/pnp_range_bias.py SEQUENCE_DIR
"""
import sys
from collections import defaultdict

import numpy as np

import dualgraph as dg


def matrix(pose):
    x, y, z, qx, qy, qz, qw = pose
    rotation = np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, (x, y, z)
    return out


def so3_log(rotation):
    angle = np.arccos(np.clip((np.trace(rotation) - 1) / 2, -1, 1))
    if angle < 1e-9:
        return np.zeros(3)
    return angle / (2 * np.sin(angle)) * np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0],
                                                    rotation[1, 0] - rotation[0, 1]])


def main(folder):
    sequence = dg.load_sequence(folder)
    if sequence.ground_truth is None:
        sys.exit(f"{folder}: no ground truth (gt.tum)")
    gt_times, gt_poses = sequence.ground_truth
    gates = {gate_id: matrix(pose) for gate_id, pose in sequence.gates.items()}
    frontend = dg.GateFrontend(sequence)
    times, ids, pixels = sequence.corners
    rows = defaultdict(list)
    for t in np.unique(times):
        image = np.where(times == t)[0]
        k = int(np.clip(np.searchsorted(gt_times, t), 1, len(gt_times) - 1))
        if abs(gt_times[k - 1] - t) < abs(gt_times[k] - t):
            k -= 1
        world_T_body = matrix(gt_poses[k])
        for o in frontend.process_corners(t, ids[image], pixels[image], gt_poses[k]):
            if o.kind != 'pose' or o.gate_id not in gates:
                continue
            estimate, truth = o.body_T_gate_matrix, np.linalg.inv(world_T_body) @ gates[o.gate_id]
            error = np.concatenate([truth[:3, :3].T @ (estimate[:3, 3] - truth[:3, 3]),
                                    so3_log(truth[:3, :3].T @ estimate[:3, :3])])
            covariance = np.array(o.covariance)
            distance = np.linalg.norm(truth[:3, 3])
            rows[int(distance // 3)].append((error @ np.linalg.solve(covariance, error),
                                             truth[:3, 3] @ (estimate[:3, 3] - truth[:3, 3]) / distance,
                                             np.linalg.norm(estimate[:3, 3] - truth[:3, 3]),
                                             np.sqrt(np.trace(covariance[:3, :3])),
                                             np.degrees(np.linalg.norm(error[3:]))))
    print("| range [m] | views | NEES mean | NEES median | range error mean [m] | translation error median [m] "
          "| stated sigma median [m] | rotation error median [deg] |")
    print("|---|---|---|---|---|---|---|---|")
    for b in sorted(rows):
        a = np.array(rows[b])
        print(f"| {3 * b}-{3 * b + 3} | {len(a)} | {a[:, 0].mean():.1f} | {np.median(a[:, 0]):.2f} | {a[:, 1].mean():+.3f} "
              f"| {np.median(a[:, 2]):.3f} | {np.median(a[:, 3]):.3f} | {np.median(a[:, 4]):.2f} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
