# SPDX-License-Identifier: MIT
"""Bad input from Python raises a dualgraph.Error subclass with the library's message, never a crash."""
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

import numpy as np

import dualgraph


def chain():
    graph = dualgraph.Graph()
    graph.add_se3_vertices([0, 1], [[0, 0, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 0, 1]])
    graph.add_se3_edges([[0, 1]], [[1, 0, 0, 0, 0, 0, 1]], np.eye(6))
    return graph


class Shapes(unittest.TestCase):
    def test_wrong_pose_shape_names_the_argument_and_both_shapes(self):
        graph = dualgraph.Graph()
        with self.assertRaises(dualgraph.InvalidArgumentError) as raised:
            graph.add_se3_vertices([0, 1], np.zeros((2, 6)))
        self.assertIn("poses: expected shape (2, 7)", str(raised.exception))
        self.assertIn("got (2, 6)", str(raised.exception))
        self.assertEqual(raised.exception.code, "InvalidArgument")
        self.assertIsInstance(raised.exception, ValueError)
        self.assertEqual(graph.num_vertices, 0)

    def test_information_and_pairs_shapes(self):
        graph = chain()
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"information: expected shape \(6, 6\) or \(1, 6, 6\)"):
            graph.add_se3_edges([[0, 1]], [[1, 0, 0, 0, 0, 0, 1]], np.eye(3))
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"pairs: expected shape \(m, 2\)"):
            graph.add_se3_edges([0, 1], [[1, 0, 0, 0, 0, 0, 1]], np.eye(6))
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"measurements: expected shape"):
            graph.add_se2_edges([[0, 1]], [[1, 0]], np.eye(3))
        self.assertEqual(graph.num_edges, 1)

    def test_wrong_dtypes(self):
        graph = dualgraph.Graph()
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "expected integer ids, got dtype float64"):
            graph.add_point_vertices([0.5], [[0, 0, 0]])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "points: expected an array of real numbers"):
            graph.add_point_vertices([0], [["a", "b", "c"]])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "points: expected an array of real numbers"):
            graph.add_point_vertices([0], [[1 + 2j, 0, 0]])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"ids\[0\] = -3 is not a valid id"):
            graph.add_point_vertices([-3], [[0, 0, 0]])
        with self.assertRaises(dualgraph.InvalidArgumentError):
            graph.add_point_vertices([0], [[0, 0], [0, 0, 0]])  # ragged


class Values(unittest.TestCase):
    def test_nan_names_the_entry(self):
        graph = dualgraph.Graph()
        poses = np.tile([0, 0, 0, 0, 0, 0, 1.0], (3, 1))
        poses[1, 3] = np.nan
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"poses\[1, 3\] is not finite \(nan\)"):
            graph.add_se3_vertices([0, 1, 2], poses)
        self.assertEqual(graph.num_vertices, 0)  # all or nothing
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"information\[2, 2\] is not finite \(inf\)"):
            info = np.eye(6)
            info[2, 2] = np.inf
            chain().add_se3_edges([[1, 0]], [[1, 0, 0, 0, 0, 0, 1]], info)

    def test_zero_quaternion_and_non_rigid_matrix(self):
        graph = dualgraph.Graph()
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "quaternion .* has zero norm"):
            graph.add_se3_vertices([0], [[1, 2, 3, 0, 0, 0, 0]])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "rotation that is not orthonormal"):
            graph.add_se3_vertices([0], np.diag([2.0, 2.0, 2.0, 1.0])[None])
        bad = np.eye(4)
        bad[3, 0] = 1
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "last row of a 4x4 pose must be 0 0 0 1"):
            dualgraph.pose_to_matrix(bad)

    def test_information_must_be_positive_definite(self):
        graph = chain()
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"information\[0\] is not symmetric positive definite"):
            graph.add_se3_edges([[1, 0]], [[1, 0, 0, 0, 0, 0, 1]], -np.eye(6))


class Ids(unittest.TestCase):
    def test_unknown_ids(self):
        graph = chain()
        with self.assertRaisesRegex(dualgraph.NotFoundError, "vertex 99 not found") as raised:
            graph.se3_estimates([99])
        self.assertIsInstance(raised.exception, LookupError)
        with self.assertRaisesRegex(dualgraph.NotFoundError, "edge 1: vertex 42 not found"):
            graph.add_se3_edges([[0, 1], [0, 42]], np.tile([1, 0, 0, 0, 0, 0, 1.0], (2, 1)), np.eye(6))
        self.assertEqual(graph.num_edges, 1)
        with self.assertRaisesRegex(dualgraph.NotFoundError, "vertex 5 not found"):
            graph.set_fixed([0, 5])
        self.assertEqual(list(graph.fixed_ids()), [])
        with self.assertRaisesRegex(dualgraph.NotFoundError, "PARAMS_SE3OFFSET with id 4"):
            graph.add_se3_priors([0], [[0, 0, 0, 0, 0, 0, 1]], np.eye(6), offset_id=4)

    def test_duplicates_wrong_kinds_and_self_loops(self):
        graph = chain()
        with self.assertRaisesRegex(dualgraph.AlreadyExistsError, "vertex 1 exists already"):
            graph.add_point_vertices([5, 1], np.zeros((2, 3)))
        with self.assertRaisesRegex(dualgraph.AlreadyExistsError, "vertex 6 appears twice"):
            graph.add_point_vertices([6, 6], np.zeros((2, 3)))
        self.assertEqual(graph.num_vertices, 2)
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "vertex 0 is a VERTEX_SE3:QUAT, not a 'se2' vertex"):
            graph.se2_estimates([0])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "wrong type for edge slot 0"):
            graph.add_se2_edges([[0, 1]], [[1, 0, 0]], np.eye(3))
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "both ends are vertex 1"):
            graph.add_se3_edges([[1, 1]], [[0, 0, 0, 0, 0, 0, 1]], np.eye(6))
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "kind must be"):
            graph.vertex_ids("se4")


class Solving(unittest.TestCase):
    def test_no_gauge(self):
        graph = chain()  # nothing fixed: H is singular (Gauss-Newton has no damping to hide it)
        graph.set_se3_estimates([1], [[1.5, 0, 0, 0, 0, 0, 1]])
        with self.assertRaises(dualgraph.OptimizationError) as raised:
            graph.optimize(algorithm="gn")
        self.assertEqual(raised.exception.code, "not_positive_definite")
        self.assertIn("not_positive_definite", str(raised.exception))
        summary = graph.optimize(algorithm="gn", check=False)
        self.assertEqual(summary.termination, "not_positive_definite")
        self.assertFalse(summary.usable)
        with self.assertRaisesRegex(dualgraph.FailedPreconditionError, "gauge is free"):
            graph.marginal(1)  # nothing fixed, no prior: the gauge is free (MarginalCovariance::compute)
        graph.fix_gauge()
        self.assertEqual(graph.marginal(1).shape, (6, 6))
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "unknown linear solver|linear solver"):
            graph.optimize(linear_solver="umfpack")
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "algorithm must be 'lm' or 'gn'"):
            graph.optimize(algorithm="dogleg")

    def test_files(self):
        with tempfile.TemporaryDirectory() as tmp:
            missing = os.path.join(tmp, "missing.g2o")
            with self.assertRaises(dualgraph.Error) as raised:
                dualgraph.Graph.load(missing)
            self.assertIn(missing, str(raised.exception))
            bad = os.path.join(tmp, "bad.g2o")
            with open(bad, "w") as out:
                out.write("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 0 0 nan 0 0 0 1\n")
            with self.assertRaisesRegex(dualgraph.ParseError, "bad.g2o:2: "):
                dualgraph.Graph.load(bad)
            with self.assertRaises(dualgraph.Error):
                dualgraph.load_sequence(tmp)


class LocalizerInput(unittest.TestCase):
    def make(self):
        return dualgraph.Localizer(dualgraph.LocalizerParams(), {0: [5, 0, 1, 0, 0, 0, 1]})

    def test_bad_samples_are_rejected_with_the_library_message(self):
        localizer = self.make()
        localizer.add_odometry(0.0, [0, 0, 0, 0, 0, 0, 1])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "odometry sample: time stamp is not finite"):
            localizer.add_odometry(float("nan"), [0, 0, 0, 0, 0, 0, 1])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"odom_T_body\[0, 1\] is not finite"):
            localizer.add_odometry(0.1, np.array([[0, np.nan, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]))
        with self.assertRaises(dualgraph.Error) as raised:
            localizer.add_odometry(-1.0, [0, 0, 0, 0, 0, 0, 1])
        self.assertTrue(str(raised.exception))
        with self.assertRaisesRegex(dualgraph.NotPositiveDefiniteError, "relative_covariance is not positive definite"):
            localizer.add_odometry(0.2, [0.1, 0, 0, 0, 0, 0, 1], covariance=-np.eye(6))
        with self.assertRaises(dualgraph.Error):
            localizer.add_pose_observation(0.1, 9, [1, 0, 0, 0, 0, 0, 1], np.eye(6) * 0.01)  # gate 9 is not in the map
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"covariance: expected shape \(6, 6\)"):
            localizer.add_pose_observation(0.1, 0, [1, 0, 0, 0, 0, 0, 1], np.eye(3))
        counters = localizer.counters()
        self.assertEqual(counters["odometry_accepted"], 1)
        self.assertGreaterEqual(counters["odometry_rejected"], 2)
        localizer.add_odometry(0.3, [0.2, 0, 0, 0, 0, 0, 1])  # still running

    def test_bad_parameters_and_maps(self):
        params = dualgraph.LocalizerParams()
        params.d_main = -1.0
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "d_main"):
            dualgraph.Localizer(params, {0: [0, 0, 0, 0, 0, 0, 1]})
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "mode must be one of 'dual', 'single'"):
            dualgraph.LocalizerParams().mode = "triple"
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "lm_damping must be one of 'identity', 'diagonal'"):
            dualgraph.LocalizerParams().lm_damping = "marquardt"
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "temp_solver must be one of 'block', 'graph'"):
            dualgraph.LocalizerParams().temp_solver = "cholmod"
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, "gates: expected a dict"):
            dualgraph.Localizer(dualgraph.LocalizerParams(), [[0, 0, 0, 0, 0, 0, 1]])
        with self.assertRaisesRegex(dualgraph.InvalidArgumentError, r"gates\[0\]: expected shape"):
            dualgraph.Localizer(dualgraph.LocalizerParams(), {0: [0, 0, 0]})
        with self.assertRaises(dualgraph.InvalidArgumentError):
            dualgraph.Localizer(dualgraph.LocalizerParams(), {})  # localization mode needs a map
        with self.assertRaisesRegex(dualgraph.ParseError, "<string>:1: "):
            dualgraph.parse_localizer_params("localizer: {d_mian: 2.0}")


class NoCrash(unittest.TestCase):
    def test_random_garbage_never_kills_the_interpreter(self):
        # In a child interpreter, so a crash would show as its exit status instead of ending this run.
        script = textwrap.dedent("""
            import numpy as np, dualgraph
            rng = np.random.default_rng(11)
            shapes = [(), (0,), (3,), (7,), (2, 7), (1, 4, 4), (2, 3), (2, 6, 6), (6, 6), (3, 3), (2, 2), (1, 2)]
            def garbage():
                kind = rng.integers(5)
                shape = shapes[rng.integers(len(shapes))]
                if kind == 0: return rng.normal(size=shape)
                if kind == 1: return np.full(shape, np.nan)
                if kind == 2: return rng.integers(-3, 5, size=shape)
                if kind == 3: return "text"
                return None
            graph = dualgraph.Graph()
            graph.add_se3_vertices([0, 1], [[0, 0, 0, 0, 0, 0, 1]] * 2)
            methods = ["add_se3_vertices", "add_se2_vertices", "add_point_vertices", "add_se3_edges", "add_se2_edges",
                       "add_se3_point_edges", "add_se3_priors", "add_point_priors", "set_se3_estimates", "se3_estimates",
                       "marginals", "set_fixed", "add_sensor_offset"]
            errors = 0
            for _ in range(3000):
                name = methods[rng.integers(len(methods))]
                nargs = {"se3_estimates": 1, "marginals": 1, "set_fixed": 1, "add_sensor_offset": 2,
                         "set_se3_estimates": 2}.get(name, 3 if "vertices" in name else 3)
                try:
                    getattr(graph, name)(*[garbage() for _ in range(nargs)])
                except dualgraph.Error:
                    errors += 1
                except TypeError:
                    errors += 1  # pybind11's own message for an argument of the wrong Python type
            loc = dualgraph.Localizer(dualgraph.LocalizerParams(), {0: [5, 0, 1, 0, 0, 0, 1]})
            for k in range(500):
                try:
                    loc.add_odometry(float(rng.normal()), garbage(), garbage() if k % 2 else None)
                except (dualgraph.Error, TypeError):
                    errors += 1
            print(errors)
        """)
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertGreater(int(done.stdout.strip()), 1000)


if __name__ == "__main__":
    unittest.main()
