# SPDX-License-Identifier: MIT
"""dualgraph.evaluate_trajectory and read_trajectory give the figures `dualgraph eval` prints, on the same files."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import dualgraph
from common import CLI, SOURCE_DIR, run_cli

ALIGNMENTS = ("se3", "4dof", "none", "sim3", "origin")  # those the library lacks must fail in both


def quaternion_xyzw(yaw, pitch, roll):
    cy, sy, cp, sp, cr, sr = (f(a / 2) for a in (yaw, pitch, roll) for f in (np.cos, np.sin))
    return np.array([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
                     cr * cp * cy + sr * sp * sy])


def trajectories(seed=7):
    """Ground truth on a 3-D figure-of-eight at 100 Hz; the estimate at 30 Hz on another clock phase, in a frame
    rotated and shifted from world, with seeded noise and a slow drift. Rows [t x y z qx qy qz qw]."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 20.0, 0.01)
    gt = np.zeros((len(t), 8))
    gt[:, 0] = t
    gt[:, 1:4] = np.c_[6 * np.sin(0.4 * t), 3 * np.sin(0.8 * t), 1.5 + 0.3 * np.sin(0.3 * t)]
    for k, tk in enumerate(t):
        gt[k, 4:] = quaternion_xyzw(0.4 * tk, 0.05 * np.sin(tk), 0.05 * np.cos(tk))
    est_t = np.arange(0.503, 19.2, 1 / 30)
    world_T_est = dualgraph.pose_to_matrix(np.r_[[2.0, -1.0, 0.3], quaternion_xyzw(0.7, 0.02, -0.01)])
    est = np.zeros((len(est_t), 8))
    est[:, 0] = est_t
    for k, tk in enumerate(est_t):
        j = int(np.searchsorted(t, tk))
        pose = dualgraph.pose_to_matrix(gt[j, 1:])  # the next GT sample: a small time error as well
        pose[:3, 3] += rng.normal(0, 0.03, 3) + [0.004 * tk, 0, 0]
        est[k, 1:] = dualgraph.matrix_to_pose(np.linalg.inv(world_T_est) @ pose)
    return gt, est


def write_tum(path, rows):
    np.savetxt(path, rows, fmt="%.17g", header="t x y z qx qy qz qw")


class AgainstTheCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.gt, cls.est = trajectories()
        cls.gt_path, cls.est_path = (os.path.join(cls.tmp.name, n) for n in ("gt.tum", "est.tum"))
        write_tum(cls.gt_path, cls.gt)
        write_tum(cls.est_path, cls.est)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def cli(self, align, *extra):
        out = os.path.join(self.tmp.name, f"eval_{align}.json")
        done = subprocess.run([CLI, "eval", "--gt", self.gt_path, "--est", self.est_path, "--align", align, "--json", out,
                               *extra], capture_output=True, text=True)
        if done.returncode != 0:
            return None, done.stderr
        with open(out) as f:
            return json.load(f), done.stdout

    def assert_same_figures(self, metrics, cli, rtol):
        def same(a, b):  # measured: identical, or 1 ulp apart (the module's own copies of inlined Eigen code)
            self.assertAlmostEqual(a, b, delta=rtol * max(abs(b), 1e-3))
        for key in ("rmse", "mean", "median", "std", "min", "max"):
            same(metrics.stats[key], cli[f"ate_{key}_m"])
        same(metrics.ate_m, cli["ate_rmse_m"])
        same(metrics.ate_rot_deg, cli["ate_rot_deg"])
        for rpe in metrics.rpe:
            key = "rpe_%gm" % rpe["distance_m"]
            same(rpe["translation_rmse_m"], cli[key + "_m"])
            same(rpe["rotation_rmse_deg"], cli[key + "_deg"])
            self.assertEqual(rpe["pairs"], cli[key + "_pairs"])
        for key in ("estimate_poses", "associated", "before_span", "after_span", "beyond_gap"):
            self.assertEqual(getattr(metrics, key), cli[key], key)

    @unittest.skipUnless(CLI and os.path.exists(CLI), "needs the dualgraph tool (DUALGRAPH_CLI)")
    def test_every_alignment_equals_dualgraph_eval(self):
        known = 0
        for align in ALIGNMENTS:
            with self.subTest(align=align):
                cli, output = self.cli(align)
                if cli is None:  # an alignment the library does not have: the same refusal from Python
                    self.assertIn(align, output)
                    with self.assertRaisesRegex(dualgraph.InvalidArgumentError, align):
                        dualgraph.evaluate_trajectory(self.gt_path, self.est_path, align=align)
                    continue
                known += 1
                metrics = dualgraph.evaluate_trajectory(self.gt_path, self.est_path, align=align)
                self.assertEqual(metrics.alignment, cli["alignment"])
                self.assert_same_figures(metrics, cli, rtol=1e-14)  # the same files read the same way
                from_arrays = dualgraph.evaluate_trajectory(self.gt, self.est, align=align)
                self.assert_same_figures(from_arrays, cli, rtol=1e-9)  # quaternions round-tripped through text
        self.assertGreaterEqual(known, 3)

    @unittest.skipUnless(CLI and os.path.exists(CLI), "needs the dualgraph tool (DUALGRAPH_CLI)")
    def test_nearest_stamp_association_equals_max_dt(self):
        cli, output = self.cli("se3", "--max-dt", "0.004")
        self.assertIsNotNone(cli, output)
        metrics = dualgraph.evaluate_trajectory(self.gt_path, self.est_path, max_dt_s=0.004)
        self.assert_same_figures(metrics, cli, rtol=1e-14)
        interpolated = dualgraph.evaluate_trajectory(self.gt_path, self.est_path)
        self.assertNotEqual(metrics.ate_m, interpolated.ate_m)  # another association, really used

    @unittest.skipUnless(CLI and os.path.exists(CLI), "needs the dualgraph tool (DUALGRAPH_CLI)")
    def test_evo_association_and_rpe_windows_equal_dualgraph_eval(self):
        cli, output = self.cli("se3", "--association", "evo", "--max-dt", "0.006", "--rpe-frames", "1,5",
                               "--rpe-pairs", "evo")
        self.assertIsNotNone(cli, output)
        metrics = dualgraph.evaluate_trajectory(self.gt_path, self.est_path, association="evo", max_dt_s=0.006,
                                                rpe_frames=[1, 5], rpe_pairing="evo")
        self.assert_same_figures(metrics, cli, rtol=1e-14)
        self.assertEqual(metrics.paired_from_poses, cli["paired_from_poses"])
        self.assertFalse(metrics.paired_from_ground_truth)  # the estimate (30 Hz) is the sparser one
        self.assertEqual([r["frames"] for r in metrics.rpe_frames], [1, 5])
        for windows, unit in ((metrics.rpe, "m"), (metrics.rpe_frames, "f")):
            for rpe in windows:
                key = "rpe_%g%s" % (rpe["distance_m"] if unit == "m" else rpe["frames"], unit)
                self.assertEqual(rpe["pairing"], "evo")
                self.assertEqual(rpe["pairs"], cli[key + "_pairs"])
                for stat in ("rmse", "mean", "median", "std", "min", "max"):
                    self.assertAlmostEqual(rpe["translation_m"][stat], cli[f"{key}_{stat}_m"], delta=1e-14)
                    self.assertAlmostEqual(rpe["rotation_deg"][stat], cli[f"{key}_{stat}_deg"], delta=1e-12)
        # evo's default max-diff when none is given, and bad names refused.
        default = dualgraph.evaluate_trajectory(self.gt_path, self.est_path, association="evo")
        self.assertGreaterEqual(default.associated, metrics.associated)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "association"):
            dualgraph.evaluate_trajectory(self.gt_path, self.est_path, association="closest")
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "pairing"):
            dualgraph.evaluate_trajectory(self.gt_path, self.est_path, rpe_pairing="all")
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "max_dt_s"):
            dualgraph.evaluate_trajectory(self.gt_path, self.est_path, association="interpolated", max_dt_s=0.01)

    @unittest.skipUnless(CLI and os.path.exists(CLI), "needs the dualgraph tool (DUALGRAPH_CLI)")
    def test_the_figures_are_those_of_the_problem(self):
        cli, _ = self.cli("se3")
        metrics = dualgraph.evaluate_trajectory(self.gt_path, self.est_path)
        self.assertGreater(metrics.associated, 500)
        self.assertLess(metrics.ate_m, 0.1)  # 0.03 m noise per axis, a small drift: SE(3) aligned
        self.assertGreater(dualgraph.evaluate_trajectory(self.gt_path, self.est_path, align="none").ate_m, 1.0)
        np.testing.assert_allclose(metrics.world_T_estimate[:3, 3], [2.0, -1.0, 0.3], atol=0.1)  # the frame, found
        self.assertEqual(metrics.world_T_estimate.shape, (4, 4))
        self.assertEqual([r["distance_m"] for r in metrics.rpe], [1.0, 10.0])
        self.assertIn("ate_m=", repr(metrics))


class Inputs(unittest.TestCase):
    def test_read_trajectory_and_the_input_forms_agree(self):
        gt, est = trajectories()
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "est.tum")
            write_tum(path, est)
            read = dualgraph.read_trajectory(path)
            euroc = os.path.join(tmp, "gt.csv")  # EuRoC CSV: t [ns], position, quaternion w first
            with open(euroc, "w") as f:
                f.write("#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n")
                for row in gt:
                    f.write("%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n" % (round(row[0] * 1e9), *row[1:4], row[7], *row[4:7]))
            from_euroc = dualgraph.evaluate_trajectory(euroc, path, rpe_distances_m=[2.0])
        self.assertEqual(read.shape, est.shape)
        signs = np.sign(est[:, 7])[:, None]  # read back with w >= 0
        np.testing.assert_allclose(read[:, :4], est[:, :4], atol=1e-15)
        np.testing.assert_allclose(read[:, 4:], est[:, 4:] * signs, atol=1e-15)
        as_array = dualgraph.evaluate_trajectory(gt, est, rpe_distances_m=[2.0])
        as_tuple = dualgraph.evaluate_trajectory((gt[:, 0], gt[:, 1:]), (est[:, 0], est[:, 1:]), rpe_distances_m=(2.0,))
        matrices = np.stack([dualgraph.pose_to_matrix(p) for p in est[:, 1:]])
        as_matrices = dualgraph.evaluate_trajectory(gt, (est[:, 0], matrices), rpe_distances_m=[2.0])
        for other in (as_tuple, as_matrices, from_euroc):
            self.assertEqual(other.associated, as_array.associated)
            self.assertAlmostEqual(other.ate_m, as_array.ate_m, delta=1e-9)
            self.assertAlmostEqual(other.rpe[0]["translation_rmse_m"], as_array.rpe[0]["translation_rmse_m"], delta=1e-9)

    def test_bad_inputs_raise(self):
        gt, est = trajectories()
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"gt: expected shape \(n, 8\)"):
            dualgraph.evaluate_trajectory(gt[:, :7], est)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "align"):
            dualgraph.evaluate_trajectory(gt, est, align="se4")
        late = est.copy()
        late[:, 0] += 1000.0
        with self.assertRaises(dualgraph.FailedPreconditionError):
            dualgraph.evaluate_trajectory(gt, late)
        with self.assertRaises(dualgraph.NotFoundError if hasattr(dualgraph, "NotFoundError") else dualgraph.Error):
            dualgraph.read_trajectory("/nonexistent/traj.tum")
        # As `dualgraph eval --min-associated 0.5`: an estimate that mostly lies outside the ground truth is refused,
        # not summarised from the sliver that overlaps; 0 accepts it.
        n = len(est)
        mostly_after = est.copy()
        mostly_after[:, 0] += (gt[-1, 0] - gt[0, 0]) * 0.8
        overlap = dualgraph.evaluate_trajectory(gt, mostly_after, min_associated=0.0, rpe_distances_m=[])
        self.assertLess(overlap.associated, n // 2)
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "below min_associated"):
            dualgraph.evaluate_trajectory(gt, mostly_after, rpe_distances_m=[])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "min_associated"):
            dualgraph.evaluate_trajectory(gt, est, min_associated=1.5)


class DetectionFixFloor(unittest.TestCase):
    """bench/detection_fix_floor.py: fixes from the detections themselves, through the library's PnP."""

    def floors(self, pixel_sigma):
        folder = tempfile.mkdtemp(prefix="dualgraph_fix_floor_")
        run_cli("simulate", "--profile", "clean", "--pixel-sigma", str(pixel_sigma), "--track",
                os.path.join(SOURCE_DIR, "data", "tracks", "ratm_ellipse.yaml"), "--seed", "1", "--laps", "1",
                "--no-plot", "--out", folder)
        bench = os.path.join(SOURCE_DIR, "bench")
        done = subprocess.run([sys.executable, os.path.join(bench, "detection_fix_floor.py"), folder, "--json"],
                              capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        perfect = subprocess.run([sys.executable, os.path.join(bench, "gate_coverage_bound.py"), folder, "--json"],
                                 capture_output=True, text=True)
        self.assertEqual(perfect.returncode, 0, perfect.stderr)
        return json.loads(done.stdout), json.loads(perfect.stdout)

    def test_exact_corners_give_the_perfect_fixes_and_noisy_ones_worse(self):
        exact, perfect = self.floors(0.01)
        self.assertLess(exact["fix_error_median_m"], 0.01)
        self.assertLess(exact["fix_error_given_attitude_median_m"], 0.01)
        self.assertLess(abs(exact["detection_floor_ate_m"] - perfect["floor_ate_m"]), 0.01)
        self.assertAlmostEqual(exact["vio_ate_m"], perfect["vio_ate_m"], places=9)
        noisy, _ = self.floors(4.0)
        self.assertGreater(noisy["fix_error_median_m"], 20 * exact["fix_error_median_m"])
        self.assertGreater(noisy["detection_floor_ate_m"], exact["detection_floor_ate_m"])
        # the attitude is what a single far detection measures worst: its position alone is far better
        self.assertLess(noisy["fix_error_given_attitude_median_m"], noisy["fix_error_median_m"])


if __name__ == "__main__":
    unittest.main()
