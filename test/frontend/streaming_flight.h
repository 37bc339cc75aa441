// SPDX-License-Identifier: MIT
// The sequence replay's own input helpers (frontend/replay/sequence_run.h), named for the streaming tests.
#pragma once

#include "dualgraph/frontend/pipeline/streaming_localizer.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph::flighttest {

using ::dualgraph::detectionInstants;
using ::dualgraph::odometryInput;

}  // namespace dualgraph::flighttest
