// SPDX-License-Identifier: MIT
#include "py_localizer.h"

#include "arrays.h"
#include "errors.h"

namespace py = pybind11;

namespace dualgraph::python {

GateMap toGateMap(py::handle gates) {
  if (!py::isinstance<py::dict>(gates)) raiseInvalid("gates: expected a dict {gate_id: world_T_gate}");
  GateMap map;
  for (const auto& [key, pose] : py::reinterpret_borrow<py::dict>(gates)) {
    const std::vector<int> id = toIds(key, "gates key", 1);
    map.world_T_gate[id[0]] = toPose(pose, "gates[" + std::to_string(id[0]) + "]");
  }
  return map;
}

py::tuple stampedPoses(const std::vector<CorrectedPose>& poses) {
  std::vector<double> times;
  IsometryList world_T_body;
  for (const CorrectedPose& pose : poses) {
    times.push_back(pose.t);
    world_T_body.push_back(pose.world_T_body);
  }
  return py::make_tuple(vectorArray(times), poseArrays(world_T_body));
}

std::unique_ptr<PyLocalizer> PyLocalizer::create(const LocalizerParams& params, py::handle gates) {
  return std::unique_ptr<PyLocalizer>(new PyLocalizer(unwrap(Localizer::create(params, toGateMap(gates)))));
}

py::array_t<double> PyLocalizer::addOdometry(double t, py::handle odom_T_body, py::handle covariance, bool as_matrix) {
  OdometrySample sample;
  sample.t = t;
  sample.odom_T_body = toPose(odom_T_body, "odom_T_body");
  if (!covariance.is_none()) sample.relative_covariance = Matrix6d(toMatrix(covariance, "covariance", 6, 6));
  const CorrectedPose pose = unwrap(localizer_->addOdometry(sample));  // GIL held: a Localizer is not thread-safe
  return as_matrix ? poseMatrix(pose.world_T_body) : poseArray(pose.world_T_body);
}

void PyLocalizer::addObservation(const GateObservation& observation) { check(localizer_->addObservation(observation)); }

void PyLocalizer::finish() { check(localizer_->finish()); }

py::tuple PyLocalizer::keyframes() const { return stampedPoses(localizer_->keyframeTrajectory()); }

py::list PyLocalizer::statsToList(const std::vector<KeyframeStats>& stats) {
  py::list rows;
  for (const KeyframeStats& s : stats) {
    py::dict row;
    row["keyframe"] = s.keyframe;
    row["t"] = s.t;
    row["main_vertices"] = s.main_vertices;
    row["main_edges"] = s.main_edges;
    row["iterations"] = s.iterations;
    row["optimize_ms"] = s.optimize_ms;
    row["termination"] = terminationReasonName(s.termination);
    row["gate_edges_added"] = s.gate_edges_added;
    row["gate_edges_rejected"] = s.gate_edges_rejected;
    row["gates_skipped"] = s.gates_skipped;
    row["observations"] = s.observations;
    row["temp_nodes"] = s.temp_nodes;
    row["temp_edges"] = s.temp_edges;
    row["temp_iterations"] = s.temp_iterations;
    row["temp_ms"] = s.temp_ms;
    rows.append(row);
  }
  return rows;
}

py::dict PyLocalizer::countersToDict(const LocalizerCounters& c) {
  py::dict out;
  out["odometry_accepted"] = c.odometry_accepted;
  out["odometry_rejected"] = c.odometry_rejected;
  out["observations_accepted"] = c.observations_accepted;
  out["observations_rejected"] = c.observations_rejected;
  out["observations_too_late"] = c.observations_too_late;
  out["observations_too_far_ahead"] = c.observations_too_far_ahead;
  out["observations_failed"] = c.observations_failed;
  out["observations_never_processed"] = c.observations_never_processed;
  out["observations_between_nodes"] = c.observations_between_nodes;
  out["observations_without_frame"] = c.observations_without_frame;
  out["losses"] = c.losses;
  out["recoveries"] = c.recoveries;
  out["relocalizations"] = c.relocalizations;
  out["keyframes_conditioned"] = c.keyframes_conditioned;
  out["partial_used"] = c.partial_used;
  out["partial_unanchored"] = c.partial_unanchored;
  out["last_error"] = c.last_error;
  return out;
}

}  // namespace dualgraph::python
