// SPDX-License-Identifier: MIT
// The simulated race the dual-graph benchmarks run on: the RATM ellipse (data/tracks/ratm_ellipse.yaml,
// 12 laps, ≈ 448 m, ≈ 95 s) flown by the race simulator with seed 1 and the RATM piloted camera
// (corner detections through PnP, as `dualgraph simulate` + `dualgraph run` do), made once per process
// in memory (raceSequence).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph::bench {

/// d_main [m] putting the keyframe count of this race near the paper's Table I rows (≈ 250 keyframes /
/// 1200 edges, ≈ 1000 / 4500, ≈ 1800 / 8600); the counts reached are in bench/README.md.
constexpr double kDMain250 = 2.8;
constexpr double kDMain1000 = 0.43;
constexpr double kDMain1800 = 0.225;

/// The sequence, simulated on first use (kept for the process).
const Result<Sequence>& ratmSequence();

/// `dualgraph simulate --track data/tracks/<track>.yaml --profile realistic --seed <seed>` in memory (the
/// track's own laps), made once per process and per (track, seed).
const Result<Sequence>& realisticRace(const std::string& track_name, std::uint64_t seed);

/// `dualgraph run`'s configuration (data/config/default.yaml) with d_main set, and main_window set when
/// `main_window` ≥ 0 (−1 keeps the configuration's).
Result<SequenceRunParams> raceRunParams(double d_main, int main_window);

/// runSequence's run (runSequenceWith) with a Localizer made here and returned after `finish`, so that its
/// main graph can be taken.
Result<std::unique_ptr<Localizer>> runRaceLocalizer(const Sequence& sequence, const SequenceRunParams& params);

}  // namespace dualgraph::bench
