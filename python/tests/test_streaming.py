# SPDX-License-Identifier: MIT
"""dualgraph.StreamingLocalizer: a sequence fed sample by sample gives run_sequence's answer (the example does it), in
numpy out; refused inputs raise naming why; the worker mode and the file constructor work."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import dualgraph
from common import SOURCE_DIR, run_cli

TRACK = os.path.join(SOURCE_DIR, "data", "tracks", "ratm_ellipse.yaml")
EXAMPLE = os.path.join(SOURCE_DIR, "python", "examples", "stream_sequence.py")


class Streaming(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="dualgraph_streaming_")
        cls.sequence_dir = os.path.join(cls.tmp, "sequence")
        # The realistic profile: the VIO in its own frame (the frame search runs), clock and mount errors.
        run_cli("simulate", "--track", TRACK, "--seed", "2", "--laps", "2", "--no-plot", "--out", cls.sequence_dir)
        cls.sequence = dualgraph.load_sequence(cls.sequence_dir)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_the_example_streams_a_flight_to_run_sequences_answer(self):
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
        done = subprocess.run([sys.executable, EXAMPLE, self.sequence_dir], capture_output=True, text=True, env=env,
                              timeout=300)
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        self.assertIn("identical (largest difference 0)", done.stdout)
        self.assertIn("tracking", done.stdout)

    def test_each_sample_gives_numpy_out_and_the_state(self):
        pipeline = dualgraph.StreamingLocalizer(self.sequence, dualgraph.RunConfig())
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        out = pipeline.add_odometry(times[0], poses[0])
        self.assertEqual(out["t"], times[0])
        self.assertEqual(out["world_T_body"].shape, (7,))
        self.assertEqual(out["state"], "initialising")
        self.assertIsNone(out["covariance"])
        snapshot = pipeline.snapshot()
        self.assertEqual(snapshot["samples"], 1)
        self.assertEqual(snapshot["last_gate_update_t"], float("-inf"))  # no gate update yet
        self.assertEqual(snapshot["map_T_odom"].shape, (7,))
        # Refused: a sample not after the previous one, a wrong pixel array, a NaN pose; each names why.
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "not after"):
            pipeline.add_odometry(times[0], poses[0])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"pixels: expected shape \(1, 4, 2\)"):
            pipeline.add_corners(times[1], [1], np.zeros((1, 3, 2)))
        bad = np.array(poses[1])
        bad[0, 3] = np.nan
        with self.assertRaises(dualgraph.InvalidArgumentError):
            pipeline.add_odometry(times[1], bad)
        # Each refused sample counts as taken, those the binding refuses before the pipeline (the NaN) included: a
        # feeder pacing itself on the count never waits for them.
        self.assertEqual(pipeline.snapshot()["samples"], 3)
        result = pipeline.finish()
        self.assertEqual(len(result.estimate[0]), 1)
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "finish"):
            pipeline.add_odometry(times[2], poses[2])

    def test_a_stream_with_corrupted_samples_refuses_each_and_keeps_tracking(self):
        # About 2 % of the odometry corrupted the ways a driver can (non-finite, not rigid, a stamp far ahead or far
        # back, a matrix that is not a covariance): each raises naming why, and the flight is localised as if they
        # were not there. Before the clock guard, the one stamp 10^6 s ahead made every later sample "not after" it.
        rng = np.random.default_rng(5)
        pipeline = dualgraph.StreamingLocalizer(self.sequence, dualgraph.RunConfig())
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        corner_times, corner_ids, corner_pixels = self._corners()
        not_a_covariance = np.eye(6) * 1e-4
        not_a_covariance[0, 5] = 1e-3
        corruptions = [lambda t, P: (np.nan, P, None), lambda t, P: (t + 1e6, P, None), lambda t, P: (t - 1e3, P, None),
                       lambda t, P: (t, P * np.diag([1, 1, 2, 1]), None), lambda t, P: (t, P, not_a_covariance)]
        refused = 0
        next_corner = 0
        for k in range(len(times)):
            while next_corner < len(corner_times) and corner_times[next_corner] <= times[k]:
                pipeline.add_corners(corner_times[next_corner], corner_ids[next_corner], corner_pixels[next_corner])
                next_corner += 1
            if k > 0 and rng.random() < 0.02:
                t, P, covariance = corruptions[rng.integers(len(corruptions))](times[k], poses[k])
                with self.assertRaises(dualgraph.InvalidArgumentError):
                    pipeline.add_odometry(t, P, absolute_covariance=covariance)
                refused += 1
            out = pipeline.add_odometry(times[k], poses[k])
            self.assertTrue(np.all(np.isfinite(out["world_T_body"])))
        self.assertGreater(refused, 10)
        self.assertEqual(pipeline.snapshot()["samples"], len(times) + refused)
        self.assertEqual(pipeline.snapshot()["state"], "tracking")
        snapshot = pipeline.snapshot()
        self.assertLess(snapshot["t"] - snapshot["last_gate_update_t"], 3.0)  # gates in view to the end
        result = pipeline.finish()
        self.assertEqual(len(result.estimate[0]), len(times))
        counted = result.pipeline_counters
        self.assertEqual(counted["odometry_invalid"] + counted["odometry_not_after_previous"] +
                         counted["odometry_held_at_clock_jump"], refused)  # every refusal under one reason
        self.assertEqual(counted["odometry_clock_jumps"], 0)

    def test_a_looped_feed_restarts_the_pipeline(self):
        # A bag played in a loop: part of the flight 500 s later, then the flight from its start. The second pass's
        # first second is held, the sample after it restarts the pipeline (said on that sample), and finish()
        # describes the flight since; in both threading modes.
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        held = next(k for k in range(len(times)) if times[k] - times[0] >= 1.0 - 1e-6)  # 1 s of the clock behind
        for threading in ("caller", "worker"):
            pipeline = dualgraph.StreamingLocalizer(self.sequence, dualgraph.RunConfig(), threading=threading)
            for k in range(300):
                self.assertFalse(pipeline.add_odometry(times[k] + 500.0, poses[k])["clock_restarted"])
            for k in range(held):
                with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "clock restart"):
                    pipeline.add_odometry(times[k], poses[k])
            restarted = [k for k in range(held, len(times))
                         if pipeline.add_odometry(times[k], poses[k])["clock_restarted"]]
            self.assertEqual(restarted, [held], threading)
            result = pipeline.finish()
            self.assertEqual(len(result.estimate[0]), len(times) - held, threading)
            self.assertEqual(result.pipeline_counters["odometry_clock_restarts"], 1, threading)
            self.assertEqual(result.pipeline_counters["odometry_held_at_clock_jump"], held, threading)
            self.assertEqual(pipeline.snapshot()["samples"], 300 + len(times), threading)

    def test_the_time_checks_are_configurable_and_checked(self):
        config = dualgraph.RunConfig()
        self.assertEqual((config.max_detection_lead_s, config.max_odometry_gap_s, config.max_odometry_jump_s),
                         (1.0, 0.5, 10.0))
        config.max_odometry_jump_s = 0.0  # off: a stamp far ahead is taken at once, as before the guard
        pipeline = dualgraph.StreamingLocalizer(self.sequence, config)
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        pipeline.add_odometry(times[0], poses[0])
        pipeline.add_odometry(times[1] + 1e6, poses[1])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "not after"):
            pipeline.add_odometry(times[2], poses[2])
        config.max_odometry_jump_s = -1.0
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "max_odometry_jump_s"):
            dualgraph.StreamingLocalizer(self.sequence, config)

    def test_a_glitched_pose_is_held_and_the_limits_are_checked(self):
        config = dualgraph.RunConfig()
        self.assertEqual((config.max_odometry_speed_mps, config.max_odometry_turn_rate_radps), (50.0, 40.0))
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        glitched = poses[1].copy()
        glitched[0, 3] += 1e6  # one pose 1000 km away: refused, the flight goes on from the one before
        for threading in ("caller", "worker"):
            pipeline = dualgraph.StreamingLocalizer(self.sequence, config, threading=threading)
            pipeline.add_odometry(times[0], poses[0])
            with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "pose jump"):
                pipeline.add_odometry(times[1], glitched)
            pipeline.add_odometry(times[2], poses[2])
            counters = pipeline.finish().pipeline_counters
            self.assertEqual((counters["odometry_held_at_pose_jump"], counters["odometry_pose_jumps"]), (1, 0), threading)
        config.max_odometry_speed_mps = 0.0  # off: taken as motion, as before the guard
        pipeline = dualgraph.StreamingLocalizer(self.sequence, config)
        pipeline.add_odometry(times[0], poses[0])
        pipeline.add_odometry(times[1], glitched)
        config.max_odometry_turn_rate_radps = float("nan")
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "max_odometry_turn_rate_radps"):
            dualgraph.StreamingLocalizer(self.sequence, config)

    def test_the_workers_queue_bound_is_the_callers(self):
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        pipeline = dualgraph.StreamingLocalizer(self.sequence, dualgraph.RunConfig(), threading="worker",
                                                max_queued_inputs=1)
        refused = 0
        for t, pose in zip(times[:400], poses[:400]):
            try:
                pipeline.add_odometry(t, pose)
            except dualgraph.Error as error:
                self.assertIn("inputs behind", str(error))
                refused += 1
        counters = pipeline.finish().pipeline_counters
        self.assertEqual(counters["odometry_queue_full"], refused)  # each refusal counted, however many the race made
        self.assertEqual(pipeline.snapshot()["samples"], 400)
        for bound in (0, -5):
            with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "max_queued_inputs"):
                dualgraph.StreamingLocalizer(self.sequence, dualgraph.RunConfig(), threading="worker",
                                             max_queued_inputs=bound)

    def _corners(self):
        """The sequence's corner detections grouped by image: stamps (camera clock, as add_corners takes them), ids,
        (m, 4, 2) pixels."""
        rows = np.loadtxt(os.path.join(self.sequence_dir, "corners.csv"), delimiter=",", skiprows=1, ndmin=2)
        stamps = np.unique(rows[:, 0])
        return (list(stamps), [rows[rows[:, 0] == t, 1].astype(int) for t in stamps],
                [rows[rows[:, 0] == t, 2:10].reshape(-1, 4, 2) for t in stamps])

    def test_worker_threading_and_the_file_constructor(self):
        pipeline = dualgraph.StreamingLocalizer.from_files(
            os.path.join(self.sequence_dir, "gates.yaml"), os.path.join(self.sequence_dir, "camera.yaml"),
            threading="worker")
        times, _ = self.sequence.odometry
        poses = self.sequence.odometry_matrices
        for k in range(200):
            pipeline.add_odometry(times[k], poses[k])
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "caller"):
            pipeline.time_offset  # the worker thread's
        result = pipeline.finish()
        self.assertEqual(len(result.estimate[0]), 200)
        self.assertEqual(pipeline.snapshot()["samples"], 200)
        with self.assertRaisesRegex(ValueError, "threading: expected 'caller' or 'worker'"):
            dualgraph.StreamingLocalizer(self.sequence, threading="fast")
        with self.assertRaisesRegex(dualgraph.Error, "no_such_gates.yaml"):
            dualgraph.StreamingLocalizer.from_files(os.path.join(self.tmp, "no_such_gates.yaml"))


if __name__ == "__main__":
    unittest.main()
