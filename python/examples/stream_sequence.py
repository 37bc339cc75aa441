#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A sequence folder fed to dualgraph.StreamingLocalizer sample by sample, as a drone's callbacks would, and the
answer compared with run_sequence (= `dualgraph run`):

    PYTHONPATH=build/python python3 python/examples/stream_sequence.py SEQUENCE_DIR [CONFIG.yaml]

Each detection instant (one image's corners, camera clock) goes in before the first odometry sample it precedes by
less than LEAD seconds, as a detector's output arrives ahead of the VIO's, and an empty call says the detector is
done up to there (its images without gates); the pipeline holds each instant until the odometry covers it. Prints the state and the corrected pose every second of flight, then the comparison; exit 1 unless the
streamed estimate equals run_sequence's.
"""
import sys

import numpy as np

import dualgraph

LEAD = 0.25  # [s], within frontend.max_detection_lead_s (1 s)


def instants(sequence):
    """[(t, gate_ids (m,), pixels (m, 4, 2))] per image, camera clock, in file order (corners.csv)."""
    times, ids, pixels = sequence.corners
    out, start = [], 0
    for k in range(1, len(times) + 1):
        if k == len(times) or times[k] != times[start]:
            out.append((times[start], ids[start:k], pixels[start:k]))
            start = k
    return out


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    config = dualgraph.load_run_config(sys.argv[2]) if len(sys.argv) == 3 else dualgraph.RunConfig()
    sequence = dualgraph.load_sequence(sys.argv[1], config)
    if not sequence.has_corners:
        print("stream_sequence.py: this example feeds corner detections (corners.csv)", file=sys.stderr)
        return 2
    pipeline = dualgraph.StreamingLocalizer(sequence, config)
    times, _ = sequence.odometry
    poses = sequence.odometry_matrices  # (n, 4, 4) exactly as read (a quaternion round trip would move the last digit)
    covariances = sequence.odometry_absolute_covariances  # as the VIO publishes them, or None
    images = instants(sequence)
    refused, next_image, next_print = 0, 0, times[0]
    for k, t in enumerate(times):
        while next_image < len(images) and images[next_image][0] <= t + LEAD:  # the detector's callback
            try:
                pipeline.add_corners(*images[next_image])
            except dualgraph.Error:  # e.g. before the first odometry sample: counted, and said at the end
                refused += 1
            next_image += 1
        # The detector has processed its images up to t + LEAD: those without gates say so (an empty call), so a
        # keyframe need not wait localizer.detection_latency for detections still to come.
        if next_image == len(images) or images[next_image][0] > t + LEAD:
            pipeline.add_corners(t + LEAD, np.zeros(0, dtype=int), np.zeros((0, 4, 2)))
        covariance = None if covariances is None else covariances[k]
        pose = pipeline.add_odometry(t, poses[k], absolute_covariance=covariance)  # the VIO's callback
        if t >= next_print:
            x, y, z = pose["world_T_body"][:3]
            print(f"t={t - times[0]:6.2f} s  {pose['state']:<12} world_T_body ({x:7.3f}, {y:7.3f}, {z:6.3f}) m")
            next_print = t + 1.0
    for image in images[next_image:]:
        try:
            pipeline.add_corners(*image)
        except dualgraph.Error:
            refused += 1
    streamed = pipeline.finish()
    replayed = dualgraph.run_sequence(sequence, config)
    (t_a, p_a), (t_b, p_b) = streamed.estimate, replayed.estimate
    same = len(t_a) == len(t_b) and np.array_equal(t_a, t_b) and np.array_equal(p_a, p_b)
    largest = float(np.abs(p_a - p_b).max()) if len(t_a) == len(t_b) else float("inf")
    print(f"streamed {len(t_a)} poses, run_sequence {len(t_b)}: {'identical' if same else 'DIFFERENT'} "
          f"(largest difference {largest:.3g}); {refused} detection instants refused")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
