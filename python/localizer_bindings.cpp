// SPDX-License-Identifier: MIT
// dualgraph.LocalizerParams, dualgraph.GateObservation, dualgraph.Localizer.
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "dual_graph/localizer.h"
#include "frontend/io/localizer_params_yaml.h"
#include "errors.h"
#include "py_localizer.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace dualgraph::python {
namespace {

template <typename Enum>
Enum parseName(const std::string& name, const char* field, std::initializer_list<std::pair<const char*, Enum>> names) {
  std::string allowed;
  for (const auto& [text, value] : names) {
    if (name == text) return value;
    allowed += (allowed.empty() ? "'" : ", '") + std::string(text) + "'";
  }
  raiseInvalid(std::string(field) + " must be one of " + allowed + ", got '" + name + "'");
}

void bindParams(py::module_& m) {
  py::class_<LocalizerParams> params(m, "LocalizerParams",
                                     "Every tunable of the Localizer with its default (metres, radians, sigmas in the units "
                                     "of their quantity); see dual_graph/localizer_params.h and data/config/default.yaml.");
  params.def(py::init<>())
      .def_property("mode", [](const LocalizerParams& p) { return localizerModeName(p.mode); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.mode = parseName<LocalizerMode>(v, "mode", {{"dual", LocalizerMode::kDual}, {"single", LocalizerMode::kSingle}});
                    })
      .def_property("landmark", [](const LocalizerParams& p) { return landmarkModelName(p.landmark); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.landmark = parseName<LandmarkModel>(v, "landmark", {{"pose", LandmarkModel::kPose}, {"point", LandmarkModel::kPoint}});
                    })
      .def_property("linear_solver", [](const LocalizerParams& p) { return linearSolverKindName(p.linear_solver); },
                    [](LocalizerParams& p, const std::string& v) { p.linear_solver = unwrap(parseLinearSolverKind(v)); })
      .def_property("lm_damping", [](const LocalizerParams& p) { return lmDampingName(p.lm_damping); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.lm_damping = parseName<LmDamping>(v, "lm_damping", {{"identity", LmDamping::kIdentity}, {"diagonal", LmDamping::kDiagonal}});
                    })
      .def_property("temp_solver", [](const LocalizerParams& p) { return temporarySolverKindName(p.temp_solver); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.temp_solver = parseName<TemporarySolverKind>(v, "temp_solver", {{"block", TemporarySolverKind::kBlock}, {"graph", TemporarySolverKind::kGraph}});
                    })
      .def_property("initial_world_T_odom", [](const LocalizerParams& p) { return poseArray(p.initial_world_T_odom); },
                    [](LocalizerParams& p, py::handle pose) { p.initial_world_T_odom = toPose(pose, "initial_world_T_odom"); })
      .def("validate", [](const LocalizerParams& p) { check(validateLocalizerParams(p)); },
           "Raises InvalidArgumentError naming the first field out of its domain.");
#define DG_FIELD(name) params.def_readwrite(#name, &LocalizerParams::name)
  DG_FIELD(mapping); DG_FIELD(d_main); DG_FIELD(theta_main); DG_FIELD(d_temp); DG_FIELD(theta_temp);
  DG_FIELD(d_single); DG_FIELD(theta_single); DG_FIELD(single_all_detections); DG_FIELD(use_input_covariance); DG_FIELD(odom_sigma_t);
  DG_FIELD(odom_sigma_r); DG_FIELD(odom_min_distance); DG_FIELD(map_sigma_t); DG_FIELD(map_sigma_r);
  DG_FIELD(fix_map_gates); DG_FIELD(initial_sigma_t); DG_FIELD(initial_sigma_r); DG_FIELD(main_max_iterations);
  DG_FIELD(main_time_budget_ms); DG_FIELD(main_relative_decrease_stop); DG_FIELD(main_window); DG_FIELD(temp_max_iterations);
  DG_FIELD(temp_relative_decrease_stop);
  DG_FIELD(temp_model_decrease_stop);
  DG_FIELD(robust_kernel); DG_FIELD(chi2_gate_pose); DG_FIELD(chi2_gate_point);
  DG_FIELD(lost_after_s); DG_FIELD(lost_min_failures); DG_FIELD(detection_latency);
#undef DG_FIELD

  m.def("load_localizer_params", [](const std::string& path) { return unwrap(loadLocalizerParams(path)); }, "path"_a,
        "Reads LocalizerParams from YAML (ParseError / InvalidArgumentError name file:line: field).");
  m.def("parse_localizer_params",
        [](const std::string& text, const std::string& source) { return unwrap(parseLocalizerParams(text, source)); },
        "text"_a, "source_name"_a = "<string>");
}

void bindObservation(py::module_& m) {
  py::class_<GateObservation>(m, "GateObservation",
                              "One gate observation: 'pose' (body_T_gate, covariance metric [t; theta] 6x6, right "
                              "perturbation in the gate frame) or 'position' (p_body [m], covariance 3x3 m^2, body axes).")
      .def_static("pose",
                  [](double t, int gate_id, py::handle body_T_gate, py::handle covariance) {
                    return GateObservation::pose(t, gate_id, toPose(body_T_gate, "body_T_gate"),
                                                 toMatrix(covariance, "covariance", 6, 6));
                  },
                  "t"_a, "gate_id"_a, "body_T_gate"_a, "covariance"_a)
      .def_static("position",
                  [](double t, int gate_id, py::handle p_body, py::handle covariance) {
                    return GateObservation::position(t, gate_id, toRows(p_body, "p_body", 1, 3).row(0).transpose(),
                                                     toMatrix(covariance, "covariance", 3, 3));
                  },
                  "t"_a, "gate_id"_a, "p_body"_a, "covariance"_a)
      .def_readonly("t", &GateObservation::t)
      .def_readonly("gate_id", &GateObservation::gate_id)
      .def_property_readonly("kind", [](const GateObservation& o) { return o.kind == ObservationKind::kPose ? "pose" : "position"; })
      .def_property_readonly("body_T_gate", [](const GateObservation& o) { return poseArray(o.body_T_gate); })
      .def_property_readonly("body_T_gate_matrix", [](const GateObservation& o) { return poseMatrix(o.body_T_gate); })
      .def_property_readonly("p_body", [](const GateObservation& o) { return matrixArray(o.centreInBody().transpose()).attr("reshape")(3); })
      .def_property_readonly("covariance", [](const GateObservation& o) {
        return o.kind == ObservationKind::kPose ? matrixArray(o.pose_covariance) : matrixArray(o.position_covariance);
      })
      .def("__repr__", [](const GateObservation& o) {
        return "GateObservation(t=" + formatTimestamp(o.t) + ", gate_id=" + std::to_string(o.gate_id) + ", kind=" +
               (o.kind == ObservationKind::kPose ? "pose" : "position") + ")";
      });
}

}  // namespace

void bindLocalizer(py::module_& m) {
  bindParams(m);
  bindObservation(m);
  py::class_<PyLocalizer>(m, "Localizer", R"doc(Drift-corrected localisation with the dual pose graph.

Feed odometry (odom_T_body, optional relative covariance: metric [t; theta] of the motion since the previous
sample, body frame) and gate observations in time order; add_odometry returns world_T_body at that sample.
A rejected input raises (InvalidArgumentError, ...) with the library's message; the Localizer goes on.)doc")
      .def(py::init(&PyLocalizer::create), "params"_a = LocalizerParams{}, "gates"_a = py::dict(),
           "gates: {id: world_T_gate as [x y z qx qy qz qw] or 4x4}; empty only in mapping mode.")
      .def("add_odometry", &PyLocalizer::addOdometry, "t"_a, "odom_T_body"_a, "covariance"_a = py::none(),
           "as_matrix"_a = false, "Returns the corrected world_T_body at t: (7,) or (4, 4).")
      .def("add_observation", &PyLocalizer::addObservation, "observation"_a)
      .def("add_pose_observation",
           [](PyLocalizer& l, double t, int gate_id, py::handle body_T_gate, py::handle covariance) {
             l.addObservation(GateObservation::pose(t, gate_id, toPose(body_T_gate, "body_T_gate"),
                                                    toMatrix(covariance, "covariance", 6, 6)));
           },
           "t"_a, "gate_id"_a, "body_T_gate"_a, "covariance"_a)
      .def("add_position_observation",
           [](PyLocalizer& l, double t, int gate_id, py::handle p_body, py::handle covariance) {
             l.addObservation(GateObservation::position(t, gate_id, toRows(p_body, "p_body", 1, 3).row(0).transpose(),
                                                        toMatrix(covariance, "covariance", 3, 3)));
           },
           "t"_a, "gate_id"_a, "p_body"_a, "covariance"_a)
      .def("finish", &PyLocalizer::finish, "End of input: distils what is collected and optimises once more.")
      .def_property_readonly("tracking_state", [](const PyLocalizer& l) { return trackingStateName(l.get().trackingState()); },
                             "'initialising', 'tracking' or 'lost' (dual_graph/tracking_monitor.h).")
      .def_property_readonly("map_T_odom", [](const PyLocalizer& l) { return poseArray(l.get().mapTOdom()); })
      .def_property_readonly("map_T_odom_matrix", [](const PyLocalizer& l) { return poseMatrix(l.get().mapTOdom()); })
      .def("keyframes", &PyLocalizer::keyframes, "(times (n,), world_T_body (n, 7)) of the keyframes' current estimates.")
      .def("stats", &PyLocalizer::stats, "One dict per main-graph optimisation (keyframe, t, main_vertices, ...).")
      .def("counters", &PyLocalizer::counters, "Inputs accepted / rejected / unused, and the last rejection's message.")
      .def_property_readonly("params", [](const PyLocalizer& l) { return l.get().params(); });
}

}  // namespace dualgraph::python
