# SPDX-License-Identifier: MIT
"""python/examples/ runs as documented, so it cannot silently break."""
import os
import subprocess
import sys
import unittest

from common import SHARED_DIR

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")


class Tour(unittest.TestCase):
    def test_tour_runs_and_corrects(self):
        args = [sys.executable, os.path.join(EXAMPLES, "tour.py")]
        garage = os.path.join(SHARED_DIR, "data", "posegraph", "parking-garage.g2o")
        if os.path.exists(garage):
            args.append(garage)
        done = subprocess.run(args, capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("termination=converged", done.stdout)
        self.assertIn("NotFoundError (NotFound): edge 0: vertex 99 not found", done.stdout)
        line = next(l for l in done.stdout.splitlines() if l.startswith("Localizer:"))
        corrected = float(line.split("final error ")[1].split(" m")[0])
        vio = float(line.split("VIO ")[1].split(" m")[0])
        self.assertLess(corrected, 0.1 * vio)
        ring = next(l for l in done.stdout.splitlines() if l.startswith("worst position error"))
        optimised, dead_reckoning = (float(x.split(" m")[0]) for x in ring.split("error ")[1].split("dead reckoning "))
        self.assertLess(optimised, 0.5 * dead_reckoning)  # the loop closure pays


if __name__ == "__main__":
    unittest.main()
