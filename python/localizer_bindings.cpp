// SPDX-License-Identifier: MIT
// dualgraph.LocalizerParams, dualgraph.GateObservation, dualgraph.Localizer.
#include <pybind11/stl.h>

#include <cstdio>

#include "arrays.h"
#include "bindings.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/dual_graph/observation_model.h"
#include "dualgraph/frontend/io/localizer_params_yaml.h"
#include "errors.h"
#include "py_localizer.h"
#include "typed_args.h"

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

std::string paramsRepr(const LocalizerParams& p) {
  char text[512];
  std::snprintf(text, sizeof(text),
                "LocalizerParams(mode='%s', landmark='%s', mapping=%s, d_main=%g, theta_main=%g, d_temp=%g, "
                "theta_temp=%g, main_window=%d, robust_kernel='%s', linear_solver='%s', lm_damping='%s', "
                "temp_solver='%s', detection_latency=%g)",
                localizerModeName(p.mode), landmarkModelName(p.landmark), p.mapping ? "True" : "False", p.d_main,
                p.theta_main, p.d_temp, p.theta_temp, p.main_window, p.robust_kernel.c_str(),
                linearSolverKindName(p.linear_solver), lmDampingName(p.lm_damping), temporarySolverKindName(p.temp_solver),
                p.detection_latency);
  return text;
}

void bindParams(py::module_& m) {
  py::class_<LocalizerParams> params(m, "LocalizerParams",
                                     "Every tunable of the Localizer with its default (metres, radians, sigmas in the units "
                                     "of their quantity); see dual_graph/localizer_params.h and data/config/default.yaml, "
                                     "whose `localizer:` keys are named exactly as these fields.");
  params.def(py::init<>(), "The defaults (those of data/config/default.yaml).")
      .def_property("mode", [](const LocalizerParams& p) { return localizerModeName(p.mode); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.mode = parseName<LocalizerMode>(v, "mode", {{"dual", LocalizerMode::kDual}, {"single", LocalizerMode::kSingle}});
                    },
                    "'dual' (a temporary graph per keyframe interval, one distilled edge per gate: the method) or 'single' "
                    "(every detection straight into one graph: the ablation baseline)")
      .def_property("landmark", [](const LocalizerParams& p) { return landmarkModelName(p.landmark); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.landmark = parseName<LandmarkModel>(v, "landmark", {{"pose", LandmarkModel::kPose}, {"point", LandmarkModel::kPoint}});
                    },
                    "'pose' (SE(3) gate poses, SE(3) detections) or 'point' (gate centres, position detections)")
      .def_property("linear_solver", [](const LocalizerParams& p) { return linearSolverKindName(p.linear_solver); },
                    [](LocalizerParams& p, const std::string& v) { p.linear_solver = unwrap(parseLinearSolverKind(v)); },
                    "'auto' (Eigen simplicial up to 3000 unknowns, CHOLMOD above), 'cholmod' or 'eigen'")
      .def_property("lm_damping", [](const LocalizerParams& p) { return lmDampingName(p.lm_damping); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.lm_damping = parseName<LmDamping>(v, "lm_damping", {{"identity", LmDamping::kIdentity}, {"diagonal", LmDamping::kDiagonal}});
                    },
                    "Levenberg-Marquardt damping of main and temporary graphs: 'diagonal' (H + lambda diag H, as Ceres) "
                    "or 'identity' (H + lambda I, as g2o)")
      .def_property("temp_solver", [](const LocalizerParams& p) { return temporarySolverKindName(p.temp_solver); },
                    [](LocalizerParams& p, const std::string& v) {
                      p.temp_solver = parseName<TemporarySolverKind>(v, "temp_solver", {{"block", TemporarySolverKind::kBlock}, {"graph", TemporarySolverKind::kGraph}});
                    },
                    "temporary graphs: 'block' (LM and marginals on 6x6 blocks) or 'graph' (the generic optimiser)")
      .def_property("initial_world_T_odom", [](const LocalizerParams& p) { return poseArray(p.initial_world_T_odom); },
                    [](LocalizerParams& p, ArrayLike pose) { p.initial_world_T_odom = toPose(pose, "initial_world_T_odom"); },
                    "(7,) [x y z qx qy qz qw] [m] (set: (7,) or (4, 4)): the first keyframe's guess is "
                    "initial_world_T_odom * odom_T_body(t0) (localization mode)")
      .def_property("initial_world_T_body",
                    [](const LocalizerParams& p) -> py::object {
                      if (!p.initial_world_T_body) return py::none();
                      return poseArray(*p.initial_world_T_body);
                    },
                    [](LocalizerParams& p, OptionalArrayLike pose) {
                      if (pose.is_none()) p.initial_world_T_body.reset(); else p.initial_world_T_body = toPose(pose, "initial_world_T_body");
                    },
                    "None or (7,) [x y z qx qy qz qw] [m]: a coarse start pose at the first odometry sample, known to "
                    "initial_sigma_t / initial_sigma_r; used by run_sequence's automatic initialisation only")
      .def("validate", [](const LocalizerParams& p) { check(validateLocalizerParams(p)); },
           "Raises InvalidArgumentError naming the first field out of its domain.")
      .def("__repr__", &paramsRepr);
#define DG_FIELD(name, doc) params.def_readwrite(#name, &LocalizerParams::name, doc)
  DG_FIELD(mapping, "false: localization against a known gate map (gate priors, detections of unknown gates rejected); "
                    "true: mapping (a landmark where a gate is first seen, the first keyframe fixed)");
  DG_FIELD(d_main, "main-graph keyframe spacing, dual mode: a new keyframe when the odometry moved this far [m]");
  DG_FIELD(theta_main, "... or turned this far [rad]");
  DG_FIELD(keyframe_max_interval_s, "... or this long has passed with detections waiting (a hovering drone) [s]; 0: off");
  DG_FIELD(d_temp, "temporary-graph node spacing at detection instants, dual mode [m]");
  DG_FIELD(theta_temp, "temporary-graph node spacing in rotation [rad]");
  DG_FIELD(d_single, "single-graph node spacing at detection instants, single mode [m]");
  DG_FIELD(theta_single, "single-graph node spacing in rotation [rad]");
  DG_FIELD(single_all_detections, "single mode: every detection, motion-compensated into the newest node (true) or only "
                                  "those at a node's own instant (false, the paper's baseline)");
  DG_FIELD(use_input_covariance, "use the odometry's own relative covariance when every sample of an interval has one; "
                                 "otherwise sigma * sqrt(d) per metre travelled");
  DG_FIELD(odom_sigma_t, "odometry translation sigma per sqrt(metre) travelled [m/sqrt(m)]");
  DG_FIELD(odom_sigma_r, "odometry yaw sigma (about the VIO frame's vertical) per sqrt(metre) travelled [rad/sqrt(m)]");
  DG_FIELD(odom_sigma_tilt, "odometry roll and pitch sigma (about the VIO frame's horizontal axes) per sqrt(metre) "
                            "travelled [rad/sqrt(m)]");
  DG_FIELD(odom_min_distance, "floor of the distance d in sigma * sqrt(d), so hovering keeps a usable covariance [m]");
  DG_FIELD(learn_odometry_noise, "learn the odometry covariance's sigma factors (and the gate edges' by range) in flight");
  DG_FIELD(odom_scale_min, "lowest learnt sigma factor on the odometry covariance [-]");
  DG_FIELD(odom_scale_max, "highest learnt sigma factor on the odometry covariance [-]");
  DG_FIELD(map_sigma_t, "prior sigma of each map gate's position (localization mode) [m]");
  DG_FIELD(map_sigma_r, "prior sigma of each map gate's orientation (localization mode) [rad]");
  DG_FIELD(fix_map_gates, "true: map gates are fixed vertices instead of prior edges");
  DG_FIELD(initial_sigma_t, "prior sigma of the first keyframe's position [m]; <= 0 fixes it instead");
  DG_FIELD(initial_sigma_r, "prior sigma of the first keyframe's orientation [rad]");
  DG_FIELD(main_max_iterations, "LM iterations after each keyframe, warm-started [count]");
  DG_FIELD(main_time_budget_ms, "wall-time budget per main optimisation [ms]; 0 = none");
  DG_FIELD(main_relative_decrease_stop, "stop the main graph's LM when an iteration lowers chi2 by less than this fraction [1]");
  DG_FIELD(main_window, "fixed lag: the newest keyframes kept free, older ones marginalised into one prior [count]; "
                        "0 = full batch, else >= 2");
  DG_FIELD(temp_max_iterations, "LM iterations of each temporary graph [count]");
  DG_FIELD(temp_relative_decrease_stop, "stop a temporary graph's LM when an iteration lowers chi2 by less than this fraction [1]");
  DG_FIELD(temp_model_decrease_stop, "or, one iteration earlier, when the undamped model predicts a decrease below this "
                                     "fraction of chi2 [1]; 0 = off");
  DG_FIELD(robust_kernel, "kernel on detection and distilled edges: 'none', 'huber:D', 'cauchy:D', 'tukey:D', 'dcs:D' "
                          "(D in whitened-error units [sigma])");
  DG_FIELD(distilled_floor_range, "systematic floor on a distilled edge: sigma along the line of sight per metre of range [-]");
  DG_FIELD(distilled_floor_lateral, "systematic floor on a distilled edge: sigma across the line of sight per metre of range [-]");
  DG_FIELD(distilled_floor_rotation, "systematic floor on a distilled edge: sigma of the gate orientation per axis [rad]");
  DG_FIELD(chi2_gate_pose, "chi-square gate on a pose edge against the main graph (99.9 % quantile, 6 dof) [1]; 0 disables");
  DG_FIELD(chi2_gate_point, "chi-square gate on a point edge (99.9 % quantile, 3 dof) [1]; 0 disables");
  DG_FIELD(lost_after_s, "tracking turns 'lost' when for this long no gate edge entered the main graph ... [s]");
  DG_FIELD(lost_min_failures, "... while at least this many detections failed [count]");
  DG_FIELD(detection_latency, "dual mode: how late a detection may reach the Localizer after its image; a keyframe waits "
                              "this long before its interval is closed [s]");
  DG_FIELD(max_observation_lead_s, "an observation stamped more than this beyond the newest odometry sample is refused "
                                   "(counted observations_too_far_ahead) [s]; 0: no limit");
#undef DG_FIELD

  m.def("load_localizer_params", [](const std::string& path) { return unwrap(loadLocalizerParams(path)); }, "path"_a,
        "Reads LocalizerParams from YAML (ParseError / InvalidArgumentError name file:line: field).");
  m.def("parse_localizer_params",
        [](const std::string& text, const std::string& source) { return unwrap(parseLocalizerParams(text, source)); },
        "text"_a, "source_name"_a = "<string>",
        "LocalizerParams from YAML text (the keys of a `localizer:` section); source_name names it in errors.");
}

void bindObservation(py::module_& m) {
  py::class_<GateObservation>(m, "GateObservation",
                              "One gate observation: 'pose' (body_T_gate, covariance metric [t; theta] 6x6, right "
                              "perturbation in the gate frame) or 'position' (p_body [m], covariance 3x3 m^2, body axes).")
      .def_static("pose",
                  [](double t, int gate_id, ArrayLike body_T_gate, ArrayLike covariance) {
                    return GateObservation::pose(t, gate_id, toPose(body_T_gate, "body_T_gate"),
                                                 toMatrix(covariance, "covariance", 6, 6));
                  },
                  "t"_a, "gate_id"_a, "body_T_gate"_a, "covariance"_a,
                  "t: image time on the odometry clock [s]; gate_id: map id (>= 0) or -1 (unknown); body_T_gate (7,) "
                  "[x y z qx qy qz qw] [m] or (4, 4); covariance (6, 6) metric [t; theta] [m^2, rad^2], gate frame.")
      .def_static("position",
                  [](double t, int gate_id, ArrayLike p_body, ArrayLike covariance) {
                    return GateObservation::position(t, gate_id, toRows(p_body, "p_body", 1, 3).row(0).transpose(),
                                                     toMatrix(covariance, "covariance", 3, 3));
                  },
                  "t"_a, "gate_id"_a, "p_body"_a, "covariance"_a,
                  "t [s]; gate_id (>= 0, or -1); p_body: the gate centre in the body frame (3,) [m]; covariance (3, 3) [m^2].")
      .def_readonly("t", &GateObservation::t, "image time on the odometry clock [s]")
      .def_readonly("gate_id", &GateObservation::gate_id, "the gate's map id, or -1 when unknown")
      .def_property_readonly("kind", [](const GateObservation& o) { return observationModel(o.kind).name(); },
                             "'pose', 'position' or 'corners' (a partial gate's corner rays)")
      .def_property_readonly("body_T_gate", [](const GateObservation& o) { return poseArray(o.body_T_gate); },
                             "(7,) [x y z qx qy qz qw] [m] (a position observation: identity rotation)")
      .def_property_readonly("body_T_gate_matrix", [](const GateObservation& o) { return poseMatrix(o.body_T_gate); },
                             "(4, 4) body_T_gate [m]")
      .def_property_readonly("p_body", [](const GateObservation& o) { return matrixArray(o.centreInBody().transpose()).attr("reshape")(3); },
                             "(3,) the gate centre in the body frame [m]")
      .def_property_readonly("covariance", [](const GateObservation& o) -> py::object {
        if (o.kind == ObservationKind::kPosition) return matrixArray(o.position_covariance);
        if (o.kind == ObservationKind::kCorners) {
          py::list rays;
          for (int k = 0; k < o.corner_rays.count; ++k) rays.append(matrixArray(o.corner_rays.covariance[static_cast<size_t>(k)]));
          return std::move(rays);
        }
        return matrixArray(o.pose_covariance);
      }, "pose: (6, 6) metric [t; theta] [m^2, rad^2]; position: (3, 3) [m^2]; corners: a list of (2, 2), per corner "
         "ray, of its normalised image coordinates [1]")
      .def("__repr__", [](const GateObservation& o) {
        const Eigen::Vector3d p = o.centreInBody();
        char centre[96];
        std::snprintf(centre, sizeof(centre), ", p_body=[%.4g, %.4g, %.4g])", p.x(), p.y(), p.z());
        return "GateObservation(t=" + formatTimestamp(o.t) + ", gate_id=" + std::to_string(o.gate_id) + ", kind=" +
               observationModel(o.kind).name() + centre;
      });
}

std::string localizerRepr(const PyLocalizer& l) {
  const LocalizerCounters& c = l.get().counters();
  return "Localizer(mode='" + std::string(localizerModeName(l.get().params().mode)) + "', tracking_state='" +
         trackingStateName(l.get().trackingState()) + "', optimisations=" + std::to_string(l.get().keyframeStats().size()) +
         ", odometry_accepted=" + std::to_string(c.odometry_accepted) + ", observations_accepted=" +
         std::to_string(c.observations_accepted) + ")";
}

}  // namespace

void bindLocalizer(py::module_& m) {
  bindParams(m);
  bindObservation(m);
  py::class_<PyLocalizer>(m, "Localizer", R"doc(Drift-corrected localisation with the dual pose graph.

Feed odometry (odom_T_body, optional relative covariance: metric [t; theta] of the motion since the previous
sample, body frame) and gate observations in time order; add_odometry returns world_T_body at that sample.
A rejected input raises (InvalidArgumentError, ...) with the library's message; the Localizer goes on.)doc")
      .def(py::init([](const LocalizerParams& params, GateMapLike gates) { return PyLocalizer::create(params, gates); }),
           py::arg_v("params", LocalizerParams{}, "LocalizerParams()"), py::arg_v("gates", py::dict(), "{}"),
           "gates: {id: world_T_gate as (7,) [x y z qx qy qz qw] [m] or (4, 4)}; empty only in mapping mode.")
      .def("add_odometry",
           [](PyLocalizer& l, double t, ArrayLike odom_T_body, OptionalArrayLike covariance, bool as_matrix) {
             return l.addOdometry(t, odom_T_body, covariance, as_matrix);
           },
           "t"_a, "odom_T_body"_a, "covariance"_a = py::none(), "as_matrix"_a = false,
           "t [s], strictly increasing; odom_T_body (7,) [m] or (4, 4); covariance: None or (6, 6) metric [t; theta] "
           "[m^2, rad^2] of the motion since the previous sample (body frame). Returns the corrected world_T_body at t: "
           "(7,) or, as_matrix, (4, 4).")
      .def("add_observation", &PyLocalizer::addObservation, "observation"_a,
           "A GateObservation (its t on the odometry clock [s]); held until the odometry covers its time.")
      .def("add_pose_observation",
           [](PyLocalizer& l, double t, int gate_id, ArrayLike body_T_gate, ArrayLike covariance) {
             l.addObservation(GateObservation::pose(t, gate_id, toPose(body_T_gate, "body_T_gate"),
                                                    toMatrix(covariance, "covariance", 6, 6)));
           },
           "t"_a, "gate_id"_a, "body_T_gate"_a, "covariance"_a, "As GateObservation.pose, then add_observation.")
      .def("add_position_observation",
           [](PyLocalizer& l, double t, int gate_id, ArrayLike p_body, ArrayLike covariance) {
             l.addObservation(GateObservation::position(t, gate_id, toRows(p_body, "p_body", 1, 3).row(0).transpose(),
                                                        toMatrix(covariance, "covariance", 3, 3)));
           },
           "t"_a, "gate_id"_a, "p_body"_a, "covariance"_a, "As GateObservation.position, then add_observation.")
      .def("observations_complete_until", &PyLocalizer::observationsCompleteUntil, "t"_a,
           "Every observation stamped at or before t [s] was given: a keyframe waiting detection_latency for late ones "
           "closes at the next sample once this reaches it (the pipeline calls it when its detector is done up to t).")
      .def("finish", &PyLocalizer::finish, "End of input: distils what is collected and optimises once more.")
      .def_property_readonly("tracking_state", [](const PyLocalizer& l) { return trackingStateName(l.get().trackingState()); },
                             "'initialising', 'tracking' or 'lost' (dual_graph/tracking_monitor.h).")
      .def_property_readonly("map_T_odom", [](const PyLocalizer& l) { return poseArray(l.get().mapTOdom()); },
                             "(7,) the current correction world_T_odom [m]: world_T_body = map_T_odom * odom_T_body")
      .def_property_readonly("map_T_odom_matrix", [](const PyLocalizer& l) { return poseMatrix(l.get().mapTOdom()); },
                             "(4, 4) map_T_odom [m]")
      .def("keyframes", &PyLocalizer::keyframes, "(times (n,) [s], world_T_body (n, 7) [m]) of the keyframes' current estimates.")
      .def("stats", &PyLocalizer::stats, "One dict per main-graph optimisation (keyframe, t [s], main_vertices, ..., times in ms).")
      .def("counters", &PyLocalizer::counters, "Inputs accepted / rejected / unused [count], and the last rejection's message.")
      .def_property_readonly("params", [](const PyLocalizer& l) { return l.get().params(); }, "a copy of its LocalizerParams")
      .def("__repr__", &localizerRepr);
}

}  // namespace dualgraph::python
