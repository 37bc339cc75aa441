// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/run_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/report/plot_frame.h"
#include "dualgraph/frontend/report/svg_plot.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;

constexpr std::array<std::uint8_t, 3> kBlack{0, 0, 0}, kOrange{230, 120, 20}, kBlue{31, 119, 180};

bool hasData(const XyPlot& plot) {
  for (const PlotSeries& s : plot.series) {
    for (const Eigen::Vector2d& p : s.points) {
      if (p.allFinite()) return true;
    }
  }
  return false;
}

std::string runTitle(const RunReport& run) { return run.mode.empty() ? run.name : run.name + " (" + run.mode + ")"; }

// The XY canvas height that fits the data and gates at equal scales on the canvas width (400-900 px).
int xyHeight(XyPlot plot) {
  plot.equal_aspect = false;
  auto frame = plotFrame(plot);
  if (!frame.ok()) return plot.height;
  const Eigen::Vector2d span = frame->hi - frame->lo;
  const double plot_w = plot.width - PlotFrame::kLeft - PlotFrame::kRight;
  const double height = plot_w * span.y() / span.x() + PlotFrame::kTop + PlotFrame::kBottom;
  return static_cast<int>(std::clamp(height, 400.0, 900.0));
}

std::string cell(double value) {
  if (!std::isfinite(value)) return "n/a";
  char text[48];
  const bool integral = std::abs(value) < 1e15 && value == std::floor(value);
  std::snprintf(text, sizeof text, integral ? "%.0f" : "%.4g", value);
  return text;
}

// The unit a metrics.json key names by its suffix (frontend/evaluation/OUTPUTS.md).
std::string unitOf(const std::string& key) {
  const auto ends = [&](const std::string& suffix) {
    return key.size() >= suffix.size() && key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (key.find("_ms") != std::string::npos) return "ms";
  if (ends("_m")) return "m";
  if (ends("_deg")) return "deg";
  if (ends("_pct")) return "%";
  if (ends("_s")) return "s";
  return "";
}

double metric(const RunReport& run, const std::string& key) {
  for (const auto& [name, value] : run.metrics) {
    if (name == key) return value;
  }
  return NAN;
}

void writeComparison(std::ostream& html, const std::vector<RunReport>& runs) {
  static const std::vector<std::pair<std::string, std::string>> kColumns{
      {"ate_m", "ATE SE(3) [m]"}, {"ate_unaligned_m", "ATE unaligned [m]"}, {"ate_rot_deg", "rot. ATE [deg]"},
      {"vio_ate_m", "VIO ATE [m]"}, {"ate_reduction_pct", "reduction [%]"}, {"keyframes", "keyframes"},
      {"nodes", "nodes"}, {"edges", "edges"}, {"opt_ms_p95", "opt. P95 [ms]"}};
  html << "<h2>Comparison</h2>\n<table class=\"comparison\">\n<tr><th>run</th><th>mode</th>";
  for (const auto& column : kColumns) html << "<th>" << escapeXml(column.second) << "</th>";
  html << "</tr>\n";
  for (const RunReport& run : runs) {
    html << "<tr><td><a href=\"#run-" << escapeXml(run.name) << "\">" << escapeXml(run.name) << "</a></td><td>"
         << escapeXml(run.mode.empty() ? "?" : run.mode) << "</td>";
    for (const auto& column : kColumns) html << "<td>" << cell(metric(run, column.first)) << "</td>";
    html << "</tr>\n";
  }
  html << "</table>\n";
}

void writeFigure(std::ostream& html, const XyPlot& plot, const std::string& caption, const std::string& empty_note) {
  if (!hasData(plot)) {
    html << "<p class=\"note\">" << escapeXml(empty_note) << "</p>\n";
    return;
  }
  auto svg = renderXyPlotSvg(plot);
  html << "<figure>\n" << (svg.ok() ? *svg : "") << "\n<figcaption>" << escapeXml(caption) << "</figcaption>\n</figure>\n";
}

void writeErrorStatistics(std::ostream& html, const RunPlots& plots) {
  html << "<h3>Position error, unaligned [m]</h3>\n<table class=\"error-stats\">\n<tr><th></th><th>rmse</th><th>mean</th>"
          "<th>median</th><th>std</th><th>min</th><th>max</th></tr>\n";
  for (const auto& [name, s] : {std::make_pair("corrected", plots.corrected_stats), std::make_pair("VIO", plots.vio_stats)}) {
    html << "<tr><td>" << name << "</td><td>" << cell(s.rmse) << "</td><td>" << cell(s.mean) << "</td><td>" << cell(s.median)
         << "</td><td>" << cell(s.std) << "</td><td>" << cell(s.min) << "</td><td>" << cell(s.max) << "</td></tr>\n";
  }
  html << "</table>\n";
}

void writeLatencyTable(std::ostream& html, const RunReport& run) {
  html << "<h3>Time per keyframe [ms]</h3>\n<table class=\"latency\">\n<tr><th>graph</th><th>keyframes</th><th>P50</th>"
          "<th>P95</th><th>P99</th><th>max</th></tr>\n";
  for (const auto& [name, series] : {std::make_pair("main graph", &run.opt_ms), std::make_pair("temporary graph", &run.temp_ms)}) {
    const std::vector<double> values = valuesOf(*series);
    if (values.empty()) continue;
    html << "<tr><td>" << name << "</td><td>" << values.size() << "</td><td>" << cell(percentile(values, 50)) << "</td><td>"
         << cell(percentile(values, 95)) << "</td><td>" << cell(percentile(values, 99)) << "</td><td>"
         << cell(*std::max_element(values.begin(), values.end())) << "</td></tr>\n";
  }
  html << "</table>\n";
}

void writeTables(std::ostream& html, const RunReport& run) {
  if (run.metrics.empty()) {
    html << "<p class=\"note\">No metrics.json in the run folder.</p>\n";
  } else {
    html << "<h3>Metrics</h3>\n<table class=\"metrics\">\n<tr><th>metrics.json key</th><th>value</th><th>unit</th></tr>\n";
    for (const auto& [key, value] : run.metrics) {
      html << "<tr><td>" << escapeXml(key) << "</td><td>" << cell(value) << "</td><td>" << unitOf(key) << "</td></tr>\n";
    }
    html << "</table>\n";
  }
  if (run.gate_corrections.empty()) return;
  html << "<h3>Correction at the gate crossings per lap</h3>\n<table class=\"gate-corrections\">\n"
          "<tr><th>lap</th><th>crossings</th><th>mean [m]</th><th>std [m]</th></tr>\n";
  for (const LapCorrection& lap : run.gate_corrections) {
    html << "<tr><td>" << lap.lap << "</td><td>" << lap.crossings << "</td><td>" << cell(lap.mean_m) << "</td><td>"
         << cell(lap.std_m) << "</td></tr>\n";
  }
  html << "</table>\n";
}

std::string page(const std::vector<RunReport>& runs, const std::vector<RunPlots>& plots,
                 const std::optional<OverlayPlots>& overlay) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>dualgraph report</title>\n"
          "<style>\nbody{font-family:sans-serif;color:#222;max-width:1200px;margin:1.5em auto;padding:0 1em}\n"
          "table{border-collapse:collapse;margin:.5em 0 1.5em;font-size:14px}\n"
          "th,td{border:1px solid #ccc;padding:3px 8px;text-align:right}\n"
          "th:first-child,td:first-child{text-align:left}\nth{background:#f3f3f3}\n"
          "svg.plot{width:100%;height:auto;display:block}\nfigure{margin:1em 0 2em}\n"
          "figcaption,.note{color:#555;font-size:90%}\nsection{border-top:2px solid #ddd;margin-top:2em}\n"
          "</style>\n</head>\n<body>\n<h1>dualgraph report</h1>\n";
  if (runs.size() > 1) writeComparison(html, runs);
  if (overlay) {
    html << "<h2>Overlay</h2>\n";
    writeFigure(html, overlay->xy, "Top view: every run's corrected estimate, the first run's ground truth (dashed) and gates.", "");
    writeFigure(html, overlay->error, "Position error of every run's corrected estimate, unaligned.",
                "No ground truth: no error overlay.");
    writeFigure(html, overlay->latency, "Distribution of every run's main-graph optimisation time per keyframe.",
                "No stats.csv rows: no latency overlay.");
  }
  for (size_t i = 0; i < runs.size(); ++i) {
    const RunReport& run = runs[i];
    html << "<section id=\"run-" << escapeXml(run.name) << "\">\n<h2>" << escapeXml(runTitle(run)) << "</h2>\n"
         << "<p class=\"note\">run folder " << escapeXml(run.run_dir) << "; sequence " << escapeXml(run.sequence_dir)
         << (run.thresholds.empty() ? "" : "; " + escapeXml(run.thresholds)) << "</p>\n";
    writeFigure(html, plots[i].xy,
                "Top view: ground truth (dashed black), raw VIO (orange), corrected estimate (blue), gates (grey); "
                "equal axes in metres.", "");
    writeFigure(html, plots[i].error,
                "Position error against ground truth (interpolated at the estimate's stamps), no alignment.",
                "No ground truth (gt.tum) in the sequence: no error plot.");
    if (plots[i].has_errors) {
      writeFigure(html, plots[i].error_corrected, "The corrected estimate's error alone, on its own axis.", "");
      writeErrorStatistics(html, plots[i]);
      writeFigure(html, plots[i].error_map, "Top view of the corrected estimate coloured by its position error.", "");
    }
    writeFigure(html, plots[i].opt_ms, "Main-graph optimisation time at each keyframe (stats.csv).",
                "stats.csv has no rows: no optimisation-time plot.");
    writeFigure(html, plots[i].latency,
                "Distribution of the time per keyframe: main-graph optimisation and temporary graph (stats.csv).",
                "stats.csv has no rows: no latency distribution.");
    writeLatencyTable(html, run);
    writeTables(html, run);
    html << "</section>\n";
  }
  html << "</body>\n</html>\n";
  return html.str();
}

/// Every plot of a report: one RunPlots per run, and the overlay when there are several runs.
struct ReportPlots {
  std::vector<RunPlots> runs;
  std::optional<OverlayPlots> overlay;
};

Result<ReportPlots> allPlots(const std::vector<RunReport>& runs) {
  if (runs.empty()) return Status(StatusCode::kInvalidArgument, "a report needs at least one run");
  ReportPlots plots;
  for (const RunReport& run : runs) {
    auto made = makeRunPlots(run);
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

Result<RunPlots> makeRunPlots(const RunReport& run) {
  RunPlots plots;
  plots.xy.title = runTitle(run) + ": trajectories, top view";
  plots.xy.series.push_back({"VIO", xyOf(run.vio), kOrange, false});
  plots.xy.series.push_back({"corrected", xyOf(run.estimate), kBlue, false});
  // Drawn last so that its dashes stay visible over the corrected estimate.
  if (!run.ground_truth.empty()) plots.xy.series.push_back({"ground truth", xyOf(run.ground_truth), kBlack, true});
  for (const TrackGate& gate : run.gates) plots.xy.gates.push_back({gate.position.head<2>(), gate.yaw, gate.size});
  plots.xy.height = xyHeight(plots.xy);
  plots.xy.legend_above = true;

  const double t0 = reportTimeOrigin(run);
  char t_label[64] = "t [s]";
  if (t0 != 0.0) std::snprintf(t_label, sizeof t_label, "t [s] since %.3f s", t0);
  for (XyPlot* plot : {&plots.error, &plots.error_corrected, &plots.opt_ms}) {
    plot->equal_aspect = false;
    plot->x_label = t_label;
    plot->height = 450;
    plot->legend_above = true;
  }
  plots.error.title = runTitle(run) + ": position error, unaligned";
  plots.error_corrected.title = runTitle(run) + ": position error of the corrected estimate, unaligned";
  plots.error.y_label = plots.error_corrected.y_label = "[m]";
  if (!run.ground_truth.empty()) {
    const std::string gt = (fs::path(run.sequence_dir) / "gt.tum").string();
    auto vio = positionErrors(run.ground_truth, run.vio, t0);
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
    plots.error_map = errorColouredTopView(runTitle(run) + ": error along the path", *corrected,
                                           run.ground_truth, run.gates);
    plots.error_map.height = plots.xy.height;
    plots.error.series.push_back({"VIO", std::move(vio->over_time), kOrange, false});
    plots.error.series.push_back({"corrected", corrected->over_time, kBlue, false});
    plots.error_corrected.series.push_back({"corrected", std::move(corrected->over_time), kBlue, false});
  }
  plots.latency = latencyDistribution(runTitle(run) + ": time per keyframe",
                                      {{"main graph", valuesOf(run.opt_ms)}, {"temporary graph", valuesOf(run.temp_ms)}});
  plots.opt_ms.title = runTitle(run) + ": main-graph optimisation per keyframe";
  plots.opt_ms.y_label = "[ms]";
  PlotSeries ms{"optimisation", {}, kBlue, false};
  for (const auto& [t, value] : run.opt_ms) ms.points.emplace_back(t - t0, value);
  plots.opt_ms.series.push_back(std::move(ms));
  return plots;
}

Result<std::string> renderRunReportHtml(const std::vector<RunReport>& runs) {
  auto plots = allPlots(runs);
  if (!plots.ok()) return plots.status();
  return page(runs, plots->runs, plots->overlay);
}

Status writeRunReport(std::vector<RunReport> runs, const std::string& html_path, std::vector<std::string>* written) {
  std::set<std::string> names;
  for (RunReport& run : runs) {
    std::string safe = run.name.empty() ? "run" : run.name;
    for (char& c : safe) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    }
    run.name = safe;
    for (int k = 2; !names.insert(run.name).second; ++k) run.name = safe + "_" + std::to_string(k);
  }
  auto plots = allPlots(runs);
  if (!plots.ok()) return plots.status();
  const std::optional<OverlayPlots>& overlay = plots->overlay;
  const fs::path folder = fs::path(html_path).parent_path();
  auto writePng = [&](const std::string& name, const XyPlot& plot) {
    if (!hasData(plot)) return Status();
    const std::string path = (folder / name).string();
    DG_RETURN_IF_ERROR(writeXyPlotPng(path, plot));
    if (written != nullptr) written->push_back(path);
    return Status();
  };
  for (size_t i = 0; i < runs.size(); ++i) {
    const RunPlots& p = plots->runs[i];
    const std::pair<const char*, const XyPlot*> files[] = {
        {"_xy.png", &p.xy},         {"_error.png", &p.error},   {"_error_corrected.png", &p.error_corrected},
        {"_error_map.png", &p.error_map}, {"_opt_ms.png", &p.opt_ms}, {"_latency.png", &p.latency}};
    for (const auto& [suffix, plot] : files) DG_RETURN_IF_ERROR(writePng(runs[i].name + suffix, *plot));
  }
  if (overlay) {
    DG_RETURN_IF_ERROR(writePng("overlay_xy.png", overlay->xy));
    DG_RETURN_IF_ERROR(writePng("overlay_error.png", overlay->error));
    DG_RETURN_IF_ERROR(writePng("overlay_latency.png", overlay->latency));
  }
  const std::string html = page(runs, plots->runs, overlay);
  DG_RETURN_IF_ERROR(writeFileAtomically(html_path, [&](std::ostream& out) {
    out << html;
    return Status();
  }));
  if (written != nullptr) written->push_back(html_path);
  return Status();
}

}  // namespace dualgraph
