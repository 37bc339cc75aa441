# SPDX-License-Identifier: MIT
"""bench/gate_coverage_bound.py and bench/vio_hybrid.py on flights made here, whose answers are known without them."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

BENCH = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'bench')
SCRIPT = os.path.join(BENCH, 'gate_coverage_bound.py')


def write_tum(path, rows, yaw=0.0):
    """Rows (t, x, y, z) with the attitude a yaw [rad]."""
    with open(path, 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw\n')
        for t, x, y, z in rows:
            f.write(f'{t:.6f} {x:.6f} {y:.6f} {z:.6f} 0 0 {math.sin(yaw / 2):.9f} {math.cos(yaw / 2):.9f}\n')


def flight(folder, drift_per_s, detection_stamps, estimate=None):
    """1 m/s along x for 20 s at 50 Hz from t = 1000 s; the VIO drifts along y and sits 5 m off in its own frame."""
    stamps = [1000.0 + 0.02 * k for k in range(1001)]
    write_tum(os.path.join(folder, 'gt.tum'), [(t, t - 1000.0, 0.0, 1.0) for t in stamps])
    write_tum(os.path.join(folder, 'vio.tum'),
              [(t, t - 1000.0 + 5.0, drift_per_s * (t - 1000.0) ** 2 / 20.0, 1.0) for t in stamps])
    with open(os.path.join(folder, 'corners.csv'), 'w') as f:
        f.write('t,gate_id,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl\n')
        for t in detection_stamps:
            f.write(f'{t:.6f},0,1,1,2,1,2,2,1,2\n')
    if estimate is not None:
        os.makedirs(os.path.join(folder, 'run'))
        write_tum(os.path.join(folder, 'run', 'estimate.tum'), [(t, t - 1000.0, estimate, 1.0) for t in stamps])


def bound(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


class GateCoverageBound(unittest.TestCase):
    def test_a_gate_seen_at_every_sample_leaves_no_error(self):
        with tempfile.TemporaryDirectory() as folder:
            flight(folder, 0.05, [1000.0 + 0.02 * k for k in range(1001)], estimate=0.0)
            result = bound(folder, os.path.join(folder, 'run'), '--markdown', 'every')
            self.assertEqual(result.returncode, 0, result.stderr)
            cells = [c.strip() for c in result.stdout.strip().strip('|').split('|')]
            self.assertEqual(cells[0], 'every')
            self.assertGreater(float(cells[1]), 0.05)  # the VIO's aligned ATE: its drift is not a rigid motion
            self.assertLess(float(cells[2]), 1e-6)     # the floor
            self.assertEqual(cells[3], '100 %')
            self.assertEqual(cells[4], '0.000')        # the run, here the truth
            self.assertEqual(cells[5], '0 %')

    def test_a_gate_seen_only_at_the_start_leaves_the_vios_drift(self):
        with tempfile.TemporaryDirectory() as folder:
            flight(folder, 0.05, [1000.0 + 0.02 * k for k in range(26)])
            result = bound(folder, '--markdown', 'start')
            self.assertEqual(result.returncode, 0, result.stderr)
            cells = [c.strip() for c in result.stdout.strip().strip('|').split('|')]
            vio, floor = float(cells[1]), float(cells[2])
            self.assertGreater(floor, 0.5 * vio)       # the fix at 0.5 s removes little of a drift that grows later
            self.assertLessEqual(floor, vio + 1e-9)
            self.assertEqual(cells[4], 'n/a')
            self.assertEqual(cells[5], '92 %')         # 925 of the 1001 stamps are over 1 s after the last fix (0.5 s)

    def test_a_vio_without_error_has_nothing_to_reduce(self):
        with tempfile.TemporaryDirectory() as folder:
            flight(folder, 0.0, [1005.0])
            result = bound(folder)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn('largest reduction n/a', result.stdout)

    def test_a_folder_without_detections_is_named(self):
        with tempfile.TemporaryDirectory() as folder:
            flight(folder, 0.05, [1005.0])
            os.remove(os.path.join(folder, 'corners.csv'))
            result = bound(folder)
            self.assertNotEqual(result.returncode, 0)
            self.assertIn(folder, result.stderr)
            self.assertIn('corners.csv', result.stderr)


class VioHybrid(unittest.TestCase):
    def test_each_part_of_the_error_is_taken_from_its_source_in_the_truths_frame(self):
        with tempfile.TemporaryDirectory() as folder:
            # The VIO's frame turned 0.3 rad about z and 5 m off: its positions and attitude both in that frame.
            stamps = [1000.0 + 0.02 * k for k in range(1001)]
            truth = [(t, t - 1000.0, 0.2 * math.sin(t - 1000.0), 1.0) for t in stamps]
            c, s = math.cos(0.3), math.sin(0.3)
            # A vertical drift no rigid motion explains (two whole periods over the flight).
            drift = [0.1 * math.cos(2 * math.pi * (t - 1000.0) / 10.0) for t in stamps]
            vio = [(t, c * x - s * y + 5.0, s * x + c * y, z + d) for (t, x, y, z), d in zip(truth, drift)]
            write_tum(os.path.join(folder, 'gt.tum'), truth)
            write_tum(os.path.join(folder, 'vio.tum'), vio, yaw=0.3 + 0.05)  # attitude off by 0.05 rad
            rows = {}
            for mode in ('position', 'attitude', 'both'):
                out = os.path.join(folder, mode + '.tum')
                result = subprocess.run([sys.executable, os.path.join(BENCH, 'vio_hybrid.py'),
                                         os.path.join(folder, 'vio.tum'), os.path.join(folder, 'gt.tum'), mode, out],
                                        capture_output=True, text=True)
                self.assertEqual(result.returncode, 0, result.stderr)
                with open(out) as f:
                    rows[mode] = [[float(v) for v in line.split()] for line in f if not line.startswith('#')]
                self.assertEqual(len(rows[mode]), 1001)
            for k in (0, 500, 1000):
                t, x, y, z = truth[k]
                self.assertAlmostEqual(rows['attitude'][k][1], x, places=5)   # the truth's position
                self.assertAlmostEqual(rows['attitude'][k][2], y, places=5)
                yaw_attitude = 2 * math.atan2(rows['attitude'][k][6], rows['attitude'][k][7])
                self.assertAlmostEqual(yaw_attitude, 0.05, delta=2e-3)           # the VIO's 0.05 rad, frame removed
                yaw_position = 2 * math.atan2(rows['position'][k][6], rows['position'][k][7])
                self.assertAlmostEqual(yaw_position, 0.0, places=6)              # the truth's attitude
                self.assertEqual(rows['both'][k][1:4], rows['position'][k][1:4])
                self.assertEqual(rows['both'][k][4:8], rows['attitude'][k][4:8])
            # The drift stays in the positions.
            vertical = [rows['position'][k][3] - truth[k][3] for k in range(1001)]
            self.assertGreater(max(vertical) - min(vertical), 0.19)


class FrameFromFixes(unittest.TestCase):
    """bench/detection_fix_floor.py's third figure: the VIO taken as exact in the frame the fixes so far fit."""

    def setUp(self):
        import types
        sys.modules.setdefault('dualgraph', types.ModuleType('dualgraph'))  # only the fit is used: no bindings needed
        sys.path.insert(0, BENCH)
        import detection_fix_floor
        import numpy
        self.floor, self.np = detection_fix_floor, numpy

    def test_exact_fixes_give_the_truth_once_they_span_a_plane_and_a_line_is_refused(self):
        np = self.np
        stamps = np.arange(0.0, 20.0, 0.05)
        truth = np.stack([np.cos(0.3 * stamps) * 5, np.sin(0.3 * stamps) * 5, 1.0 + 0.1 * stamps], 1)
        yaw, offset = 0.4, np.array([3.0, -2.0, 0.5])  # the VIO's frame in the map: world = Rz(yaw)·odom + offset
        rz = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
        odom = (rz.T @ (truth - offset).T).T
        q = [0.0, 0.0, math.sin(-yaw / 2), math.cos(-yaw / 2)]  # the body level and along the map's x, seen in odom
        vio = np.column_stack([stamps, odom, np.tile(q, (len(stamps), 1))])
        fix_times = stamps[::20]
        fixes = {}
        for t in fix_times:
            pose = np.eye(4)
            pose[:3, 3] = truth[np.searchsorted(stamps, t)]
            fixes[t] = pose
        placed = self.floor.frame_from_fixes(vio, fixes, fix_times, stamps)
        self.assertLess(np.abs(placed - truth).max(), 1e-6)  # one exact pose fix already tells the frame
        line = np.column_stack([np.arange(5.0), np.zeros(5), np.zeros(5)])
        self.assertIsNone(self.floor.rigid_fit(line, line))
        r, p = self.floor.rigid_fit(odom[::37], truth[::37])
        self.assertLess(np.abs(r - rz).max(), 1e-9)
        self.assertLess(np.abs(p - offset).max(), 1e-9)


if __name__ == '__main__':
    unittest.main()
