#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The second floor: gate_coverage_bound.py's causal fusion with fixes as good as the detections themselves are.

gate_coverage_bound.py fixes the pose perfectly at every detection (the ground truth's position and attitude). Real
corners are noisy and far gates are small in the image, so no estimator gets such fixes from them. Here each
detection instant's fix is what that instant's detections alone measure: every detection solved by the library's
own gate PnP (dualgraph.GateFrontend with the default configuration, the sequence's camera and map; the ground
truth only chooses which map gate a detection is, as the known ids do; partial gates are left out), the pose of the instant's most precise
one (smallest position covariance) taken as world_T_body = world_T_gate · body_T_gate⁻¹; between fixes the VIO's
own motion from the last one, as in the first floor. An instant whose detections give no pose keeps the last fix.
Also the same fixes' positions with the ground truth's attitude (the gate's centre as the detection puts it in the
body, placed at the map gate): what the detections' positions are worth once the attitude is right. Neither is a
lower bound (an estimator that pools several instants can do better); they show what one instant's detections are
worth on the flight, so a run can be read against what its detections allow.
Third: the VIO taken as exact and put in the map by the rigid frame that the PnP fixes so far fit (positions, least
squares; the newest fix's pose while they span no plane). A causal run must find the VIO's frame from these
detections: where this is above the VIO's own ATE, even an estimator that trusted the VIO fully could not end at
the VIO's ATE.

Usage: PYTHONPATH=BUILD/python bench/detection_fix_floor.py SEQUENCE_DIR [RUN_DIR] [--json]
Prints the VIO's ATE, both floors and the run's (when given) over the same span as gate_coverage_bound.py (from the
first fix on), and the fixes' median position errors.
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gate_coverage_bound as bound  # noqa: E402

try:
    import dualgraph
except ImportError:
    sys.exit("detection_fix_floor.py needs the dualgraph Python module: PYTHONPATH=BUILD/python")


def detection_fixes(sequence_dir, truth):
    """{t: 4×4 world_T_body} from each instant's most precise PnP pose, and the same with the ground truth's attitude
    (the detection's position content alone: the gate's centre in the body put at the map gate)."""
    sequence = dualgraph.load_sequence(sequence_dir)
    config_path = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'data', 'config', 'default.yaml')
    frontend = dualgraph.GateFrontend(sequence, dualgraph.load_run_config(config_path))
    world_T_gate = {gate: dualgraph.pose_to_matrix(pose) for gate, pose in sequence.gates.items()}
    stamps, ids, pixels = sequence.corners[:3]
    fixes, fixes_given_attitude = {}, {}
    start = 0
    while start < len(stamps):
        end = start
        while end < len(stamps) and stamps[end] == stamps[start]:
            end += 1
        t = float(stamps[start])
        p, r = bound.pose_at(truth, t)
        world_T_body = np.eye(4)
        world_T_body[:3, :3], world_T_body[:3, 3] = r, p
        whole = np.isfinite(np.asarray(pixels[start:end])).all(axis=(1, 2))  # partial gates give no pose
        observations = [] if not whole.any() else frontend.process_corners(
            t, np.asarray(ids[start:end])[whole], np.asarray(pixels[start:end])[whole], world_T_body)
        best = None
        for observation in observations:
            if observation.kind != 'pose' or observation.gate_id not in world_T_gate:
                continue
            spread = float(np.trace(np.asarray(observation.covariance)[:3, :3]))
            if best is None or spread < best[0]:
                best = (spread, observation)
        if best is not None:
            body_T_gate = np.asarray(best[1].body_T_gate_matrix)
            fixes[t] = world_T_gate[best[1].gate_id] @ np.linalg.inv(body_T_gate)
            # The same detection's position with the attitude known: the gate's centre seen from the body.
            with_attitude = world_T_body.copy()
            with_attitude[:3, 3] = world_T_gate[best[1].gate_id][:3, 3] - r @ body_T_gate[:3, 3]
            fixes_given_attitude[t] = with_attitude
        start = end
    return fixes, fixes_given_attitude


def rigid_fit(source, target):
    """R, p with R·source + p ≈ target (least squares, no scale), or None when the points span no plane."""
    mu_s, mu_t = source.mean(0), target.mean(0)
    u, singular, vt = np.linalg.svd((target - mu_t).T @ (source - mu_s) / len(source))
    if len(source) < 3 or singular[1] < 1e-4:  # collinear within a centimetre: the roll about the line is free
        return None
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    r = u @ d @ vt
    return r, mu_t - r @ mu_s


def frame_from_fixes(vio, fixes, fix_times, stamps):
    """The VIO taken as exact, put in the map by the frame the fixes so far tell: at each stamp, the rigid fit of the
    VIO's positions at every fix instant up to it onto the fixes' positions (the newest fix's whole pose while the
    fixes span no plane). Positions [n×3]: what an estimator that trusted the VIO fully could give, causally."""
    fix_positions = np.array([fixes[t][:3, 3] for t in fix_times])
    vio_at_fixes = bound.positions_at(vio, fix_times)
    out = np.empty((len(stamps), 3))
    count_before = np.searchsorted(fix_times, stamps, side='right')
    fits = {}
    for k, t in enumerate(stamps):
        n = count_before[k]
        if n not in fits:
            fits[n] = rigid_fit(vio_at_fixes[:n], fix_positions[:n])
            if fits[n] is None:  # one fix's pose: world_T_odom = world_T_body · (odom_T_body)⁻¹
                p, r = bound.pose_at(vio, fix_times[n - 1])
                world_T_body = fixes[fix_times[n - 1]]
                rotation = world_T_body[:3, :3] @ r.T
                fits[n] = (rotation, world_T_body[:3, 3] - rotation @ p)
        r, p = fits[n]
        out[k] = r @ bound.positions_at(vio, np.array([t]))[0] + p
    return out


def main(argv):
    args = [a for a in argv if not a.startswith('--')]
    if not 1 <= len(args) <= 2:
        sys.exit(__doc__)
    sequence = args[0]
    vio = bound.read_tum(os.path.join(sequence, 'vio.tum'))
    truth = bound.read_tum(os.path.join(sequence, 'gt.tum'))
    estimate = bound.read_tum(os.path.join(args[1], 'estimate.tum')) if len(args) == 2 else None
    fixes, fixes_given_attitude = detection_fixes(sequence, truth)
    if not fixes:
        sys.exit(f"{sequence}: no detection gave a pose")
    fix_times = np.array(sorted(fixes))
    first = bound.detection_stamps(sequence)[0]
    begin, end = max(vio[0, 0], truth[0, 0], first), min(vio[-1, 0], truth[-1, 0])
    source = estimate if estimate is not None else vio
    stamps = source[:, 0][(source[:, 0] >= begin) & (source[:, 0] <= end)]
    stamps = stamps[stamps >= fix_times[0]]
    if len(stamps) < 3:
        sys.exit(f"{sequence}: fewer than three stamps after the first fix")
    last_fix = fix_times[np.searchsorted(fix_times, stamps, side='right') - 1]
    vio_positions = bound.positions_at(vio, stamps)
    truth_positions = bound.positions_at(truth, stamps)

    def floor_with(chosen):
        floor = bound.follow_vio_from_fixes(vio, vio_positions, last_fix,
                                            lambda fix: (chosen[fix][:3, 3], chosen[fix][:3, :3]))
        return bound.aligned_ate(floor, truth_positions)

    def median_error(chosen):
        return float(np.median([np.linalg.norm(chosen[t][:3, 3] - bound.pose_at(truth, t)[0]) for t in fix_times]))

    result = {'span_begin': float(stamps[0]), 'span_end': float(stamps[-1]), 'fixes': len(fix_times),
              'fix_error_median_m': median_error(fixes),
              'fix_error_given_attitude_median_m': median_error(fixes_given_attitude),
              'vio_ate_m': bound.aligned_ate(vio_positions, truth_positions),
              'detection_floor_ate_m': floor_with(fixes),
              'detection_floor_given_attitude_ate_m': floor_with(fixes_given_attitude),
              'frame_fit_ate_m': bound.aligned_ate(frame_from_fixes(vio, fixes, fix_times, stamps), truth_positions),
              'run_ate_m': None if estimate is None else bound.aligned_ate(bound.positions_at(estimate, stamps),
                                                                           truth_positions)}
    if '--json' in argv:
        print(json.dumps(result))
    else:
        run = 'n/a' if result['run_ate_m'] is None else f"{result['run_ate_m']:.4f} m"
        print(f"{result['fixes']} fixes: VIO ATE {result['vio_ate_m']:.4f} m; with each instant's PnP pose as the fix "
              f"(median position error {result['fix_error_median_m']:.3f} m) {result['detection_floor_ate_m']:.4f} m; "
              f"its position with the true attitude (median error {result['fix_error_given_attitude_median_m']:.3f} m) "
              f"{result['detection_floor_given_attitude_ate_m']:.4f} m; the VIO as exact in the frame the fixes so far "
              f"fit {result['frame_fit_ate_m']:.4f} m; run {run}")


if __name__ == '__main__':
    main(sys.argv[1:])
