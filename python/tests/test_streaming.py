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
        result = pipeline.finish()
        self.assertEqual(len(result.estimate[0]), 1)
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "finish"):
            pipeline.add_odometry(times[2], poses[2])

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
