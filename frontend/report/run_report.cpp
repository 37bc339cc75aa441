// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/run_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/report/plot_frame.h"
#include "dualgraph/frontend/report/report_page.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;

constexpr std::array<std::uint8_t, 3> kBlack{0, 0, 0}, kOrange{230, 120, 20}, kBlue{31, 119, 180};

// The XY canvas height that fits the data and gates at equal scales on the canvas width (400-900 px).
int xyHeight(XyPlot plot) {
  plot.equal_aspect = false;
  auto frame = plotFrame(plot);
  if (!frame.ok()) return plot.height;
  const Eigen::Vector2d span = frame->hi - frame->lo;
  const double plot_w = plot.width - PlotFrame::kLeft - frame->right;
  const double height = plot_w * span.y() / span.x() + PlotFrame::kTop + PlotFrame::kBottom;
  return static_cast<int>(std::clamp(height, 400.0, 900.0));
}

/// Every plot of a report: one RunPlots per run, and the overlay when there are several runs.
struct ReportPlots {
  std::vector<RunPlots> runs;
  std::optional<OverlayPlots> overlay;
};

Result<ReportPlots> allPlots(const std::vector<RunReport>& runs, const RunReportOptions& options) {
  if (runs.empty()) return Status(StatusCode::kInvalidArgument, "a report needs at least one run");
  ReportPlots plots;
  for (const RunReport& run : runs) {
    auto made = makeRunPlots(run, options);
    if (!made.ok()) return made.status();
    plots.runs.push_back(std::move(*made));
  }
  if (runs.size() > 1) {
    auto overlay = makeOverlayPlots(runs);
    if (!overlay.ok()) return overlay.status();
    plots.overlay = std::move(*overlay);
  }
  return plots;
}

}  // namespace

Result<RunPlots> makeRunPlots(const RunReport& run, const RunReportOptions& options) {
  RunPlots plots;
  const std::string title = reportRunTitle(run);
  const double t0 = reportTimeOrigin(run);
  plots.time_origin = t0;
  plots.vio = vioForReport(run, options.vio_frame, t0);
  plots.xy.title = title + ": trajectories, top view";
  plots.xy.series.push_back({plots.vio.label, xyOf(plots.vio.poses), kOrange, false});
  plots.xy.series.push_back({"corrected", xyOf(run.estimate), kBlue, false});
  // Drawn last so that its dashes stay visible over the corrected estimate.
  if (!run.ground_truth.empty()) plots.xy.series.push_back({"ground truth", xyOf(run.ground_truth), kBlack, true});
  for (const TrackGate& gate : run.gates) plots.xy.gates.push_back({gate.position.head<2>(), gate.yaw, gate.size});
  plots.xy.height = xyHeight(plots.xy);
  plots.xy.legend_above = true;

  const std::string t_label = timeAxisLabel(t0);
  plots.error.equal_aspect = plots.opt_ms.equal_aspect = false;
  plots.error.height = plots.opt_ms.height = 450;
  plots.error.legend_above = plots.opt_ms.legend_above = true;
  plots.error.x_label = plots.opt_ms.x_label = t_label;
  plots.error.title = title + ": position error, no alignment";
  plots.error.y_label = "[m]";
  if (!run.ground_truth.empty()) {
    const std::string gt = run.gt_path.empty() ? (fs::path(run.sequence_dir) / "gt.tum").string() : run.gt_path;
    auto vio = positionErrors(run.ground_truth, plots.vio.poses, t0);
    if (!vio.ok()) {
      const std::string file = run.vio_path.empty() ? (fs::path(run.sequence_dir) / "vio.tum").string() : run.vio_path;
      return Status(vio.status().code(), file + " against " + gt + ": " + vio.status().message());
    }
    auto corrected = positionErrors(run.ground_truth, run.estimate, t0);
    if (!corrected.ok()) {
      const std::string file = (fs::path(run.run_dir) / "estimate.tum").string();
      return Status(corrected.status().code(), file + " against " + gt + ": " + corrected.status().message());
    }
    plots.has_errors = true;
    plots.corrected_stats = corrected->stats;
    plots.vio_stats = vio->stats;
    plots.corrected_stats_se3 = alignedErrorStatistics(run.ground_truth, run.estimate);
    plots.vio_stats_se3 = alignedErrorStatistics(run.ground_truth, run.vio);  // the same in any frame
    plots.error_map = errorColouredTopView(title + ": corrected estimate coloured by its error", *corrected,
                                           run.ground_truth, run.gates);
    plots.error_map.height = plots.xy.height;
    plots.error_corrected =
        errorOverTime(title + ": position error of the corrected estimate, no alignment", "corrected", *corrected, kBlue);
    plots.error_vio = errorOverTime(title + ": position error of " + plots.vio.label + ", no alignment",
                                    plots.vio.label, *vio, kOrange);
    plots.error_corrected.x_label = plots.error_vio.x_label = t_label;
    plots.error.series.push_back({plots.vio.label, std::move(vio->over_time), kOrange, false});
    plots.error.series.push_back({"corrected", std::move(corrected->over_time), kBlue, false});
  }
  plots.latency = latencyDistribution(title + ": time per keyframe",
                                      {{"main graph", valuesOf(run.opt_ms)}, {"temporary graph", valuesOf(run.temp_ms)}});
  plots.opt_ms.title = title + ": main-graph optimisation per keyframe";
  plots.opt_ms.y_label = "[ms]";
  PlotSeries ms{"optimisation", {}, kBlue, false};
  for (const auto& [t, value] : run.opt_ms) ms.points.emplace_back(t - t0, value);
  plots.opt_ms.series.push_back(std::move(ms));
  return plots;
}

Result<std::string> renderRunReportHtml(const std::vector<RunReport>& runs, const RunReportOptions& options) {
  auto plots = allPlots(runs, options);
  if (!plots.ok()) return plots.status();
  return renderReportPage(runs, plots->runs, plots->overlay);
}

Status writeRunReport(std::vector<RunReport> runs, const std::string& html_path, std::vector<std::string>* written,
                      const RunReportOptions& options) {
  std::set<std::string> names;
  for (RunReport& run : runs) {
    std::string safe = run.name.empty() ? "run" : run.name;
    for (char& c : safe) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    }
    run.name = safe;
    for (int k = 2; !names.insert(run.name).second; ++k) run.name = safe + "_" + std::to_string(k);
  }
  auto plots = allPlots(runs, options);
  if (!plots.ok()) return plots.status();
  const std::optional<OverlayPlots>& overlay = plots->overlay;
  const fs::path folder = fs::path(html_path).parent_path();
  auto writePng = [&](const std::string& name, const XyPlot& plot) {
    if (!plotHasData(plot)) return Status();
    const std::string path = (folder / name).string();
    DG_RETURN_IF_ERROR(writeXyPlotPng(path, plot));
    if (written != nullptr) written->push_back(path);
    return Status();
  };
  for (size_t i = 0; i < runs.size(); ++i) {
    const RunPlots& p = plots->runs[i];
    const std::pair<const char*, const XyPlot*> files[] = {
        {"_xy.png", &p.xy},           {"_error.png", &p.error},         {"_error_corrected.png", &p.error_corrected},
        {"_error_vio.png", &p.error_vio}, {"_error_map.png", &p.error_map}, {"_opt_ms.png", &p.opt_ms},
        {"_latency.png", &p.latency}};
    for (const auto& [suffix, plot] : files) DG_RETURN_IF_ERROR(writePng(runs[i].name + suffix, *plot));
  }
  if (overlay) {
    DG_RETURN_IF_ERROR(writePng("overlay_xy.png", overlay->xy));
    DG_RETURN_IF_ERROR(writePng("overlay_error.png", overlay->error));
    DG_RETURN_IF_ERROR(writePng("overlay_latency.png", overlay->latency));
  }
  const std::string html = renderReportPage(runs, plots->runs, overlay);
  DG_RETURN_IF_ERROR(writeFileAtomically(html_path, [&](std::ostream& out) {
    out << html;
    return Status();
  }));
  if (written != nullptr) written->push_back(html_path);
  return Status();
}

}  // namespace dualgraph
