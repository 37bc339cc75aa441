# SPDX-License-Identifier: MIT
"""dualgraph.Graph: g2o files, batches from numpy, optimisation, marginal covariances."""
import json
import os
import tempfile
import unittest

import numpy as np

import dualgraph
from common import SHARED_DIR, needs_shared, run_cli

PARKING_GARAGE = os.path.join(SHARED_DIR, "data", "posegraph", "parking-garage.g2o")


def se3_chain(n, rng):
    """n poses along x with small seeded rotations, and the exact relative measurements."""
    poses = np.zeros((n, 7))
    for i in range(n):
        axis = rng.normal(size=3)
        angle = 0.1 * rng.normal()
        poses[i, :3] = [i, 0.1 * rng.normal(), 0.0]
        poses[i, 3:6] = np.sin(angle / 2) * axis / np.linalg.norm(axis)
        poses[i, 6] = np.cos(angle / 2)
    matrices = np.stack([dualgraph.pose_to_matrix(p) for p in poses])
    relative = np.stack([np.linalg.inv(matrices[i]) @ matrices[i + 1] for i in range(n - 1)])
    return poses, relative


class ParkingGarage(unittest.TestCase):
    @needs_shared(PARKING_GARAGE)
    def test_chi2_equals_the_cli(self):
        cli = json.loads(run_cli("optimize", PARKING_GARAGE, "--json"))
        graph = dualgraph.Graph.load(PARKING_GARAGE)
        self.assertEqual(graph.num_vertices, cli["vertices"])
        self.assertEqual(graph.num_edges, cli["edges"])
        self.assertEqual(dualgraph.Graph.load(PARKING_GARAGE).fix_gauge(), cli["gauge_vertex"])  # same default
        self.assertEqual(graph.fix_gauge("highest"), cli["gauge_vertex"])  # the CLI's default gauge
        start = graph.chi2()
        summary = graph.optimize(init="auto")  # the CLI's default start; Graph.optimize's own default is "none"
        self.assertEqual(cli["init"], "chordal")
        self.assertEqual(summary.iterations, cli["iterations"])
        self.assertEqual(summary.termination, cli["termination"])
        self.assertAlmostEqual(start, cli["initial_chi2"], delta=1e-12 * cli["initial_chi2"])  # the file's
        self.assertAlmostEqual(summary.initial_chi2, cli["init_chi2"], delta=1e-12 * cli["init_chi2"])  # chordal
        self.assertAlmostEqual(summary.final_chi2, cli["final_chi2"], delta=1e-12 * cli["final_chi2"])
        self.assertAlmostEqual(graph.chi2(), summary.final_chi2, delta=1e-9 * summary.final_chi2)
        self.assertLess(summary.final_chi2, 1.3)  # README: 1.238684 after LM

    @needs_shared(PARKING_GARAGE)
    def test_each_damping_from_the_files_start_equals_the_cli(self):
        for damping in ("identity", "diagonal"):
            cli = json.loads(run_cli("optimize", PARKING_GARAGE, "--json", "--damping", damping, "--init", "none"))
            graph = dualgraph.Graph.load(PARKING_GARAGE)
            graph.fix_gauge("highest")
            summary = graph.optimize(damping=damping) if damping == "identity" else graph.optimize()  # the default
            self.assertEqual(summary.iterations, cli["iterations"])
            self.assertAlmostEqual(summary.initial_chi2, cli["initial_chi2"], delta=1e-12 * cli["initial_chi2"])
            self.assertAlmostEqual(summary.final_chi2, cli["final_chi2"], delta=1e-12 * cli["final_chi2"])
            self.assertLess(summary.final_chi2, 1.3)  # the same optimum with either damping
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "damping must be 'identity' or 'diagonal'"):
            graph.optimize(damping="marquardt")
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "unknown initialisation 'spectral'"):
            graph.optimize(init="spectral")

    @needs_shared(PARKING_GARAGE)
    def test_marginals_of_the_optimum(self):
        graph = dualgraph.Graph.load(PARKING_GARAGE)
        gauge = graph.fix_gauge("lowest")
        graph.optimize()
        ids = graph.vertex_ids("se3")
        far = int(ids[-1])
        sigma = graph.marginal(far)
        self.assertEqual(sigma.shape, (6, 6))
        np.testing.assert_allclose(sigma, sigma.T, atol=1e-15)
        self.assertGreater(np.linalg.eigvalsh(sigma).min(), 0.0)
        joint = graph.marginals([gauge, far])
        np.testing.assert_array_equal(joint[:6, :], 0.0)  # the fixed vertex is known exactly
        np.testing.assert_allclose(joint[6:, 6:], sigma, rtol=1e-9, atol=1e-18)
        metric = graph.marginal(far, metric=True)
        np.testing.assert_allclose(metric, dualgraph.covariance_g2o_to_metric(sigma), rtol=1e-12)

    @needs_shared(PARKING_GARAGE)
    def test_marginal_blocks_of_every_pose_equal_the_per_vertex_marginals(self):
        graph = dualgraph.Graph.load(PARKING_GARAGE)
        gauge = graph.fix_gauge("highest")
        graph.optimize()
        ids = graph.vertex_ids("se3")
        blocks = graph.marginal_blocks(ids)
        self.assertEqual(blocks.shape, (len(ids), 6, 6))
        np.testing.assert_array_equal(blocks[list(ids).index(gauge)], 0.0)  # the gauge is known exactly
        for k in [0, 1, 500, 1200, len(ids) - 2]:  # the per-vertex solve path, one vertex at a time
            sigma = graph.marginal(int(ids[k]))
            np.testing.assert_allclose(blocks[k], sigma, rtol=1e-9, atol=1e-9 * np.abs(sigma).max())
        metric = graph.marginal_blocks(ids[:3], metric=True)
        np.testing.assert_allclose(metric[1], dualgraph.covariance_g2o_to_metric(blocks[1]), rtol=1e-12)


class BuiltFromNumpy(unittest.TestCase):
    def test_se3_chain_round_trips_through_a_g2o_file(self):
        rng = np.random.default_rng(1)
        poses, relative = se3_chain(6, rng)
        graph = dualgraph.Graph()
        noisy = poses.copy()
        noisy[1:, :3] += rng.normal(0, 0.05, (5, 3))  # vertex 0 stays at the truth: it is the gauge
        graph.add_se3_vertices(np.arange(6), noisy)
        graph.add_se3_edges(np.c_[np.arange(5), np.arange(1, 6)], relative, np.eye(6) * 100.0)
        graph.set_fixed(0)
        self.assertEqual((graph.num_vertices, graph.num_edges), (6, 5))
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "chain.g2o")
            graph.save(path)
            loaded = dualgraph.Graph.load(path)
        self.assertAlmostEqual(loaded.chi2(), graph.chi2(), delta=1e-12 * graph.chi2())  # 17 digits in the file
        np.testing.assert_array_equal(loaded.fixed_ids(), [0])
        np.testing.assert_allclose(loaded.se3_estimates(), graph.se3_estimates(), atol=1e-15)
        summary = loaded.optimize()
        self.assertTrue(summary.usable)
        self.assertLess(summary.final_chi2, 1e-12)  # exact measurements: zero residual at the truth
        truth = np.stack([dualgraph.pose_to_matrix(p) for p in poses])
        estimate = np.stack([dualgraph.pose_to_matrix(p) for p in loaded.se3_estimates()])
        np.testing.assert_allclose(estimate, truth, atol=1e-8)

    def test_se3_marginal_of_one_edge_is_its_inverse_information(self):
        # At zero residual H = J^T Omega J with J = I for the free end: Sigma = Omega^-1 (g2o units).
        a = np.random.default_rng(2).normal(size=(6, 6))
        omega = a @ a.T + 6 * np.eye(6)
        relative = dualgraph.pose_to_matrix([1.0, 2.0, 0.5, 0.1, -0.2, 0.3, 0.9])
        graph = dualgraph.Graph()
        graph.add_se3_vertices([0, 1], np.stack([np.eye(4), relative]))
        graph.add_se3_edges([[0, 1]], relative[None], omega)
        graph.set_fixed([0])
        np.testing.assert_allclose(graph.marginal(1), np.linalg.inv(omega), rtol=1e-9, atol=1e-14)
        d = np.diag([1, 1, 1, 2, 2, 2.0])
        np.testing.assert_allclose(graph.marginal(1, metric=True), d @ np.linalg.inv(omega) @ d, rtol=1e-9, atol=1e-14)

    def test_point_priors_add_their_information(self):
        graph = dualgraph.Graph()
        graph.add_point_vertices([7], [[1.0, 2.0, 3.0]])
        info = np.stack([np.diag([1.0, 4.0, 9.0]), np.array([[2.0, 0.5, 0], [0.5, 1.0, 0], [0, 0, 1.0]])])
        graph.add_point_priors([7, 7], [[1.0, 2.0, 3.0], [1.5, 2.0, 3.0]], info)
        graph.optimize()
        np.testing.assert_allclose(graph.marginal(7), np.linalg.inv(info[0] + info[1]), rtol=1e-12)
        expected = np.linalg.solve(info[0] + info[1], info[0] @ [1, 2, 3.0] + info[1] @ [1.5, 2, 3.0])
        np.testing.assert_allclose(graph.point_estimates([7])[0], expected, atol=1e-12)

    def test_chordal_init_recovers_a_square_and_refuses_points(self):
        truth = np.array([[0, 0, 0], [1, 0, np.pi / 2], [1, 1, np.pi], [0, 1, -np.pi / 2]], float)
        graph = dualgraph.Graph()
        graph.add_se2_vertices(np.arange(4), truth + [[0, 0, 0], [0.5, -0.5, 2.0], [-1, 2, -2.5], [3, 0, 1.0]])
        graph.add_se2_edges([[0, 1], [1, 2], [2, 3], [3, 0]], np.array([[1, 0, np.pi / 2]] * 4),
                            np.diag([100.0, 100.0, 400.0]))
        graph.set_fixed(0)
        summary = graph.optimize(init="chordal", max_iterations=0)  # the initialiser alone
        self.assertLess(summary.initial_chi2, 1e-16)  # after the initialisation
        np.testing.assert_allclose(graph.se2_estimates(), truth, atol=1e-9)
        graph.add_point_vertices([9], [[0.0, 0.0, 0.0]])
        graph.add_point_priors([9], [[1.0, 2.0, 3.0]], np.eye(3))
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "vertex 9 is neither"):
            graph.optimize(init="chordal")
        self.assertTrue(graph.optimize(init="auto").usable)  # auto: the graph's own start

    def test_marginal_blocks_need_one_dimension_and_an_anchored_gauge(self):
        graph = dualgraph.Graph()
        graph.add_se3_vertices([0, 1], [[0, 0, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 0, 1]])
        graph.add_point_vertices([2], [[1.0, 2.0, 3.0]])
        graph.add_se3_edges([[0, 1]], [[1, 0, 0, 0, 0, 0, 1]], np.eye(6))
        graph.add_se3_point_edges([[1, 2]], [[0.0, 2.0, 3.0]], np.eye(3))
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "gauge is free.*fix a vertex"):
            graph.marginal_blocks([0, 1])  # nothing fixed, no prior
        graph.set_fixed(0)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "dimensions differ \\(vertex 1: 6, vertex 2: 3\\)"):
            graph.marginal_blocks([1, 2])
        poses = graph.marginal_blocks([1, 0, 1])
        self.assertEqual(poses.shape, (3, 6, 6))
        np.testing.assert_array_equal(poses[1], 0.0)
        np.testing.assert_allclose(poses[0], graph.marginal(1), rtol=1e-9, atol=1e-12)
        np.testing.assert_array_equal(poses[0], poses[2])
        point = graph.marginal_blocks([2])
        self.assertEqual(point.shape, (1, 3, 3))
        np.testing.assert_allclose(point[0], graph.marginal(2), rtol=1e-9, atol=1e-12)
        self.assertEqual(graph.marginal_blocks([]).shape, (0, 0, 0))
        with self.assertRaises(dualgraph.NotFoundError):
            graph.marginal_blocks([1, 9])

    def test_se2_square_with_a_loop_closure(self):
        rng = np.random.default_rng(3)
        truth = np.array([[0, 0, 0], [1, 0, np.pi / 2], [1, 1, np.pi], [0, 1, -np.pi / 2]], float)
        steps = np.array([[1, 0, np.pi / 2]] * 4)
        graph = dualgraph.Graph()
        graph.add_se2_vertices(np.arange(4), truth + rng.normal(0, 0.1, (4, 3)))
        graph.add_se2_edges([[0, 1], [1, 2], [2, 3], [3, 0]], steps, np.diag([100.0, 100.0, 400.0]))
        graph.set_fixed(0)
        graph.set_se2_estimates([0], truth[:1])
        summary = graph.optimize()
        self.assertEqual(summary.termination, "converged")
        self.assertLess(summary.final_chi2, 1e-16)
        np.testing.assert_allclose(graph.se2_estimates(), truth, atol=1e-7)

    def test_sensor_offsets_and_landmarks_survive_save_and_load(self):
        graph = dualgraph.Graph()
        graph.add_sensor_offset(3, [0.1, 0, 0.2, 0, 0, 0, 1])
        graph.add_se3_vertices([0], [[0, 0, 0, 0, 0, 0, 1]], fixed=True)
        graph.add_point_vertices([1], [[2.0, 0.1, 0.0]])
        graph.add_se3_point_edges([[0, 1]], [[1.9, 0.0, -0.2]], np.eye(3), offset_id=3)
        graph.add_se3_priors([0], [[0, 0, 0, 0, 0, 0, 1]], np.eye(6))  # default offset: id 0, identity
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "landmark.g2o")
            graph.save(path)
            loaded = dualgraph.Graph.load(path)
        self.assertAlmostEqual(loaded.chi2(), graph.chi2(), delta=1e-15)
        loaded.optimize()
        np.testing.assert_allclose(loaded.point_estimates([1])[0], [2.0, 0.0, 0.0], atol=1e-9)

    def test_poses_as_vectors_or_matrices_are_the_same(self):
        pose = np.array([1.0, -2.0, 3.0, 0.2, 0.1, -0.3, 0.9])
        graph = dualgraph.Graph()
        graph.add_se3_vertices([0, 1], np.stack([pose, pose]))
        graph.set_se3_estimates([1], dualgraph.pose_to_matrix(pose)[None])
        a, b = graph.se3_estimates()
        np.testing.assert_allclose(a, b, atol=1e-15)
        np.testing.assert_allclose(a[3:], pose[3:] / np.linalg.norm(pose[3:]), atol=1e-15)
        self.assertEqual(graph.vertex_kind(0), "se3")
        np.testing.assert_array_equal(graph.vertex_ids("se2"), np.zeros(0))


if __name__ == "__main__":
    unittest.main()
