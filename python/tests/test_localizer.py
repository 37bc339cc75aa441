# SPDX-License-Identifier: MIT
"""The Localizer from Python gives the same estimate as `dualgraph run` on the same sequence."""
import json
import os
import shutil
import tempfile
import unittest

import numpy as np

import dualgraph
from common import SOURCE_DIR, pose_matrices, read_tum, run_cli

CONFIG = os.path.join(SOURCE_DIR, "data", "config", "default.yaml")
TRACK = os.path.join(SOURCE_DIR, "data", "tracks", "ratm_ellipse.yaml")


def localize_in_python(sequence, config):
    """runSequence (frontend/replay/sequence_run.cpp) written out in Python: odometry in time order; before each sample
    (after the first one), every detection up to its time, one instant at a time, through the GateFrontend at
    the corrected pose of that instant and on to the Localizer, which holds them until the sample covers them; the
    Localizer told that every detection up to the sample is in (as the replay's detector says).
    Returns (times, world_T_body (n, 7)) at every sample."""
    localizer = dualgraph.Localizer(config.localizer, sequence.gates)
    frontend = dualgraph.GateFrontend(sequence, config)
    times, _ = sequence.odometry
    matrices = sequence.odometry_matrices
    covariances = sequence.odometry_covariances
    if sequence.has_corners:
        det_times, det_ids, det_pixels = sequence.corners
    else:
        detections = sequence.pose_detections
        det_times = np.array([d.t for d in detections])
    next_detection = int(np.searchsorted(det_times, times[0], side="left"))  # earlier ones are not usable
    estimate = []

    def hand_detections_up_to(t):
        nonlocal next_detection
        while next_detection < len(det_times) and det_times[next_detection] <= t:
            instant = det_times[next_detection]
            end = next_detection
            while end < len(det_times) and det_times[end] == instant:
                end += 1
            world_T_body = localizer.map_T_odom_matrix @ sequence.odometry_pose_at(instant)
            if sequence.has_corners:
                observations = frontend.process_corners(instant, det_ids[next_detection:end],
                                                        det_pixels[next_detection:end], world_T_body)
            else:
                observations = frontend.process_poses(detections[next_detection:end], world_T_body)
            for observation in observations:
                try:
                    localizer.add_observation(observation)
                except dualgraph.Error:
                    pass  # counted by the Localizer, as in `dualgraph run`
            next_detection = end

    for k, t in enumerate(times):
        if k > 0:  # the detections a sample covers go first: the sample may close their keyframe interval
            hand_detections_up_to(t)
        localizer.observations_complete_until(t)  # every detection up to t is in: no keyframe waits for late ones
        estimate.append(localizer.add_odometry(t, matrices[k], covariances[k]))
        if k == 0:
            hand_detections_up_to(t)
    localizer.finish()
    return np.array(times), np.array(estimate), localizer


class SameAsTheCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="dualgraph_python_")
        cls.sequence_dir = os.path.join(cls.tmp, "sequence")
        cls.run_dir = os.path.join(cls.tmp, "run")
        run_cli("simulate", "--profile", "clean", "--track", TRACK, "--seed", "1", "--laps", "1", "--no-plot",
                "--out", cls.sequence_dir)
        # The Localizer driven from Python starts from localizer.initial_world_T_odom as it is: so does the CLI
        # here (`initialization: given`; the automatic initialisation is the run path's, not the Localizer's).
        config_path = os.path.join(cls.tmp, "given.yaml")
        with open(CONFIG, encoding="utf-8") as default, open(config_path, "w", encoding="utf-8") as given:
            given.write(default.read().replace("initialization: auto", "initialization: given"))
        run_cli("run", "--sequence", cls.sequence_dir, "--out", cls.run_dir, "--quiet", "--config", config_path)
        cls.config = dualgraph.load_run_config(config_path)
        cls.sequence = dualgraph.load_sequence(cls.sequence_dir, cls.config)
        cls.cli_times, cls.cli_poses = read_tum(os.path.join(cls.run_dir, "estimate.tum"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def assertSameTrajectory(self, times, poses, cli_times, cli_poses):
        self.assertEqual(len(times), len(cli_times))
        np.testing.assert_array_equal(times, cli_times)  # 17 significant digits in the file: exact
        np.testing.assert_allclose(pose_matrices(poses), pose_matrices(cli_poses), rtol=0, atol=1e-12)

    def test_run_sequence_equals_dualgraph_run(self):
        result = dualgraph.run_sequence(self.sequence, self.config)
        times, poses = result.estimate
        self.assertSameTrajectory(times, poses, self.cli_times, self.cli_poses)
        kf_times, kf_poses = result.keyframes
        cli_kf_times, cli_kf_poses = read_tum(os.path.join(self.run_dir, "keyframes.tum"))
        self.assertSameTrajectory(kf_times, kf_poses, cli_kf_times, cli_kf_poses)
        stats_rows = np.loadtxt(os.path.join(self.run_dir, "stats.csv"), delimiter=",", skiprows=1, usecols=(0, 2, 3),
                                ndmin=2)
        # stats.csv starts with keyframe 0 (not an optimisation), then one row per optimisation.
        self.assertEqual(len(result.stats), len(stats_rows) - 1)
        self.assertEqual([(r["main_vertices"], r["main_edges"]) for r in result.stats],
                         [(int(n), int(e)) for _, n, e in stats_rows[1:]])
        # The corner noise the run used, and where it came from, as metrics.json has them.
        with open(os.path.join(self.run_dir, "metrics.json")) as f:
            metrics = json.load(f)
        counters = result.frontend_counters
        for key in ("pixel_sigma_source", "pixel_sigma_fits", "pixel_sigma_large_gate_fits"):
            self.assertEqual(counters[key], metrics[key], key)
        self.assertAlmostEqual(counters["pixel_sigma_px"], metrics["pixel_sigma_px"], places=12)

    def test_tracking_states_and_the_initialization(self):
        self.assertEqual(self.config.initialization, "given")
        self.assertEqual(set(dualgraph.run_sequence(self.sequence, self.config).states), {"tracking"})
        config = dualgraph.load_run_config(CONFIG)
        self.assertEqual(config.initialization, "auto")
        result = dualgraph.run_sequence(self.sequence, config)
        states = result.states
        self.assertEqual(len(states), len(result.estimate[0]))
        self.assertEqual(states[0], "initialising")  # the frame is found from the first detections
        self.assertEqual(states[-1], "tracking")
        self.assertEqual(result.localizer_counters["losses"], 0)
        with self.assertRaises(ValueError):
            config.initialization = "guess"

    def test_the_lock_and_the_self_calibration_are_dualgraph_runs(self):
        # The default configuration (frame search, corner fit, self-calibration at 8 s): RunResult reports what
        # metrics.json of `dualgraph run` reports, to the digit.
        run_dir = os.path.join(self.tmp, "run_default")
        run_cli("run", "--sequence", self.sequence_dir, "--out", run_dir, "--quiet", "--config", CONFIG)
        with open(os.path.join(run_dir, "metrics.json")) as f:
            metrics = json.load(f)
        config = dualgraph.load_run_config(CONFIG)
        result = dualgraph.run_sequence(dualgraph.load_sequence(self.sequence_dir, config), config)
        lock = result.initialization
        self.assertTrue(lock["locked"])
        self.assertEqual(metrics["initialized"], 1)
        self.assertEqual(lock["at_s"], metrics["initialized_at_s"])
        self.assertEqual(lock["refined_on_corners"], metrics["lock_refined_on_corners"] == 1)
        self.assertTrue(lock["refined_on_corners"])
        self.assertGreaterEqual(lock["gates"], 2)
        self.assertGreater(lock["inliers"], lock["runner_up"])
        self.assertEqual(lock["why_not"], "")
        world_T_odom = lock["world_T_odom"]
        self.assertEqual(world_T_odom.shape, (7,))
        expected = [metrics["lock_world_T_odom_" + key] for key in ("x_m", "y_m", "z_m", "qx", "qy", "qz", "qw")]
        sign = 1.0 if world_T_odom[6] >= 0 else -1.0  # metrics.json writes w >= 0
        np.testing.assert_allclose(np.concatenate([world_T_odom[:3], sign * world_T_odom[3:]]), expected,
                                   rtol=0, atol=1e-12)
        calibration = result.self_calibration
        self.assertTrue(calibration["attempted"])
        self.assertEqual(calibration["applied"], metrics["self_calibration_applied"] == 1)
        for key in ("at_s", "applied_at_s", "time_offset_before_s", "time_offset_s", "time_offset_sigma_s", "mount_change_deg",
                    "first_half_mount_change_deg", "second_half_mount_change_deg", "halves_mount_change_deg",
                    "halves_mount_sigma_deg", "clock_offset_first_at_s", "clock_offset_first_s"):
            self.assertEqual(calibration[key], metrics["self_calibration_" + key], key)
        self.assertGreater(calibration["halves_mount_sigma_deg"], 0.0)  # both halves were calibrated
        for key in ("attempts", "iterations", "why_not", "why_not_time_offset", "why_not_mount", "parts"):
            self.assertEqual(calibration[key], metrics["self_calibration_" + key], key)
        for key in ("time_offset_applied", "mount_applied", "clock_offset_first_applied"):
            self.assertEqual(calibration[key], metrics["self_calibration_" + key] == 1, key)
        given = dualgraph.run_sequence(self.sequence, self.config)
        self.assertIsNone(given.initialization)  # `initialization: given`: no search
        self.assertFalse(given.self_calibration["applied"])  # the clean profile: nothing to correct

    def test_the_vio_scale_is_the_configs_and_reported(self):
        self.assertTrue(dualgraph.RunConfig().estimate_odometry_scale)
        config = dualgraph.load_run_config(CONFIG)
        self.assertTrue(config.estimate_odometry_scale)
        self.assertEqual(config.odometry_scale_min_error, 0.02)
        with self.assertRaisesRegex(ValueError, r"must be in \[0, 0\.5\)"):  # OdometryScaleParams::max_error
            config.odometry_scale_min_error = 0.7
        scale = dualgraph.run_sequence(self.sequence, config).odometry_scale
        self.assertTrue(scale["enabled"])
        self.assertFalse(scale["applied"])  # the bundled flight's VIO has no scale error to take out
        self.assertIsNone(scale["applied_at_s"])
        self.assertEqual(scale["scale"], 1.0)
        self.assertGreater(scale["updates"], 0)
        self.assertLess(abs(scale["estimate"] - 1.0), 0.02)
        config.estimate_odometry_scale = False
        self.assertFalse(dualgraph.run_sequence(self.sequence, config).odometry_scale["enabled"])

    def test_self_calibration_is_the_configs(self):
        # One set of defaults: the struct's, which default.yaml holds (test/frontend/default_config_keys_test.cpp).
        self.assertEqual(dualgraph.RunConfig().self_calibration_after_s, 8.0)
        self.assertEqual(dualgraph.load_run_config(CONFIG).self_calibration_after_s, 8.0)
        self.assertEqual(dualgraph.RunConfig().to_yaml(), dualgraph.load_run_config(CONFIG).to_yaml())
        config = dualgraph.load_run_config(CONFIG)
        config.self_calibration_after_s = 0.0
        self.assertIsNone(dualgraph.run_sequence(self.sequence, config).camera_switched_at)

    def test_localizer_driven_from_python_equals_dualgraph_run(self):
        times, poses, localizer = localize_in_python(self.sequence, self.config)
        self.assertSameTrajectory(times, poses, self.cli_times, self.cli_poses)
        counters = localizer.counters()
        self.assertEqual(counters["odometry_accepted"], len(times))
        self.assertEqual(counters["observations_too_late"], 0)
        self.assertGreater(counters["observations_accepted"], 100)
        stats = localizer.stats()
        self.assertGreater(len(stats), 10)
        self.assertGreater(sum(row["gate_edges_added"] for row in stats), 10)
        # The correction is real: against the ground truth, well below the VIO's error (the last pose 0.068 m, the
        # VIO's 0.127 m, with the default systematic floor on distilled edges).
        gt_times, gt_poses = self.sequence.ground_truth
        _, vio = self.sequence.odometry
        last = int(np.searchsorted(gt_times, times[-1]))
        vio_error = np.linalg.norm(vio[-1, :3] - gt_poses[min(last, len(gt_times) - 1), :3])
        self.assertLess(np.linalg.norm(poses[-1, :3] - gt_poses[min(last, len(gt_times) - 1), :3]), 0.65 * vio_error)


class Synthetic(unittest.TestCase):
    def test_circle_flight_with_yaw_drift(self):
        radius, speed, drift = 10.0, 5.0, 0.02
        omega = speed / radius

        def on_circle(phi):
            pose = np.eye(4)
            pose[:3, 3] = [radius * np.cos(phi), radius * np.sin(phi), 1.5]
            c, s = np.cos(phi + np.pi / 2), np.sin(phi + np.pi / 2)
            pose[:2, :2] = [[c, -s], [s, c]]
            return pose

        def yaw(angle):
            pose = np.eye(4)
            pose[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
            return pose

        gates = {g: on_circle(np.pi / 4 + g * np.pi / 2) for g in range(4)}
        localizer = dualgraph.Localizer(dualgraph.LocalizerParams(), gates)
        covariance = np.diag([0.05 ** 2] * 3 + [0.02 ** 2] * 3)
        duration = 2 * 2 * np.pi / omega
        for k in range(int(duration / 0.02)):
            t = 0.02 * k
            world_T_body = on_circle(omega * t)
            corrected = localizer.add_odometry(t, yaw(drift * t) @ world_T_body, as_matrix=True)
            if k % 5 == 0:
                for gate_id, world_T_gate in gates.items():
                    body_T_gate = np.linalg.inv(world_T_body) @ world_T_gate
                    if 1.0 < body_T_gate[0, 3] < 8.0:
                        localizer.add_pose_observation(t, gate_id, body_T_gate, covariance)
        localizer.finish()
        vio_error = np.linalg.norm((yaw(drift * t) @ world_T_body)[:3, 3] - world_T_body[:3, 3])
        self.assertGreater(vio_error, 1.0)
        self.assertLess(np.linalg.norm(corrected[:3, 3] - world_T_body[:3, 3]), 0.1 * vio_error)
        times, keyframes = localizer.keyframes()
        self.assertEqual(len(times), len(keyframes))
        self.assertEqual(localizer.stats()[-1]["main_vertices"], len(times) + len(gates))
        self.assertEqual(localizer.counters()["observations_rejected"], 0)

    def test_an_observation_stamped_far_ahead_is_refused_and_holds_nothing_back(self):
        gates = {0: np.eye(4)}
        gates[0][:3, 3] = [5.0, 0.0, 1.0]
        localizer = dualgraph.Localizer(dualgraph.LocalizerParams(), gates)
        covariance = np.diag([0.05 ** 2] * 3 + [0.02 ** 2] * 3)
        body_T_gate = gates[0].copy()
        for k in range(50):
            localizer.add_odometry(0.02 * k, np.eye(4), as_matrix=True)
        with self.assertRaises(dualgraph.InvalidArgumentError) as refused:
            localizer.add_pose_observation(1000.0, 0, body_T_gate, covariance)
        self.assertIn("beyond the newest odometry", str(refused.exception))
        for k in range(50):
            localizer.add_pose_observation(0.02 * k, 0, body_T_gate, covariance)  # none "older than the previous"
        counters = localizer.counters()
        self.assertEqual(counters["observations_too_far_ahead"], 1)
        self.assertEqual(counters["observations_rejected"], 1)
        self.assertEqual(counters["observations_accepted"], 50)


if __name__ == "__main__":
    unittest.main()
