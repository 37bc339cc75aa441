// SPDX-License-Identifier: MIT
// PyLocalizer, behind Python's dualgraph.Localizer, and numpy conversions of gates and poses.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <vector>

#include "dualgraph/dual_graph/localizer.h"

namespace dualgraph::python {

/// The Python `dualgraph.Localizer`: owns a Localizer; every rejection raises with the library's message.
class PyLocalizer {
 public:
  static std::unique_ptr<PyLocalizer> create(const LocalizerParams& params, pybind11::handle gates);

  /// world_T_body at t as (7,) or (4, 4).
  pybind11::array_t<double> addOdometry(double t, pybind11::handle odom_T_body, pybind11::handle covariance, bool as_matrix);
  void addObservation(const GateObservation& observation);
  void finish();
  pybind11::tuple keyframes() const;
  pybind11::list stats() const { return statsToList(localizer_->keyframeStats()); }
  pybind11::dict counters() const { return countersToDict(localizer_->counters()); }
  const Localizer& get() const { return *localizer_; }
  void observationsCompleteUntil(double t) { localizer_->observationsCompleteUntil(t); }

  static pybind11::list statsToList(const std::vector<KeyframeStats>& stats);
  static pybind11::dict countersToDict(const LocalizerCounters& counters);

 private:
  explicit PyLocalizer(std::unique_ptr<Localizer> localizer) : localizer_(std::move(localizer)) {}
  std::unique_ptr<Localizer> localizer_;
};

/// {id: world_T_gate} (ids ≥ 0; poses (7,) or (4, 4)) → GateMap.
GateMap toGateMap(pybind11::handle gates);
/// (times (n,), poses (n, 7)).
pybind11::tuple stampedPoses(const std::vector<CorrectedPose>& poses);

}  // namespace dualgraph::python
