# SPDX-License-Identifier: MIT
"""Paths the tests get from ctest (python/CMakeLists.txt), and small helpers."""
import os
import subprocess
import unittest

import numpy as np

CLI = os.environ.get("DUALGRAPH_CLI", "")
SHARED_DIR = os.environ.get("DUALGRAPH_SHARED_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared"))
SOURCE_DIR = os.environ.get("DUALGRAPH_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
# CI, which has ../shared, sets DUALGRAPH_REQUIRE_SHARED=1: a test that needs it then fails instead of skipping.
REQUIRE_SHARED = os.environ.get("DUALGRAPH_REQUIRE_SHARED", "") not in ("", "0")


def needs_shared(path):
    """Skips a test, naming the file, when `path` (in ../shared, which a user's clone has not) is missing; with
    DUALGRAPH_REQUIRE_SHARED set the test runs (and fails on the missing file)."""
    return unittest.skipUnless(REQUIRE_SHARED or os.path.exists(path),
                               f"needs {path} (../shared: tests and CI only, not in a user's clone)")


def run_cli(*args):
    """Runs the `dualgraph` tool; returns its stdout, raises with stderr when it fails."""
    if not CLI or not os.path.exists(CLI):
        raise RuntimeError("DUALGRAPH_CLI is not set to the dualgraph executable (run the tests through ctest)")
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"dualgraph {' '.join(args)} exited {done.returncode}: {done.stderr}")
    return done.stdout


def read_tum(path):
    """(times (n,), poses (n, 7) [x y z qx qy qz qw])."""
    rows = np.loadtxt(path, ndmin=2)
    return rows[:, 0], rows[:, 1:8]


def pose_matrices(poses):
    """(n, 7) -> (n, 4, 4) via the library's conversion."""
    import dualgraph
    return np.stack([dualgraph.pose_to_matrix(p) for p in poses])
