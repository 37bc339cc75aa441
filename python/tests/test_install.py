# SPDX-License-Identifier: MIT
"""`cmake --install BUILD --prefix P --component python` gives an importable module and its stub under P."""
import os
import subprocess
import sys
import sysconfig
import tempfile
import unittest

BUILD_DIR = os.environ.get("DUALGRAPH_BUILD_DIR", "")
CMAKE = os.environ.get("DUALGRAPH_CMAKE_COMMAND", "cmake")
SITE_DIR = os.environ.get("DUALGRAPH_PYTHON_INSTALL_DIR", "")

PROBE = """
import sys, dualgraph, numpy as np
g = dualgraph.Graph()
g.add_point_vertices([0], [[0.0, 0.0, 0.0]])
g.add_custom_edge([0], 3, None, lambda est: est[0] - [1.0, 2.0, 3.0])
g.optimize()
print(dualgraph.__file__)
print(g.point_estimates()[0].tolist())
"""


@unittest.skipUnless(BUILD_DIR and SITE_DIR, "needs DUALGRAPH_BUILD_DIR and DUALGRAPH_PYTHON_INSTALL_DIR (run through ctest)")
class Install(unittest.TestCase):
    def test_the_python_component_installs_into_the_site_packages_layout(self):
        self.assertFalse(os.path.isabs(SITE_DIR))
        default = os.path.relpath(sysconfig.get_path("platlib", "posix_prefix", vars={"base": "/_P", "platbase": "/_P"}), "/_P")
        if os.name == "posix" and not SITE_DIR.endswith("dist-packages"):  # not the documented Debian override
            self.assertEqual(SITE_DIR, default)  # e.g. lib/python3.11/site-packages
        with tempfile.TemporaryDirectory() as prefix:
            done = subprocess.run([CMAKE, "--install", BUILD_DIR, "--prefix", prefix, "--component", "python"],
                                  capture_output=True, text=True)
            self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
            site = os.path.join(prefix, SITE_DIR)
            installed = sorted(os.listdir(site))
            self.assertIn("dualgraph.pyi", installed)
            modules = [n for n in installed if n.startswith("dualgraph.") and n.endswith(".so")]
            self.assertEqual(len(modules), 1, installed)
            self.assertEqual(set(installed), {"dualgraph.pyi", modules[0]})  # the component holds these two only
            # A fresh interpreter that sees the prefix only (no build tree, no source tree on the path).
            env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
            env["PYTHONPATH"] = site
            run = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, cwd=prefix)
            self.assertEqual(run.returncode, 0, run.stderr)
            module_file, estimate = run.stdout.splitlines()
            self.assertTrue(os.path.realpath(module_file).startswith(os.path.realpath(site) + os.sep), module_file)
            self.assertEqual(eval(estimate), [1.0, 2.0, 3.0])  # noqa: S307 - our own probe's list output
            with open(os.path.join(site, "dualgraph.pyi")) as stub, \
                    open(os.path.join(BUILD_DIR, "python", "dualgraph.pyi")) as built:
                self.assertEqual(stub.read(), built.read())


if __name__ == "__main__":
    unittest.main()
