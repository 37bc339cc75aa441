// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/replay/self_calibration.h"

namespace dualgraph {

Result<SequenceRunResult> runSequenceSelfCalibrating(const Sequence& sequence, const SequenceRunParams& params,
                                                      const RunProgress& progress, SelfCalibrationReport* report) {
  Result<SequenceRunResult> run = runSequence(sequence, params, progress);
  if (report != nullptr) *report = run.ok() ? run->self_calibration : SelfCalibrationReport{};
  return run;
}

}  // namespace dualgraph
