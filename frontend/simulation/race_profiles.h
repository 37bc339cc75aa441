// SPDX-License-Identifier: MIT
// Named sets of simulation parameters: clean (the sensor models alone), realistic and harsh (a real flight's errors).
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/simulation/race_simulator.h"

namespace dualgraph {

/// The profile names, mildest first: "clean", "realistic", "harsh".
const std::vector<std::string>& simulationProfileNames();

/// Sets every parameter a profile fixes (the table in frontend/simulation/README.md) in `params`, leaving the
/// seed, laps, speed, rates, output and the other flight parameters alone (the whole detector is reset). clean:
/// the sensor models' defaults (1 px corners, whole gates only, VIO in the map's frame, exact calibration and
/// clock, every lap alike); realistic: 3 px corners plus 0.5 px per rad/s of blur, gates cut by the image border
/// reported with their 2-3 visible corners (partial_gates), 3 % displaced ones, 20 % misses, 1.5° camera-mount error, 15 ms camera clock offset, 5 cm / 1.5° map error, twice
/// the VIO drift, the VIO in its own frame (any yaw, up to 10 m away), laps varying by ±5 % in speed and 0.3 m in
/// line; harsh: 4 px + 1 px per rad/s, partial gates, 5 % displaced, 30 % misses at 15 Hz, 2°, 15 ms, 5 cm / 1.5°, three times
/// the drift, own frame, ±10 % and 0.5 m. kInvalidArgument naming the known profiles otherwise.
Status applySimulationProfile(const std::string& name, RaceSimParams& params);

/// The regimes real estimators bring, each over a profile: "good_vio", "mono_scale", "vio_clock", "epoch",
/// "big_hall".
const std::vector<std::string>& simulationRegimeNames();

/// Sets the few parameters a regime fixes (the second table in frontend/simulation/README.md) over whatever
/// `params` holds (a profile first): good_vio: the VIO's drift at 0.2 times the model's defaults (≈ 0.08–0.17 m per
/// 100 m flown); mono_scale: a scale error of 5.6–9.4 % (scale_error_bias 0.075) its covariance does not admit;
/// vio_clock: the VIO's stamps 50 ms behind the ground truth's and camera's clock; epoch: every stamp on Unix time
/// (time_origin 1764288000.125 s); big_hall: the track 2.5 times as wide (gates seen from 10–15 m). Several apply in
/// turn. kInvalidArgument naming the known regimes otherwise.
Status applySimulationRegime(const std::string& name, RaceSimParams& params);

}  // namespace dualgraph
