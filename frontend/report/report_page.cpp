// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/report_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/report/svg_plot.h"

namespace dualgraph {
namespace {

std::string reportCell(double value) {
  if (!std::isfinite(value)) return "n/a";
  char text[48];
  const bool integral = std::abs(value) < 1e15 && value == std::floor(value);
  std::snprintf(text, sizeof text, integral ? "%.0f" : "%.4g", value);
  return text;
}

// The unit a metrics.json key names by its suffix (frontend/evaluation/OUTPUTS.md).
std::string reportMetricUnit(const std::string& key) {
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

double reportMetric(const RunReport& run, const std::string& key) {
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
    for (const auto& column : kColumns) html << "<td>" << reportCell(reportMetric(run, column.first)) << "</td>";
    html << "</tr>\n";
  }
  html << "</table>\n";
}

void writeFigure(std::ostream& html, const XyPlot& plot, const std::string& caption, const std::string& empty_note) {
  if (!plotHasData(plot)) {
    html << "<p class=\"note\">" << escapeXml(empty_note) << "</p>\n";
    return;
  }
  auto svg = renderXyPlotSvg(plot);
  html << "<figure>\n" << (svg.ok() ? *svg : "") << "\n<figcaption>" << escapeXml(caption) << "</figcaption>\n</figure>\n";
}

void writeErrorStatistics(std::ostream& html, const RunPlots& plots) {
  html << "<h3>Position error [m]</h3>\n<table class=\"error-stats\">\n<tr><th></th>"
          "<th colspan=\"6\">no alignment (the map frame)</th><th colspan=\"6\">SE(3)-aligned (Umeyama, as evo_ape -a)</th>"
          "</tr>\n<tr><th></th>";
  for (int k = 0; k < 2; ++k) html << "<th>rmse</th><th>mean</th><th>median</th><th>std</th><th>min</th><th>max</th>";
  html << "</tr>\n";
  const auto row = [&](const std::string& name, const ErrorStatistics& raw, const ErrorStatistics& aligned) {
    html << "<tr><td>" << escapeXml(name) << "</td>";
    for (const ErrorStatistics* s : {&raw, &aligned}) {
      html << "<td>" << reportCell(s->rmse) << "</td><td>" << reportCell(s->mean) << "</td><td>" << reportCell(s->median) << "</td><td>"
           << reportCell(s->std) << "</td><td>" << reportCell(s->min) << "</td><td>" << reportCell(s->max) << "</td>";
    }
    html << "</tr>\n";
  };
  row("corrected", plots.corrected_stats, plots.corrected_stats_se3);
  row(plots.vio.label, plots.vio_stats, plots.vio_stats_se3);
  html << "</table>\n";
}

void writeLatencyTable(std::ostream& html, const RunReport& run) {
  html << "<h3>Time per keyframe [ms]</h3>\n<table class=\"latency\">\n<tr><th>graph</th><th>keyframes</th><th>P50</th>"
          "<th>P95</th><th>P99</th><th>max</th></tr>\n";
  for (const auto& [name, series] : {std::make_pair("main graph", &run.opt_ms), std::make_pair("temporary graph", &run.temp_ms)}) {
    const std::vector<double> values = valuesOf(*series);
    if (values.empty()) continue;
    html << "<tr><td>" << name << "</td><td>" << values.size() << "</td><td>" << reportCell(percentile(values, 50)) << "</td><td>"
         << reportCell(percentile(values, 95)) << "</td><td>" << reportCell(percentile(values, 99)) << "</td><td>"
         << reportCell(*std::max_element(values.begin(), values.end())) << "</td></tr>\n";
  }
  html << "</table>\n";
}

void writeTables(std::ostream& html, const RunReport& run) {
  if (run.metrics.empty()) {
    html << "<p class=\"note\">No metrics.json in the run folder.</p>\n";
  } else {
    html << "<h3>Metrics</h3>\n<table class=\"metrics\">\n<tr><th>metrics.json key</th><th>value</th><th>unit</th></tr>\n";
    for (const auto& [key, value] : run.metrics) {
      html << "<tr><td>" << escapeXml(key) << "</td><td>" << reportCell(value) << "</td><td>" << reportMetricUnit(key) << "</td></tr>\n";
    }
    html << "</table>\n";
  }
  if (run.gate_corrections.empty()) return;
  html << "<h3>Correction at the gate crossings per lap (against the VIO put in the map at the lock)</h3>\n"
          "<table class=\"gate-corrections\">\n"
          "<tr><th>lap</th><th>crossings</th><th>mean [m]</th><th>std [m]</th></tr>\n";
  for (const LapCorrection& lap : run.gate_corrections) {
    html << "<tr><td>" << lap.lap << "</td><td>" << lap.crossings << "</td><td>" << reportCell(lap.mean_m) << "</td><td>"
         << reportCell(lap.std_m) << "</td></tr>\n";
  }
  html << "</table>\n";
}

}  // namespace

std::string reportRunTitle(const RunReport& run) { return run.mode.empty() ? run.name : run.name + " (" + run.mode + ")"; }

bool plotHasData(const XyPlot& plot) {
  for (const PlotSeries& s : plot.series) {
    for (const Eigen::Vector2d& p : s.points) {
      if (p.allFinite()) return true;
    }
  }
  return false;
}

std::string renderReportPage(const std::vector<RunReport>& runs, const std::vector<RunPlots>& plots,
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
    writeFigure(html, overlay->xy,
                "Top view: every run's corrected estimate, the first run's ground truth (dashed black) and gates (grey).", "");
    writeFigure(html, overlay->error,
                "Position error of every run's corrected estimate, no alignment, on one time axis (" +
                    overlay->error.x_label + ").",
                "No ground truth: no error overlay.");
    writeFigure(html, overlay->latency, "Distribution of every run's main-graph optimisation time per keyframe.",
                "No stats.csv rows: no latency overlay.");
  }
  for (size_t i = 0; i < runs.size(); ++i) {
    const RunReport& run = runs[i];
    html << "<section id=\"run-" << escapeXml(run.name) << "\">\n<h2>" << escapeXml(reportRunTitle(run)) << "</h2>\n"
         << "<p class=\"note\">run folder " << escapeXml(run.run_dir) << "; sequence " << escapeXml(run.sequence_dir)
         << (run.thresholds.empty() ? "" : "; " + escapeXml(run.thresholds)) << "</p>\n";
    const RunPlots& p = plots[i];
    writeFigure(html, p.xy,
                "Top view: ground truth (dashed black), " + p.vio.label + " (orange), corrected estimate (blue), gates "
                "(grey); equal axes in metres. " + p.vio.note, "");
    writeFigure(html, p.error,
                "Position error against ground truth (interpolated at each trajectory's stamps), no alignment: the "
                "corrected estimate (blue) and " + p.vio.label + " (orange). " + p.vio.note,
                "No ground truth (gt.tum) in the sequence: no error plot.");
    if (p.has_errors) {
      writeFigure(html, p.error_corrected,
                  "The corrected estimate's error alone, no alignment, with its rmse (red), mean (green), median "
                  "(purple) and mean ± std (grey band), as evo_ape plots them.", "");
      writeFigure(html, p.error_vio,
                  "The error of " + p.vio.label + " alone, no alignment, with the same statistics. " + p.vio.note, "");
      writeErrorStatistics(html, p);
      writeFigure(html, p.error_map,
                  "Top view of the corrected estimate coloured by its position error (colour bar, metres), the "
                  "ground truth dashed black, gates grey.", "");
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

}  // namespace dualgraph
