// SPDX-License-Identifier: MIT
// The paper's Tables I–III (Markdown and CSV) from the ablation's per-run metrics.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"

namespace dualgraph::tools {

/// The metrics of one (track, seed, configuration) run of the ablation.
struct AblationRow {
  std::string profile;  ///< the simulation profile: clean, realistic or harsh
  std::string track;
  int seed = 0;
  std::string variant;  ///< e.g. "Dual 2.0/0.1" (d_main/d_temp [m]) or "Single 0.5" (d_single [m])
  RunMetrics metrics;
};

/// Writes the paper's tables from the rows (Tables I–III on the first profile; Table I per track on its first
/// seed, Table III a row per flight: every track and seed, or given folder):
///  - table1.csv / Table I: per track, every configuration with ATE (SE(3)-aligned) [m], nodes, edges, Opt P95 [ms];
///  - table2.csv / Table II: per track, VIO and every configuration, ATE translation [m] and rotation
///    [deg] as mean ± sample std over the seeds ("mean (1 run)" and an empty CSV std for one seed);
///  - table3.csv / Table III: as the paper's, Dual 2.0/0.1, one row per flight (seed): the correction at gate
///    crossings (RunMetrics::gate_corrections: against the VIO put in the map at the lock) per lap and over the
///    Full Track, mean ± std [m], and an Average row (mean ± sample std over the flights of each column's mean);
///    CSV `flight,lap,crossings,mean_m,std_m` (lap `full`: the whole flight);
///  - table4.csv / Table IV: per track and configuration, every profile side by side: ATE mean ± std [m] and
///    the mean reduction against the VIO [%];
///  - runs.csv: every row with every metric; tables.md: the four tables in Markdown.
Status writeAblationTables(const std::filesystem::path& out, const std::vector<AblationRow>& rows);

}  // namespace dualgraph::tools
