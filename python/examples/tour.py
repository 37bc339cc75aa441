# SPDX-License-Identifier: MIT
"""A tour of the dualgraph Python module, in notebook-style cells (`# %%`: run them one by one in VS Code or
Jupytext, or the whole file with `/usr/bin/python3 python/examples/tour.py [FILE.g2o]`).

PYTHONPATH must hold the built module: `PYTHONPATH=build/python /usr/bin/python3 python/examples/tour.py`.
"""
# %% A pose graph from numpy: an SE(2) ring of 20 poses, odometry with a heading bias, one precise loop closure.
import sys

import numpy as np

import dualgraph

rng = np.random.default_rng(0)
n = 20
angles = 2 * np.pi * np.arange(n) / n
truth = np.c_[5 * np.cos(angles), 5 * np.sin(angles), angles + np.pi / 2]  # [x y theta], on a 5 m circle
chord = 2 * 5 * np.sin(np.pi / n)  # pose k to k+1 in pose k's frame: the chord, pi/n left of the heading
step = [chord * np.cos(np.pi / n), chord * np.sin(np.pi / n), 2 * np.pi / n]
odometry = np.tile(step, (n - 1, 1)) + rng.normal(0, [0.02, 0.02, 0.005], (n - 1, 3)) + [0, 0, 0.01]
closure = np.array(step) + rng.normal(0, [0.01, 0.01, 0.002])  # pose 19 -> pose 0, e.g. a place recognised

graph = dualgraph.Graph()
guess = [truth[0]]
for k in range(n - 1):  # dead reckoning from the biased odometry
    x, y, th = guess[-1]
    dx, dy, dth = odometry[k]
    guess.append([x + np.cos(th) * dx - np.sin(th) * dy, y + np.sin(th) * dx + np.cos(th) * dy, th + dth])
graph.add_se2_vertices(np.arange(n), np.array(guess))
graph.add_se2_edges(np.c_[np.arange(n - 1), np.arange(1, n)], odometry, np.diag([1 / 0.02 ** 2, 1 / 0.02 ** 2, 1 / 0.01 ** 2]))
information = np.diag([1 / 0.01 ** 2, 1 / 0.01 ** 2, 1 / 0.002 ** 2])
graph.add_se2_edges([[n - 1, 0]], closure[None], information)
graph.set_fixed([0])
print(f"ring: {graph.num_vertices} vertices, {graph.num_edges} edges, chi2 {graph.chi2():.1f}")

# %% Optimise with Levenberg-Marquardt on CHOLMOD, read the estimates and a marginal covariance.
summary = graph.optimize(linear_solver="cholmod")
print(summary)
estimate = graph.se2_estimates()
print(f"worst position error {np.abs(estimate[:, :2] - truth[:, :2]).max():.3f} m "
      f"(dead reckoning {np.abs(np.array(guess)[:, :2] - truth[:, :2]).max():.3f} m)")
sigma = graph.marginal(n // 2)  # [x y theta] of the pose opposite the fixed one
print("sigma of pose", n // 2, "[m, m, rad]:", np.sqrt(np.diag(sigma)).round(4))

# %% A g2o file (argument), optimised as `dualgraph optimize FILE` does (gauge: highest id).
if len(sys.argv) > 1:
    garage = dualgraph.Graph.load(sys.argv[1])
    print(f"{sys.argv[1]}: fixed vertex {garage.fix_gauge('highest')}, {garage.optimize()}")

# %% The Localizer: a circle flight with a drifting odometry and gate detections.
def on_circle(phi, radius=10.0):
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
params = dualgraph.LocalizerParams()
params.d_main = 2.0  # keyframe every 2 m of VIO travel (the default)
localizer = dualgraph.Localizer(params, gates)
detection_covariance = np.diag([0.05 ** 2] * 3 + [0.02 ** 2] * 3)  # metric [t; theta], gate frame
omega = 0.5  # [rad/s]: 5 m/s on the 10 m circle
for k in range(int(2 * 2 * np.pi / omega / 0.02)):  # two laps of 50 Hz odometry
    t = 0.02 * k
    world_T_body = on_circle(omega * t)
    odom_T_body = yaw(0.02 * t) @ world_T_body  # the VIO's yaw drifts by 0.02 rad/s
    corrected = localizer.add_odometry(t, odom_T_body, as_matrix=True)
    if k % 5 == 0:  # then a detection of every gate 1-8 m ahead, 10 Hz
        for gate_id, world_T_gate in gates.items():
            body_T_gate = np.linalg.inv(world_T_body) @ world_T_gate
            if 1.0 < body_T_gate[0, 3] < 8.0:
                localizer.add_pose_observation(t, gate_id, body_T_gate, detection_covariance)
localizer.finish()
print(f"Localizer: final error {np.linalg.norm(corrected[:3, 3] - world_T_body[:3, 3]):.3f} m, "
      f"VIO {np.linalg.norm(odom_T_body[:3, 3] - world_T_body[:3, 3]):.3f} m; "
      f"{len(localizer.stats())} optimisations, counters {localizer.counters()}")

# %% Errors are Python exceptions carrying the library's message.
try:
    graph.add_se2_edges([[0, 99]], [[1.0, 0.0, 0.0]], information)
except dualgraph.NotFoundError as error:
    print(f"{type(error).__name__} ({error.code}): {error}")
