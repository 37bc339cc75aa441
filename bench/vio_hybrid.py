#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A VIO with one part of its error taken out: its positions with the ground truth's attitude, or the reverse.

The VIO is first put in the ground truth's frame by the SE(3) (Umeyama, no scale) alignment of its positions; then
  position  keeps the VIO's positions and takes the ground truth's attitude (the attitude error removed),
  attitude  keeps the VIO's attitude and takes the ground truth's positions (the position drift removed),
  both      keeps both (the aligned VIO itself).
Feed the result to `dualgraph simulate --flight GT --vio OUT` to see what each part of a real VIO's error costs a
run (bench/README.md). Output: TUM rows at the VIO's stamps inside the ground truth's span.

Usage: bench/vio_hybrid.py VIO.tum GT.tum position|attitude|both OUT.tum
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gate_coverage_bound import read_tum, rotation  # noqa: E402


def quaternion(r):
    """xyzw of a rotation matrix (w ≥ 0)."""
    w = np.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2.0
    x = np.copysign(np.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2.0, r[2, 1] - r[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2.0, r[0, 2] - r[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2.0, r[1, 0] - r[0, 1])
    q = np.array([x, y, z, w])
    return q / np.linalg.norm(q)


def main(argv):
    if len(argv) != 4 or argv[2] not in ('position', 'attitude', 'both'):
        sys.exit(__doc__)
    vio, truth = read_tum(argv[0]), read_tum(argv[1])
    vio = vio[(vio[:, 0] >= truth[0, 0]) & (vio[:, 0] <= truth[-1, 0])]
    if len(vio) < 3:
        sys.exit(f"{argv[0]}: fewer than three poses inside {argv[1]}'s span")
    t = vio[:, 0]
    true_positions = np.stack([np.interp(t, truth[:, 0], truth[:, k]) for k in (1, 2, 3)], 1)
    mu_v, mu_g = vio[:, 1:4].mean(0), true_positions.mean(0)
    u, _, vt = np.linalg.svd((true_positions - mu_g).T @ (vio[:, 1:4] - mu_v) / len(vio))
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    world_r_vio = u @ d @ vt
    aligned = (world_r_vio @ vio[:, 1:4].T).T + (mu_g - world_r_vio @ mu_v)
    nearest = np.clip(np.searchsorted(truth[:, 0], t), 0, len(truth) - 1)
    with open(argv[3], 'w') as out:
        out.write(f'# {argv[2]} of {argv[0]} aligned to {argv[1]} (bench/vio_hybrid.py): t x y z qx qy qz qw\n')
        for k in range(len(t)):
            keep_position = argv[2] in ('position', 'both')
            keep_attitude = argv[2] in ('attitude', 'both')
            p = aligned[k] if keep_position else true_positions[k]
            r = world_r_vio @ rotation(vio[k, 4:8]) if keep_attitude else rotation(truth[nearest[k], 4:8])
            out.write('%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n' % (t[k], *p, *quaternion(r)))


if __name__ == '__main__':
    main(sys.argv[1:])
