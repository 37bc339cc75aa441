#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plays a sequence folder as a live record stream for `dualgraph live` (frontend/io/FORMATS.md, "Live stream").

    python3 examples/live_feed.py SEQUENCE [--speed 1.0] | dualgraph live --map SEQUENCE/gates.yaml \
        --camera SEQUENCE/camera.yaml --out RUN

Odometry records (vio.tum rows) go out in time order, paced by their stamps (--speed 1: real time, 4: four times
faster, 0: as fast as the pipe takes them); each detection record (a corners.csv or detections.csv row) goes out
just before the first odometry record it precedes by less than --lead seconds, as a detector's output arrives
ahead of the VIO's, followed by a `done` record (the detector has processed its images up to there). Every line is
flushed at once.
"""
import argparse
import os
import sys
import time


def rows(path, skip_header):
    """The data rows of a TUM/CSV file as lists of text fields (comments, blank lines and a header skipped)."""
    out = []
    with open(path, encoding="utf-8-sig") as f:
        for line in f:
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            fields = text.split(",") if "," in text else text.split()
            if skip_header and not out and fields[0].strip() == "t":
                continue
            out.append([field.strip() for field in fields])
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sequence", help="sequence folder (vio.tum, corners.csv or detections.csv)")
    parser.add_argument("--speed", type=float, default=1.0, help="playback speed (1 real time, 0 no pacing)")
    parser.add_argument("--lead", type=float, default=0.25, help="how far ahead of the odometry a detection goes [s]")
    args = parser.parse_args()
    if args.speed < 0 or args.lead < 0:
        parser.error("--speed and --lead must be >= 0")
    odometry = rows(os.path.join(args.sequence, "vio.tum"), False)
    corners = os.path.join(args.sequence, "corners.csv")
    tag, path = ("corners", corners) if os.path.exists(corners) else ("pose", os.path.join(args.sequence, "detections.csv"))
    detections = rows(path, True)
    out = sys.stdout
    start_wall = time.monotonic()
    t0 = float(odometry[0][0]) if odometry else 0.0
    k = 0
    for sample in odometry:
        t = float(sample[0])
        while k < len(detections) and float(detections[k][0]) <= t + args.lead:
            out.write(tag + " " + " ".join(detections[k]) + "\n")
            k += 1
        # The detector is done up to there: the images without a row held no gate (keyframes need not wait for it).
        out.write(f"done {t + args.lead!r}\n")
        if args.speed > 0:
            delay = start_wall + (t - t0) / args.speed - time.monotonic()
            if delay > 0:
                time.sleep(delay)
        out.write("odom " + " ".join(sample) + "\n")
        out.flush()
    for row in detections[k:]:
        out.write(tag + " " + " ".join(row) + "\n")
    out.write("end\n")
    out.flush()


if __name__ == "__main__":
    try:
        main()
    except BrokenPipeError:  # the consumer stopped reading
        sys.exit(1)
