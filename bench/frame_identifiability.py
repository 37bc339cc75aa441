#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""When the detections could first tell the VIO's frame: the earliest time, with hindsight, at which every other
frame the gate map allows is refuted by the detections so far.

A gate seen alone does not fix the frame: a square, upright gate looks the same from its front at a pose as from its
back at that pose turned half a turn about the gate's vertical axis, and with the ids unknown it looks the same as any
other gate of the same size. The frames the map allows besides the true one are therefore, for every gate g seen so
far, world_T_g' · F · world_T_g⁻¹ applied to the true trajectory, F the identity or half a turn about the vertical,
g' = g when the ids are known (F the turn only) and any map gate when they are not. Each hypothesis is tested on
every whole-gate detection (partial ones are skipped): the gate (the named one, or with the ids unknown the best one)
projected from the ground-truth pose under the hypothesis, through the sequence's camera (its stated mount and clock
offset), its four corners in the image order FORMATS.md writes them, against the detected corners; a detection is
explained when the corners' RMS is within 5 σ + 10 px (σ the detector's corner noise from sequence.yaml, 2 px if
absent: the margin takes a mount error of ~1.5° and gross misplacements only are tested). The frame is identified at
the first detection after which the truth explains at least 8 detections and every alternative at least 5 fewer than
the truth. The odometry's drift plays no part: it is what a causal lock must live with, not what the detections show.

Prints the earliest time (seconds after the first detection) and the alternative refuted last; with RUN_DIR, the
run's lock (metrics.json's initialized_at_s) against it.

Usage: bench/frame_identifiability.py SEQUENCE_DIR [RUN_DIR] [--json]   (numpy and PyYAML: Debian's python3-numpy,
python3-yaml)
SEQUENCE_DIR holds gt.tum, corners.csv, gates.yaml, camera.yaml (and sequence.yaml for σ and unknown ids).
"""
import csv
import json
import math
import os
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gate_coverage_bound import pose_at, read_tum, rotation  # noqa: E402

MIN_EXPLAINED = 8   # detections the truth must explain
MARGIN = 5          # detections every alternative must explain fewer than the truth


def yaw_matrix(yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def gate_pose(gate):
    """world_T_gate as (R, t): Rz(yaw) Ry(pitch) Rx(roll)."""
    yaw, pitch, roll = gate.get('yaw', 0.0), gate.get('pitch', 0.0), gate.get('roll', 0.0)
    cp, sp, cr, sr = math.cos(pitch), math.sin(pitch), math.cos(roll), math.sin(roll)
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return yaw_matrix(yaw) @ ry @ rx, np.array(gate['position'], dtype=float)


def gate_corners(gate):
    """The four inner corners in the world frame (3 x 4)."""
    r, t = gate_pose(gate)
    h = 0.5 * gate.get('size', 1.5)
    local = np.array([[0, h, h], [0, -h, h], [0, -h, -h], [0, h, -h]], dtype=float).T
    return r @ local + t[:, None]


class Camera:
    def __init__(self, path):
        c = yaml.safe_load(open(path))
        self.model = c.get('model', 'radtan')
        self.fx, self.fy, self.cx, self.cy = c['fx'], c['fy'], c['cx'], c['cy']
        self.width, self.height = c['width'], c['height']
        self.k = np.array(c.get('distortion', [0, 0, 0, 0]), dtype=float)
        pose = c.get('body_T_camera', {})
        self.r = rotation(np.array(pose.get('quaternion_xyzw', [0, 0, 0, 1]), dtype=float))
        self.t = np.array(pose.get('position', [0, 0, 0]), dtype=float)
        self.time_offset = float(c.get('time_offset', 0.0))

    def project(self, p):
        """Camera-frame points (3 x N) to pixels (2 x N); NaN behind the camera."""
        z = p[2]
        x, y = p[0] / z, p[1] / z
        if self.model == 'equidistant':
            r = np.hypot(x, y)
            theta = np.arctan(r)
            k1, k2, k3, k4 = (list(self.k) + [0, 0, 0, 0])[:4]
            td = theta * (1 + k1 * theta ** 2 + k2 * theta ** 4 + k3 * theta ** 6 + k4 * theta ** 8)
            scale = np.where(r > 1e-12, td / np.maximum(r, 1e-12), 1.0)
            xd, yd = x * scale, y * scale
        else:
            k1, k2, p1, p2 = (list(self.k) + [0, 0, 0, 0])[:4]
            r2 = x * x + y * y
            radial = 1 + k1 * r2 + k2 * r2 * r2
            xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
            yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
        pixels = np.vstack([self.fx * xd + self.cx, self.fy * yd + self.cy])
        pixels[:, z <= 0.05] = np.nan
        return pixels


def image_order(pixels):
    """FORMATS.md's order: the two upper (smaller v) left to right, then the two lower right to left."""
    order = np.argsort(pixels[1], kind='stable')
    upper = sorted(order[:2], key=lambda i: pixels[0, i])
    lower = sorted(order[2:], key=lambda i: -pixels[0, i])
    return pixels[:, upper + lower]


def read_detections(sequence):
    rows = []
    with open(os.path.join(sequence, 'corners.csv')) as f:
        for row in csv.DictReader(f):
            corners = np.array([[float(row[f'u_{c}']), float(row[f'v_{c}'])] for c in ('tl', 'tr', 'br', 'bl')]).T
            if np.all(np.isfinite(corners)):
                rows.append((float(row['t']), int(row['gate_id']), corners))
    rows.sort(key=lambda r: r[0])
    return rows


def main(argv):
    args = [a for a in argv if not a.startswith('--')]
    if not 1 <= len(args) <= 2:
        sys.exit(__doc__)
    sequence = args[0]
    truth = read_tum(os.path.join(sequence, 'gt.tum'))
    camera = Camera(os.path.join(sequence, 'camera.yaml'))
    gates = yaml.safe_load(open(os.path.join(sequence, 'gates.yaml')))['gates']
    info = {}
    if os.path.exists(os.path.join(sequence, 'sequence.yaml')):
        info = yaml.safe_load(open(os.path.join(sequence, 'sequence.yaml'))) or {}
    sigma = float((info.get('detection') or {}).get('pixel_sigma', 2.0))
    threshold = 5.0 * sigma + 10.0
    detections = read_detections(sequence)
    if not detections:
        sys.exit(f"{sequence}: no whole-gate detection in corners.csv")
    ids = [g['id'] for g in gates]
    corners_world = {g['id']: gate_corners(g) for g in gates}
    poses = {g['id']: gate_pose(g) for g in gates}
    unknown = all(d[1] < 0 for d in detections)
    # Camera poses at the detections (the stamp less the camera's clock offset), from the ground truth.
    cameras = []
    for t, _, _ in detections:
        p_b, r_b = pose_at(truth, t - camera.time_offset)
        cameras.append((r_b @ camera.r, r_b @ camera.t + p_b))

    def residuals(transform):
        """Per detection: the corner RMS [px] of the best explaining gate under world' = A · world, and that gate."""
        ra, ta = transform
        out = np.full(len(detections), np.inf)
        which = np.full(len(detections), -1)
        for k, (t, gate_id, observed) in enumerate(detections):
            r_c, p_c = cameras[k]
            r_c, p_c = ra @ r_c, ra @ p_c + ta   # the camera where the hypothesis puts it
            for g in ([gate_id] if gate_id >= 0 else ids):
                if g not in corners_world:
                    continue
                predicted = camera.project(r_c.T @ (corners_world[g] - p_c[:, None]))
                if not np.all(np.isfinite(predicted)):
                    continue
                rms = math.sqrt(np.mean(np.sum((image_order(predicted) - observed) ** 2, axis=0)))
                if rms < out[k]:
                    out[k], which[k] = rms, g
        return out, which

    true_res, true_gate = residuals((np.eye(3), np.zeros(3)))
    explained_true = true_res < threshold
    first_seen = {}
    for k in range(len(detections)):
        if explained_true[k] and true_gate[k] not in first_seen:
            first_seen[int(true_gate[k])] = k
    # The alternatives: gate g seen (as the truth explains it) taken for g' (turned or not).
    turn = (yaw_matrix(math.pi), np.zeros(3))
    alternatives = []
    for g, since in first_seen.items():
        rg, tg = poses[g]
        for g2 in (ids if unknown else [g]):
            r2, t2 = poses[g2]
            for flip in (False, True):
                if g2 == g and not flip:
                    continue
                rf = turn[0] if flip else np.eye(3)
                ra = r2 @ rf @ rg.T
                alternatives.append((since, f"gate {g} taken for {'the back of ' if flip else ''}gate {g2}",
                                     (ra, t2 - ra @ tg)))
    cumulative_true = np.cumsum(explained_true)
    # Told apart at detection k: the truth explains at least MIN_EXPLAINED, and every alternative in play (its gate
    # seen by k) explains at least MARGIN fewer, from k on (one not yet in play is no rival: once its gate is seen,
    # it must still explain what came before).
    told = cumulative_true >= MIN_EXPLAINED
    hardest = {}
    for since, label, transform in alternatives:
        res, _ = residuals(transform)
        refuted = cumulative_true - np.cumsum(res < threshold) >= MARGIN
        refuted[:since] = True
        told &= refuted
        hardest[label] = refuted
    stays = np.flip(np.logical_and.accumulate(np.flip(told)))
    earliest, last = None, "the truth explains fewer than 8 detections"
    if stays.any():
        k = int(np.argmax(stays))
        earliest = detections[k][0]
        # The alternative refuted last before k (the one that held the frame back).
        last_k = -1
        for label, refuted in hardest.items():
            before = np.nonzero(~refuted[:k + 1])[0]
            if len(before) and before[-1] > last_k:
                last_k, last = before[-1], label
        if last_k < 0:
            last = "none: the truth's 8 detections"
    else:
        for label, refuted in hardest.items():
            if not refuted[-1]:
                last = label + " (never refuted)"
    first = detections[0][0]
    result = {'first_detection': first, 'identified_at': earliest,
              'identified_after_s': None if earliest is None else earliest - first,
              'alternatives': len(alternatives), 'refuted_last': last, 'ids_unknown': unknown,
              'threshold_px': threshold, 'explained_by_truth': int(explained_true.sum()), 'detections': len(detections)}
    if len(args) == 2:
        metrics = json.load(open(os.path.join(args[1], 'metrics.json')))
        lock = metrics.get('initialized_at_s')
        result['lock_at'] = lock
        result['lock_after_identified_s'] = None if lock is None or earliest is None else lock - earliest
    if '--json' in argv:
        print(json.dumps(result))
        return
    text = "never" if earliest is None else f"{earliest - first:.2f} s after the first detection"
    print(f"{sequence}: the frame is identified {text} ({len(alternatives)} alternatives; the last refuted: {last}; "
          f"{int(explained_true.sum())} of {len(detections)} whole detections within {threshold:.0f} px of the truth)")
    if 'lock_at' in result:
        lock = result['lock_at']
        print("  run's lock: " + ("never" if lock is None else f"{lock - first:.2f} s after the first detection" +
              ("" if earliest is None else f", {lock - earliest:+.2f} s from the earliest")))


if __name__ == '__main__':
    main(sys.argv[1:])
