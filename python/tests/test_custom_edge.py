# SPDX-License-Identifier: MIT
"""Graph.add_custom_edge: built-in edges rewritten in Python give the built-in results; callback errors re-raise."""
import os
import tempfile
import traceback
import unittest

import numpy as np

import dualgraph

TIGHT = dict(relative_decrease_stop=1e-15, max_iterations=200)  # to the optimum, not to a tolerance


def wrap(angle):
    return np.arctan2(np.sin(angle), np.cos(angle))


def se2_compose(a, b):
    c, s = np.cos(a[2]), np.sin(a[2])
    return np.array([a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], wrap(a[2] + b[2])])


def se2_inverse(a):
    c, s = np.cos(a[2]), np.sin(a[2])
    return np.array([-(c * a[0] + s * a[1]), -(-s * a[0] + c * a[1]), -a[2]])


def se2_residual(z):
    """EDGE_SE2's error (types/edge_se2.cpp): z^-1 * (x_i^-1 * x_j) as [x y theta]."""
    return lambda est: se2_compose(se2_inverse(z), se2_compose(se2_inverse(est[0]), est[1]))


def se2_jacobians(z):
    """Its Jacobians in VertexSE2's chart ([x y theta] += delta)."""
    def jacobians(est):
        xi, xj = est
        zr_world = rotation2(z[2]).T @ rotation2(xi[2]).T
        d = xj[:2] - xi[:2]
        ji, jj = np.zeros((3, 3)), np.zeros((3, 3))
        ji[:2, :2], ji[:2, 2], ji[2, 2] = -zr_world, -zr_world @ [-d[1], d[0]], -1.0
        jj[:2, :2], jj[2, 2] = zr_world, 1.0
        return [ji, jj]
    return jacobians


def rotation2(theta):
    return np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def se2_ring(seed=0, n=8):
    """An SE(2) ring: noisy odometry and one loop closure, dead-reckoned initial guess."""
    rng = np.random.default_rng(seed)
    step = np.array([1.0, 0.0, 2 * np.pi / n])
    odometry = step + rng.normal(0, [0.05, 0.05, 0.02], (n, 3))
    guess = [np.zeros(3)]
    for k in range(n - 1):
        guess.append(se2_compose(guess[-1], odometry[k]) + rng.normal(0, [0.1, 0.1, 0.05]))
    pairs = [(k, (k + 1) % n) for k in range(n)]
    info = np.diag([100.0, 100.0, 400.0])
    return np.array(guess), pairs, odometry, info


def ring_graph(custom, analytic=True, seed=0):
    guess, pairs, odometry, info = se2_ring(seed)
    graph = dualgraph.Graph()
    graph.add_se2_vertices(np.arange(len(guess)), guess)
    graph.set_fixed(0)
    if not custom:
        graph.add_se2_edges(pairs, odometry, info)
    for (i, j), z in zip(pairs, odometry) if custom else ():
        graph.add_custom_edge([i, j], 3, info, se2_residual(z), se2_jacobians(z) if analytic else None)
    return graph


class SameAsBuiltIn(unittest.TestCase):
    def test_se2_ring_equals_edge_se2(self):
        builtin, custom = ring_graph(False), ring_graph(True)
        self.assertAlmostEqual(custom.chi2(), builtin.chi2(), delta=1e-12 * builtin.chi2())
        expected, got = builtin.optimize(**TIGHT), custom.optimize(**TIGHT)
        self.assertGreater(expected.initial_chi2, 100 * expected.final_chi2)  # a real problem, really solved
        self.assertAlmostEqual(got.final_chi2, expected.final_chi2, delta=1e-9 * expected.final_chi2)
        np.testing.assert_allclose(custom.se2_estimates(), builtin.se2_estimates(), rtol=0, atol=1e-9)
        np.testing.assert_allclose(custom.marginals([3, 5]), builtin.marginals([3, 5]), rtol=1e-7, atol=1e-12)

    def test_numeric_jacobians_equal_analytic_ones(self):
        analytic, numeric = ring_graph(True, True, seed=1), ring_graph(True, False, seed=1)
        a, b = analytic.optimize(**TIGHT), numeric.optimize(**TIGHT)
        self.assertAlmostEqual(b.final_chi2, a.final_chi2, delta=1e-9 * a.final_chi2)
        np.testing.assert_allclose(numeric.se2_estimates(), analytic.se2_estimates(), rtol=0, atol=1e-9)
        for solver, algorithm in (("eigen", "lm"), ("cholmod", "gn")):
            graph = ring_graph(True, False, seed=1)
            summary = graph.optimize(linear_solver=solver, algorithm=algorithm, **TIGHT)
            self.assertAlmostEqual(summary.final_chi2, a.final_chi2, delta=1e-9 * a.final_chi2)

    def test_se3_point_edges_in_the_documented_chart(self):
        """EDGE_SE3_TRACKXYZ in Python with the Jacobians the docstring's se3 chart implies (body-frame
        [dt; dq], dq ~ dtheta / 2): same optimum as the built-in edge, with as_matrix poses."""
        rng = np.random.default_rng(4)
        points = rng.uniform(-3, 3, (5, 3)) + [0, 0, 5]
        poses = np.array([[0, 0, 0, 0, 0, 0, 1.0], [1.0, 0.2, 0.1, 0.05, -0.02, 0.1, 1.0]])
        poses[:, 3:] /= np.linalg.norm(poses[:, 3:], axis=1, keepdims=True)
        matrices = [dualgraph.pose_to_matrix(p) for p in poses]
        pairs, measured = [], []
        for i, m in enumerate(matrices):
            for k, p in enumerate(points):
                pairs.append((i, 10 + k))
                measured.append(m[:3, :3].T @ (p - m[:3, 3]) + rng.normal(0, 0.02, 3))
        graphs = []
        for custom in (False, True):
            graph = dualgraph.Graph()
            graph.add_se3_vertices([0, 1], poses + [[0, 0, 0, 0, 0, 0, 0], [0.1, -0.1, 0.05, 0, 0, 0, 0]])
            graph.add_point_vertices(np.arange(10, 15), points + rng.normal(0, 0.1, points.shape) * 0)
            graph.set_fixed(0)
            info = np.eye(3) * 2500.0
            if not custom:
                graph.add_se3_point_edges(pairs, np.array(measured), info)
            for (i, j), z in zip(pairs, measured) if custom else ():
                def residual(est, z=z):
                    pose, p = est
                    return pose[:3, :3].T @ (p - pose[:3, 3]) - z

                def jacobians(est):
                    pose, p = est
                    p_body = pose[:3, :3].T @ (p - pose[:3, 3])
                    return [np.hstack([-np.eye(3), 2 * skew(p_body)]), pose[:3, :3].T]
                graph.add_custom_edge([i, j], 3, info, residual, jacobians, as_matrix=True)
            graphs.append(graph)
        builtin, custom = graphs
        self.assertAlmostEqual(custom.chi2(), builtin.chi2(), delta=1e-12 * builtin.chi2())
        expected, got = builtin.optimize(**TIGHT), custom.optimize(**TIGHT)
        self.assertEqual(got.iterations, expected.iterations)  # the same steps: the same Jacobians
        self.assertAlmostEqual(got.final_chi2, expected.final_chi2, delta=1e-9 * expected.final_chi2)
        np.testing.assert_allclose(custom.se3_estimates(), builtin.se3_estimates(), rtol=0, atol=1e-9)
        np.testing.assert_allclose(custom.point_estimates(), builtin.point_estimates(), rtol=0, atol=1e-9)

    def test_a_scalar_prior_mixed_with_built_in_edges(self):
        """A 1-D custom edge (a prior on a point's height) beside built-in point priors: the weighted mean."""
        graph = dualgraph.Graph()
        graph.add_point_vertices([0], [[0.0, 0.0, 0.0]])
        graph.add_point_priors([0], [[1.0, 2.0, 3.0]], np.eye(3))
        graph.add_custom_edge([0], 1, [[3.0]], lambda est: [est[0][2] - 7.0])
        graph.optimize()
        np.testing.assert_allclose(graph.point_estimates()[0], [1.0, 2.0, (3.0 + 3 * 7.0) / 4], atol=1e-9)
        np.testing.assert_allclose(graph.marginal(0), np.diag([1.0, 1.0, 0.25]), atol=1e-9)


class CallbackErrors(unittest.TestCase):
    def failing_ring(self, where, after):
        """The ring plus one edge whose `where` callback raises at its `after`-th call."""
        graph = ring_graph(True)
        calls = {"residual": 0, "jacobians": 0}
        guess, pairs, odometry, info = se2_ring()

        def residual(est):
            calls["residual"] += 1
            if where == "residual" and calls["residual"] == after:
                raise ValueError("boom from the residual")
            return se2_residual(odometry[0])(est)

        def jacobians(est):
            calls["jacobians"] += 1
            if where == "jacobians" and calls["jacobians"] == after:
                raise KeyError("boom from the jacobians")
            return se2_jacobians(odometry[0])(est)
        graph.add_custom_edge([0, 1], 3, info, residual, jacobians)
        return graph, calls

    def test_an_exception_in_the_residual_is_re_raised_by_optimize(self):
        graph, calls = self.failing_ring("residual", after=3)
        try:  # not assertRaises: it drops the traceback
            graph.optimize()
            self.fail("optimize did not raise")
        except ValueError as error:
            self.assertEqual(str(error), "boom from the residual")
            frames = traceback.extract_tb(error.__traceback__)
        self.assertEqual(frames[-1].name, "residual")  # the original exception, its traceback kept
        self.assertEqual(calls["residual"], 3)  # no callback after the failure
        self.assertTrue(np.isfinite(graph.se2_estimates()).all())  # left at the last accepted state
        self.assertTrue(graph.optimize(**TIGHT).usable)  # the failure was cleared: the Graph goes on
        self.assertGreater(calls["residual"], 3)

    def test_an_exception_in_the_jacobians_and_in_chi2(self):
        graph, calls = self.failing_ring("jacobians", after=2)
        with self.assertRaisesRegex(KeyError, "boom from the jacobians"):
            graph.optimize()
        graph, calls = self.failing_ring("residual", after=1)
        with self.assertRaisesRegex(ValueError, "boom"):
            graph.chi2()
        self.assertGreater(graph.chi2(), 0.0)
        graph, calls = self.failing_ring("residual", after=1)
        with self.assertRaisesRegex(ValueError, "boom"):
            graph.marginal(3)

    def test_bad_values_name_the_edge(self):
        cases = [
            (lambda est: np.zeros(2), None, r"custom edge 0 \(vertices 0 1\): residual has shape \(2,\), expected \(3,\)"),
            (lambda est: [0.0, np.nan, 0.0], None, r"custom edge 0 \(vertices 0 1\): residual\[1\] is not finite \(nan\)"),
            (lambda est: "abc", None, r"custom edge 0 \(vertices 0 1\): residual: expected an array of real numbers"),
            (lambda est: np.zeros(3), lambda est: [np.eye(3)], r"custom edge 0 \(vertices 0 1\): jacobians must return a list of 2"),
            (lambda est: np.zeros(3), lambda est: [np.eye(3), np.ones((3, 2))],
             r"custom edge 0 \(vertices 0 1\): jacobians\[1\] has shape \(3, 2\), expected \(3, 3\)"),
            (lambda est: np.zeros(3), lambda est: [np.eye(3), np.full((3, 3), np.inf)],
             r"custom edge 0 \(vertices 0 1\): jacobians\[1\]\[0, 0\] is not finite \(inf\)"),
        ]
        for residual, jacobians, message in cases:
            graph = dualgraph.Graph()
            graph.add_se2_vertices([0, 1], np.zeros((2, 3)))
            graph.add_custom_edge([0, 1], 3, np.eye(3), residual, jacobians)
            with self.assertRaisesRegex(dualgraph.InvalidArgumentError, message):
                graph.optimize()

    def test_add_custom_edge_checks_its_arguments(self):
        graph = dualgraph.Graph()
        graph.add_se2_vertices([0, 1], np.zeros((2, 3)))
        ok = lambda est: np.zeros(3)  # noqa: E731
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "residual must be callable"):
            graph.add_custom_edge([0, 1], 3, None, 5)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "jacobians must be callable or None"):
            graph.add_custom_edge([0, 1], 3, None, ok, "no")
        with self.assertRaisesRegex(dualgraph.NotFoundError, "vertex_ids: vertex 9 not found"):
            graph.add_custom_edge([0, 9], 3, None, ok)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "vertex 1 appears twice"):
            graph.add_custom_edge([1, 1], 3, None, ok)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "information is not symmetric positive definite"):
            graph.add_custom_edge([0, 1], 3, -np.eye(3), ok)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"information: expected shape \(3, 3\)"):
            graph.add_custom_edge([0, 1], 3, np.eye(2), ok)
        self.assertEqual(graph.num_edges, 0)
        self.assertEqual(graph.add_custom_edge([0, 1], 3, None, ok), 0)
        self.assertEqual(graph.add_custom_edge([1], 3, None, ok), 1)

    def test_save_refuses_a_graph_with_custom_edges(self):
        graph = ring_graph(True)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "ring.g2o")
            with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "8 Python-defined edge"):
                graph.save(path)
            self.assertFalse(os.path.exists(path))
        self.assertIn("custom_edges=8", repr(graph))


if __name__ == "__main__":
    unittest.main()
