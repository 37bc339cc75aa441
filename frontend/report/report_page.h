// SPDX-License-Identifier: MIT
// The report's HTML page from its plots (run_report.h builds them): tables, figures with their captions. No I/O.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dualgraph/frontend/report/run_report.h"

namespace dualgraph {

/// A run's title in plots and headings: "name (mode)", or the name alone without a mode.
std::string reportRunTitle(const RunReport& run);

/// Whether `plot` has a finite point to draw (else it is left out of the page and no PNG is written).
bool plotHasData(const XyPlot& plot);

/// The self-contained page (inline CSS and SVG, no scripts) of `runs` with their `plots` (one per run, same
/// order) and, for several runs, their `overlay`; captions say what each plot draws and in which frame.
std::string renderReportPage(const std::vector<RunReport>& runs, const std::vector<RunPlots>& plots,
                             const std::optional<OverlayPlots>& overlay);

}  // namespace dualgraph
