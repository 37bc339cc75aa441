// SPDX-License-Identifier: MIT
// Gate PnP (frontend/gates/gate_pnp.h) per detection on the simulated RATM ellipse flight (seed 1, the
// default detector noise): the true detections of one flight, solved in turn, with each covariance
// model. Arguments: covariance model (0 tilt posterior, 1 Laplace, 2 Laplace under the upright prior at 2°, the true
// gravity as the pipeline gives the VIO's), range bin (0 all, 1 below 6 m,
// 2 at 6 m and beyond). Reports the views per iteration and how many were accepted.
#include <benchmark/benchmark.h>

#include <vector>

#include "bench/bench_data.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/simulation/race_simulator.h"
#include "dualgraph/frontend/io/track_io.h"

namespace dualgraph {
namespace {

struct PnpView {
  GateCornerPixels pixels;
  GateSide side;
  double range;  ///< camera → gate centre [m], the truth
  Eigen::Vector3d up_in_camera;  ///< the gate's z axis (the track's gates stand upright), the truth
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

struct PnpViews {
  Status status;
  CameraModel camera;
  std::vector<PnpView, Eigen::aligned_allocator<PnpView>> views;
};

PnpViews simulateViews() {
  PnpViews out;
  Result<Track> track = loadTrackYaml(bench::repositoryDataPath("tracks/ratm_ellipse.yaml"));
  Result<CameraModel> camera = loadCameraYaml(bench::repositoryDataPath("cameras/ratm_piloted.yaml"));
  if (!track.ok() || !camera.ok()) {
    out.status = track.ok() ? camera.status() : track.status();
    return out;
  }
  RaceSimParams params;
  params.seed = 1;
  Result<SimulatedRace> race = simulateRace(*track, *camera, params);
  if (!race.ok()) {
    out.status = race.status();
    return out;
  }
  out.camera = *camera;
  for (const SimulatedDetection& d : race->detections) {
    if (d.kind != SimulatedDetectionKind::kTrue) continue;
    PnpView view;
    for (int i = 0; i < 4; ++i) view.pixels.col(i) = d.corners.corners[static_cast<size_t>(i)];
    view.side = d.seen_from_front ? GateSide::kFront : GateSide::kBack;
    const Eigen::Isometry3d camera_T_gate = camera->body_T_camera.inverse() * d.body_T_gate;
    view.range = camera_T_gate.translation().norm();
    view.up_in_camera = camera_T_gate.linear().col(2);
    out.views.push_back(view);
  }
  return out;
}

void BM_GatePnp_Solve(benchmark::State& state) {
  static const PnpViews data = simulateViews();
  if (!data.status.ok()) return state.SkipWithError(data.status.message().c_str());
  GatePnpParams params;
  params.covariance_model = state.range(0) == 0 ? PnpCovarianceModel::kTiltPosterior : PnpCovarianceModel::kLaplace;
  std::vector<const PnpView*> views;
  for (const PnpView& view : data.views) {
    if (state.range(1) == 0 || (state.range(1) == 1) == (view.range < 6.0)) views.push_back(&view);
  }
  int accepted = 0;
  for (auto _ : state) {
    accepted = 0;
    for (const PnpView* view : views) {
      const UprightGatePrior upright{view->up_in_camera, 2.0 * M_PI / 180.0};
      const GatePnpSolution solution =
          solveGatePnp(view->pixels, data.camera, view->side, params, state.range(0) == 2 ? &upright : nullptr);
      accepted += solution.ok() ? 1 : 0;
      benchmark::DoNotOptimize(solution.covariance.data());
    }
  }
  state.counters["views"] = static_cast<double>(views.size());
  state.counters["accepted"] = accepted;
  state.counters["us_per_view"] = benchmark::Counter(static_cast<double>(views.size()) * state.iterations(),
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_GatePnp_Solve)
    ->ArgNames({"model", "bin"})
    ->ArgsProduct({{0, 1, 2}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dualgraph
