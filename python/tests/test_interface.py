# SPDX-License-Identifier: MIT
"""The module's face: typed signatures (no `handle`), documented properties with units, __repr__, the .pyi stub."""
import ast
import inspect
import os
import re
import unittest

import numpy as np

import dualgraph

STUB = os.path.join(os.path.dirname(dualgraph.__file__), "dualgraph.pyi")
EXTRA_DUNDERS = ("__init__", "__repr__")


def bound_classes():
    return [c for c in vars(dualgraph).values() if inspect.isclass(c) and not issubclass(c, BaseException)]


def members(cls):
    """Public names a class defines, and its __init__ (when a constructor is bound) / __repr__."""
    names = {n for n in vars(cls) if not n.startswith("_") or n in EXTRA_DUNDERS}
    if "__init__" in names and not (vars(cls)["__init__"].__doc__ or "").startswith("__init__("):
        names.remove("__init__")  # pybind11's placeholder for a class without a constructor
    return names


def docstrings():
    """(where, text) of every docstring: module, functions, classes, methods, property getters and setters."""
    yield "dualgraph", dualgraph.__doc__
    for name, obj in vars(dualgraph).items():
        if name.startswith("__"):
            continue
        yield name, getattr(obj, "__doc__", None)
        if inspect.isclass(obj) and not issubclass(obj, BaseException):
            for member_name, member in vars(obj).items():
                if member_name not in members(obj):
                    continue
                if isinstance(member, property):
                    for accessor in (member, member.fget, member.fset):
                        yield f"{name}.{member_name}", getattr(accessor, "__doc__", None)
                elif isinstance(member, staticmethod):
                    yield f"{name}.{member_name}", member.__func__.__doc__
                elif callable(member):
                    yield f"{name}.{member_name}", member.__doc__


class Signatures(unittest.TestCase):
    def test_no_parameter_is_typed_handle(self):
        bad = [where for where, doc in docstrings() if doc and re.search(r"\bhandle\b", doc)]
        self.assertEqual(bad, [])
        self.assertIn("poses: numpy.typing.ArrayLike", dualgraph.Graph.add_se3_vertices.__doc__)
        self.assertIn("ids: typing.Union[int, numpy.typing.ArrayLike]", dualgraph.Graph.set_fixed.__doc__)

    def test_every_function_and_method_says_what_it_does(self):
        undocumented = []
        for where, doc in docstrings():
            lines = [l for l in (doc or "").splitlines() if l.strip()]
            if where.endswith(".__repr__"):
                continue  # its output is the documentation
            if not lines or all(re.match(r"^(\d+\. )?\w*\(.*\)( -> .*)?$", l.strip()) for l in lines):
                undocumented.append(where)  # nothing beyond pybind11's signature line
        # A property's setter repeats its getter's doc; pybind11 gives it the signature only.
        undocumented = [w for w in undocumented if not any(w == f"{c.__name__}.{p}" for c in bound_classes()
                                                           for p, m in vars(c).items() if isinstance(m, property))]
        self.assertEqual(undocumented, [])


class Units(unittest.TestCase):
    def test_every_property_has_a_doc(self):
        missing = [f"{c.__name__}.{n}" for c in bound_classes() for n, m in vars(c).items()
                   if isinstance(m, property) and not (m.__doc__ or "").strip()]
        self.assertEqual(missing, [])

    def test_every_number_says_its_unit(self):
        graph = dualgraph.Graph()
        graph.add_point_vertices([0], [[0, 0, 0]])
        graph.add_point_priors([0], [[1, 2, 3]], np.eye(3))
        objects = [dualgraph.LocalizerParams(), dualgraph.RunConfig(), graph.optimize(),
                   dualgraph.GateObservation.pose(1.5, 2, [1, 0, 0, 0, 0, 0, 1], np.eye(6))]
        checked = 0
        for obj in objects:
            for name, member in vars(type(obj)).items():
                if isinstance(member, property) and isinstance(getattr(obj, name), (int, float)) \
                        and not isinstance(getattr(obj, name), bool) and not name.endswith("_id"):  # ids: no unit
                    checked += 1
                    self.assertRegex(member.__doc__ or "", r"\[[^\]]+\]", f"{type(obj).__name__}.{name}: no [unit]")
        self.assertGreater(checked, 35)  # measured: 38
        self.assertIn("[m]", vars(dualgraph.LocalizerParams)["d_main"].__doc__)
        self.assertIn("[rad/sqrt(m)]", vars(dualgraph.LocalizerParams)["odom_sigma_r"].__doc__)
        self.assertIn("[s]", vars(dualgraph.LocalizerParams)["detection_latency"].__doc__)


class Reprs(unittest.TestCase):
    def test_every_class_has_its_own_repr(self):
        self.assertEqual([c.__name__ for c in bound_classes() if "__repr__" not in vars(c)], [])

    def test_reprs_show_the_key_fields(self):
        params = dualgraph.LocalizerParams()
        params.d_main = 3.5
        params.mode = "single"
        self.assertRegex(repr(params), r"^LocalizerParams\(mode='single', .*d_main=3\.5")
        graph = dualgraph.Graph()
        graph.add_se2_vertices([0, 1], np.zeros((2, 3)))
        graph.set_fixed(0)
        self.assertEqual(repr(graph), "Graph(vertices=2, edges=0, fixed=1, custom_edges=0)")
        graph.add_se2_edges([[0, 1]], [[1, 0, 0]], np.eye(3))
        self.assertRegex(repr(graph.optimize()), r"OptimizeSummary\(termination=converged, iterations=\d+, initial_chi2=1, final_chi2=")
        observation = dualgraph.GateObservation.position(2.25, 4, [1.0, 2.0, 3.0], np.eye(3))
        self.assertEqual(repr(observation), "GateObservation(t=2.25, gate_id=4, kind=position, p_body=[1, 2, 3])")
        config = dualgraph.RunConfig()
        self.assertRegex(repr(config), r"^RunConfig\(initialization='auto', .*localizer=LocalizerParams\(mode='dual'")
        localizer = dualgraph.Localizer(params, {0: [5, 0, 1, 0, 0, 0, 1]})
        self.assertRegex(repr(localizer), r"^Localizer\(mode='single', tracking_state='\w+', .*odometry_accepted=0")
        for obj in (params, graph, config, localizer, observation):
            self.assertNotIn(" object at 0x", repr(obj))


class Stub(unittest.TestCase):
    """dualgraph.pyi (generated at build time by python/make_stub.py, installed beside the module) names exactly
    what the module has: every function, class, method and property, and nothing else."""

    @classmethod
    def setUpClass(cls):
        with open(STUB) as f:
            cls.tree = ast.parse(f.read(), STUB)

    def test_module_level_names(self):
        in_stub = set()
        for node in self.tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                in_stub.add(node.name)
            elif isinstance(node, ast.AnnAssign):
                in_stub.add(node.target.id)
        in_module = {n for n in dir(dualgraph) if not n.startswith("_")} | {"__version__"}
        self.assertEqual(in_stub, in_module)

    def test_class_members_and_bases(self):
        classes = {node.name: node for node in self.tree.body if isinstance(node, ast.ClassDef)}
        for cls in (c for c in vars(dualgraph).values() if inspect.isclass(c)):
            node = classes[cls.__name__]
            if issubclass(cls, BaseException):
                self.assertEqual([ast.unparse(b) for b in node.bases], [b.__name__ for b in cls.__bases__])
                continue
            in_stub = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
            self.assertEqual(in_stub, members(cls), cls.__name__)
            for n in node.body:  # properties are properties, setters exactly where the module has them
                if isinstance(n, ast.FunctionDef):
                    decorators = {ast.unparse(d) for d in n.decorator_list}
                    member = vars(cls)[n.name]
                    if "property" in decorators:
                        self.assertIsInstance(member, property)
                    if f"{n.name}.setter" in decorators:
                        self.assertIsNotNone(member.fset, f"{cls.__name__}.{n.name}")

    def test_parameters_match_the_module(self):
        functions = {node.name: node for node in self.tree.body if isinstance(node, ast.FunctionDef)}
        node = functions["evaluate_trajectory"]
        self.assertEqual([a.arg for a in node.args.args], ["gt", "est", "align", "max_gap_s", "rpe_distances_m", "max_dt_s", "min_associated", "association", "rpe_frames", "rpe_pairing"])
        graph = next(n for n in self.tree.body if isinstance(n, ast.ClassDef) and n.name == "Graph")
        custom = next(n for n in graph.body if isinstance(n, ast.FunctionDef) and n.name == "add_custom_edge")
        self.assertEqual([a.arg for a in custom.args.args],
                         ["self", "vertex_ids", "dimension", "information", "residual", "jacobians", "as_matrix"])
        self.assertIn("Callable", ast.unparse(custom.args.args[4].annotation))


if __name__ == "__main__":
    unittest.main()
