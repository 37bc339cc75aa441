// SPDX-License-Identifier: MIT
// dualgraph.evaluate_trajectory (ATE / RPE as `dualgraph eval`), dualgraph.read_trajectory, TrajectoryMetrics.
#include <pybind11/stl.h>

#include <optional>

#include "arrays.h"
#include "bindings.h"
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "errors.h"
#include "typed_args.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace dualgraph::python {
namespace {

bool isPath(py::handle object) {
  return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__");
}

/// readTrajectory (TUM or EuRoC CSV, recognised from the file) without the GIL.
OdometryLog readTrajectoryFile(py::handle path_object) {
  const std::string path = py::str(py::module_::import("os").attr("fspath")(path_object));
  Result<OdometryLog> log = [&] {
    py::gil_scoped_release release;
    return readTrajectory(path);
  }();
  return unwrap(std::move(log));
}

/// A path (read as the CLI reads it: bit-exact parity), an (n, 8) array [t x y z qx qy qz qw], or (times (n,),
/// poses (n, 7) or (n, 4, 4)) as Sequence.odometry, Sequence.ground_truth and RunResult.estimate give them.
StampedPoses toStampedPoses(py::handle object, const std::string& name) {
  if (isPath(object)) return stampedPosesFromSamples(readTrajectoryFile(object).samples);
  StampedPoses out;
  if (py::isinstance<py::tuple>(object) && py::len(object) == 2) {
    const py::tuple pair = py::reinterpret_borrow<py::tuple>(object);
    const DoubleArray times = toDoubles(pair[0], name + "[0]");
    if (times.ndim() != 1) raiseInvalid(name + "[0]: expected times of shape (n,), got " + shapeString(times));
    requireFinite(times, name + "[0]");
    const IsometryList poses = toPoses(pair[1], name + "[1]", static_cast<long>(times.size()));
    for (py::ssize_t i = 0; i < times.size(); ++i) out.emplace_back(times.data()[i], poses[static_cast<size_t>(i)]);
    return out;
  }
  const auto rows = toRows(object, name, -1, 8);
  const Eigen::MatrixXd pose_rows = rows.rightCols<7>();
  py::array_t<double> poses({static_cast<py::ssize_t>(rows.rows()), py::ssize_t{7}});
  for (long i = 0; i < rows.rows(); ++i) {
    for (int k = 0; k < 7; ++k) poses.mutable_data()[7 * i + k] = pose_rows(i, k);
  }
  const IsometryList isometries = toPoses(poses, name + "[:, 1:]", rows.rows());
  for (long i = 0; i < rows.rows(); ++i) out.emplace_back(rows(i, 0), isometries[static_cast<size_t>(i)]);
  return out;
}

py::dict statsDict(const ErrorStatistics& s) {
  return py::dict("rmse"_a = s.rmse, "mean"_a = s.mean, "median"_a = s.median, "std"_a = s.std, "min"_a = s.min,
                  "max"_a = s.max);
}

py::list rpeDicts(const std::vector<RelativePoseError>& windows) {
  py::list out;
  for (const RelativePoseError& r : windows) {
    out.append(py::dict("distance_m"_a = r.distance_m, "frames"_a = r.frames, "pairing"_a = rpePairingName(r.pairing),
                        "pairs"_a = r.pairs, "translation_rmse_m"_a = r.translation_rmse_m,
                        "rotation_rmse_deg"_a = r.rotation_rmse_deg, "translation_m"_a = statsDict(r.translation_m),
                        "rotation_deg"_a = statsDict(r.rotation_deg)));
  }
  return out;
}

}  // namespace

void bindEvaluation(py::module_& m) {
  py::class_<TrajectoryMetrics>(m, "TrajectoryMetrics", R"doc(Accuracy of an estimate against ground truth (evaluate_trajectory).

Position errors |p_gt - world_T_estimate * p_est| [m] over the associated poses, with the alignment asked
for; rotation error the geodesic angle of R_gt^-1 * R_aligned [deg]; RPE over travelled-distance windows
(alignment-free). The same figures as `dualgraph eval` (frontend/evaluation/trajectory_metrics.h).)doc")
      .def_property_readonly("alignment", [](const TrajectoryMetrics& t) { return std::string(trajectoryAlignmentName(t.alignment)); },
                             "the alignment used, e.g. 'se3', '4dof', 'none'")
      .def_property_readonly("world_T_estimate", [](const TrajectoryMetrics& t) { return poseMatrix(t.world_T_estimate); },
                             "(4, 4) the transform the alignment found, estimate frame -> world [m]")
      .def_readonly("ate_m", &TrajectoryMetrics::ate_m, "position ATE (RMSE) with that alignment [m]")
      .def_readonly("ate_rot_deg", &TrajectoryMetrics::ate_rot_deg, "rotation ATE (RMSE of the angle) with that alignment [deg]")
      .def_property_readonly("stats", [](const TrajectoryMetrics& t) { return statsDict(t.ate_stats); },
                             "evo's statistics of the position errors [m]: {'rmse', 'mean', 'median', 'std' (population), "
                             "'min', 'max'}; rmse == ate_m")
      .def_property_readonly("rpe", [](const TrajectoryMetrics& t) { return rpeDicts(t.rpe); },
                             "one dict per RPE window in metres: {'distance_m' [m], 'frames' (0), 'pairing' ('every' or "
                             "'evo'), 'pairs' [count], 'translation_rmse_m' [m], 'rotation_rmse_deg' [deg], "
                             "'translation_m' and 'rotation_deg': evo's statistics as in stats} (NaN without pairs)")
      .def_property_readonly("rpe_frames", [](const TrajectoryMetrics& t) { return rpeDicts(t.rpe_frames); },
                             "one dict per RPE window in frames (rpe_frames), as rpe with 'distance_m' 0 and 'frames' Δ")
      .def_readonly("paired_from_ground_truth", &TrajectoryMetrics::paired_from_ground_truth,
                    "association 'evo' paired from the ground truth (it had fewer poses): the counters count its poses")
      .def_readonly("paired_from_poses", &TrajectoryMetrics::paired_from_poses,
                    "poses of the trajectory paired from (the estimate's unless paired_from_ground_truth) [count]")
      .def_readonly("estimate_poses", &TrajectoryMetrics::estimate_poses, "poses in the estimate [count]")
      .def_readonly("associated", &TrajectoryMetrics::associated, "estimate poses with ground truth: the ATE's sample count [count]")
      .def_property_readonly("unassociated", &TrajectoryMetrics::unassociated,
                             "before_span + after_span + beyond_gap [count]")
      .def_readonly("before_span", &TrajectoryMetrics::before_span, "estimate stamps before the first ground-truth sample [count]")
      .def_readonly("after_span", &TrajectoryMetrics::after_span, "estimate stamps after the last ground-truth sample [count]")
      .def_readonly("beyond_gap", &TrajectoryMetrics::beyond_gap,
                    "estimate stamps inside the ground truth's span but farther than max_gap_s from its samples [count]")
      .def("__repr__", [](const TrajectoryMetrics& t) {
        return "TrajectoryMetrics(alignment='" + std::string(trajectoryAlignmentName(t.alignment)) + "', ate_m=" +
               formatNumber(t.ate_m) + ", ate_rot_deg=" + formatNumber(t.ate_rot_deg) + ", associated=" + std::to_string(t.associated) +
               " of " + std::to_string(t.estimate_poses) + ", rpe=" + std::to_string(t.rpe.size()) + " windows)";
      });

  m.def("evaluate_trajectory",
        [](TrajectoryLike gt, TrajectoryLike est, const std::string& align, double max_gap_s,
           const std::vector<double>& rpe_distances_m, double max_dt_s, double min_associated,
           std::optional<std::string> association_name, const std::vector<long>& rpe_frames,
           const std::string& rpe_pairing) {
          if (!(min_associated >= 0.0 && min_associated <= 1.0)) {
            raiseInvalid("min_associated: expected a share in [0, 1], got " + std::to_string(min_associated));
          }
          TrajectoryMetricsParams params;
          params.alignment = unwrap(parseTrajectoryAlignment(align));  // every mode the library knows, by its name
          params.max_gap_s = max_gap_s;
          params.rpe_distances_m = rpe_distances_m;
          params.rpe_frames = rpe_frames;
          params.rpe_pairing = unwrap(parseRpePairing(rpe_pairing));
          // None: as `dualgraph eval` without --association: interpolated, or nearest when max_dt_s is given.
          const std::string association = association_name.value_or(max_dt_s != 0.0 ? "nearest" : "interpolated");
          if (association == "interpolated") {
            if (max_dt_s != 0.0) raiseInvalid("max_dt_s: not used by association 'interpolated' (max_gap_s is)");
          } else if (association == "nearest" || association == "evo") {
            params.max_dt_s = max_dt_s != 0.0 ? max_dt_s : (association == "evo" ? 0.01 : 0.0);
            if (!(params.max_dt_s > 0.0)) raiseInvalid("max_dt_s: association 'nearest' needs max_dt_s > 0 [s]");
            params.evo_association = association == "evo";
          } else {
            raiseInvalid("association: expected 'interpolated', 'nearest' or 'evo', got '" + association + "'");
          }
          const StampedPoses gt_poses = toStampedPoses(gt, "gt");
          const StampedPoses est_poses = toStampedPoses(est, "est");
          Result<TrajectoryMetrics> metrics = [&] {
            py::gil_scoped_release release;
            return evaluateTrajectory(gt_poses, est_poses, params);
          }();
          TrajectoryMetrics result = unwrap(std::move(metrics));
          // As `dualgraph eval --min-associated`: figures from a sliver of the poses paired from are a plausible
          // wrong answer.
          if (static_cast<double>(result.associated) < min_associated * static_cast<double>(result.paired_from_poses)) {
            const std::string side = result.paired_from_ground_truth ? " ground-truth poses have an estimate pose"
                                                                     : " estimate poses have ground truth";
            raise(Status(StatusCode::kFailedPrecondition,
                         "only " + std::to_string(result.associated) + " of " + std::to_string(result.paired_from_poses) +
                             side + " (below min_associated " + std::to_string(min_associated) +
                             "): the two trajectories do not cover the same time (another clock, or nanoseconds read "
                             "as seconds?)"));
          }
          return result;
        },
        "gt"_a, "est"_a, "align"_a = "se3", "max_gap_s"_a = 0.1, py::arg_v("rpe_distances_m", std::vector<double>{1.0, 10.0}, "(1.0, 10.0)"), "max_dt_s"_a = 0.0,
        "min_associated"_a = 0.5, "association"_a = py::none(), py::arg_v("rpe_frames", std::vector<long>{}, "()"),
        "rpe_pairing"_a = "every",
        R"doc(ATE and RPE of an estimate against ground truth, as `dualgraph eval --align ALIGN`.

gt, est: a trajectory file path (TUM `t x y z qx qy qz qw` [s, m] or EuRoC CSV [ns], as read_trajectory),
an (n, 8) array [t x y z qx qy qz qw] (t [s], position [m], quaternion Hamilton), or (times (n,) [s],
poses (n, 7) or (n, 4, 4)) as Sequence.odometry / Sequence.ground_truth / RunResult.estimate give them.
association: None (default: 'interpolated', or 'nearest' when max_dt_s is given, as `dualgraph eval`);
'interpolated': every estimate pose inside the ground
truth's time span with a ground-truth sample within max_gap_s [s] is paired with the ground truth interpolated at
its stamp; 'nearest': with the ground-truth pose of the nearest stamp within max_dt_s [s] (> 0); 'evo': as
evo_ape --t_max_diff, each pose of the trajectory with fewer poses with the other's nearest stamp within max_dt_s
(0: evo's 0.01 s). align: the name of an alignment of frontend/evaluation/trajectory_metrics.h ('se3' Umeyama
without scale, 'sim3', '4dof' yaw + translation, 'none', and any mode added there). rpe_distances_m: the RPE
windows [m]; rpe_frames: windows in associated poses (1: evo_rpe's default); rpe_pairing: 'every' (a pair from
every pose) or 'evo' (evo_rpe's consecutive pairs). Raises InvalidArgumentError for a bad input, alignment,
association or pairing name, FailedPreconditionError when nothing can be associated, too few poses to align, or
fewer than min_associated [1] of the poses paired from have a partner (`eval --min-associated`, 0.5; 0 accepts
any).)doc");

  m.def("read_trajectory",
        [](PathLike path) {
          const OdometryLog log = readTrajectoryFile(path);
          py::array_t<double> out({static_cast<py::ssize_t>(log.samples.size()), py::ssize_t{8}});
          for (size_t i = 0; i < log.samples.size(); ++i) {
            out.mutable_data()[8 * i] = log.samples[i].t;
            const Eigen::Matrix<double, 7, 1> pose = poseToVector(log.samples[i].odom_T_body);
            for (int k = 0; k < 7; ++k) out.mutable_data()[8 * i + 1 + k] = pose[k];
          }
          return out;
        },
        "path"_a,
        "A TUM trajectory (`t x y z qx qy qz qw`, t [s], position [m]) or EuRoC CSV (t [ns], quaternion w first), "
        "recognised from the file as `dualgraph eval` does -> (n, 8) [t x y z qx qy qz qw] (t [s], w >= 0).");
}

}  // namespace dualgraph::python
