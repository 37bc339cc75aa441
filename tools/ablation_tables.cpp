// SPDX-License-Identifier: MIT
#include "tools/ablation_tables.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "dualgraph/core/atomic_file.h"

namespace dualgraph::tools {
namespace {

/// Mean and sample standard deviation.
std::pair<double, double> meanStd(const std::vector<double>& v) {
  double sum = 0.0, sq = 0.0;
  for (double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  for (double x : v) sq += (x - mean) * (x - mean);
  return {mean, v.size() > 1 ? std::sqrt(sq / static_cast<double>(v.size() - 1)) : std::nan("")};  // no spread of one
}

/// A CSV field: the number, or empty where there is none (the spread of one run).
std::string csvNumber(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s << v;
  return s.str();
}

/// "mean ± std", or "mean (1 run)" where a spread cannot be had.
std::string pm(const std::vector<double>& v, int digits) {
  if (v.size() == 1) return formatFixed(v.front(), digits) + " (1 run)";
  const auto [mean, sd] = meanStd(v);
  return formatFixed(mean, digits) + " ± " + formatFixed(sd, digits);
}

Status writeText(const std::filesystem::path& path, const std::string& text) {
  return writeFileAtomically(path.string(), [&](std::ostream& out) {
    out << text;
    return Status();
  });
}

}  // namespace

Status writeAblationTables(const std::filesystem::path& out, const std::vector<AblationRow>& rows) {
  if (rows.empty()) return Status(StatusCode::kInvalidArgument, "ablation: no runs");
  const std::string first_profile = rows.front().profile;
  std::vector<std::string> profiles, tracks, variants;
  auto note = [](std::vector<std::string>& seen, const std::string& name) {
    if (std::find(seen.begin(), seen.end(), name) == seen.end()) seen.push_back(name);
  };
  for (const AblationRow& r : rows) {
    note(profiles, r.profile);
    note(tracks, r.track);
    note(variants, r.variant);
  }
  std::ostringstream md, t1, t2, t3, t4, all;

  md << "# Ablation (`dualgraph ablation`)\n\nTables I–III on the `" << first_profile
     << "` profile (`given`: the sequence folders given, as they are); Table IV every profile side by side. Each run's "
        "folder is under `runs/PROFILE/TRACK_seedN/` (given: `runs/given/FOLDER/`; `dualgraph report --run ...`).\n";
  t1 << "track,configuration,ate_m,nodes,edges,opt_ms_p95\n";
  for (const std::string& track : tracks) {  // one Table I per track, its first seed
    int seed = 0;
    for (const AblationRow& r : rows) {
      if (r.profile == first_profile && r.track == track) {
        seed = r.seed;
        break;
      }
    }
    md << "\n## Table I — " << track << (seed > 0 ? ", seed " + std::to_string(seed) : std::string())
       << "\n\n| configuration | ATE [m] | nodes | edges | Opt P95 [ms] |\n|---|---:|---:|---:|---:|\n";
    bool vio_row = false;
    for (const AblationRow& r : rows) {
      if (r.profile != first_profile || r.track != track || r.seed != seed) continue;
      if (!vio_row) {
        md << "| VIO | " << formatFixed(r.metrics.vio.ate_se3_m, 3) << " | | | |\n";
        t1 << track << ",VIO," << r.metrics.vio.ate_se3_m << ",,,\n";
        vio_row = true;
      }
      const RunMetrics& m = r.metrics;
      md << "| " << r.variant << " | " << formatFixed(m.estimate.ate_se3_m, 3) << " | " << m.nodes << " | " << m.edges << " | "
         << formatFixed(m.opt_ms_p95, 2) << " |\n";
      t1 << track << ',' << r.variant << ',' << m.estimate.ate_se3_m << ',' << m.nodes << ',' << m.edges << ','
         << m.opt_ms_p95 << '\n';
    }
  }

  md << "\n## Table II — ATE over seeds (mean ± std)\n\n| track | configuration | translation [m] | rotation [deg] | runs |\n"
        "|---|---|---:|---:|---:|\n";
  t2 << "track,configuration,ate_m_mean,ate_m_std,ate_rot_deg_mean,ate_rot_deg_std,runs\n";
  for (const std::string& track : tracks) {
    std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> by_variant;
    std::vector<double> vio_t, vio_r;
    std::vector<int> vio_seeds;
    for (const AblationRow& r : rows) {
      if (r.profile != first_profile || r.track != track) continue;
      by_variant[r.variant].first.push_back(r.metrics.estimate.ate_se3_m);
      by_variant[r.variant].second.push_back(r.metrics.estimate.ate_rot_deg);
      if (std::find(vio_seeds.begin(), vio_seeds.end(), r.seed) == vio_seeds.end()) {
        vio_seeds.push_back(r.seed);
        vio_t.push_back(r.metrics.vio.ate_se3_m);
        vio_r.push_back(r.metrics.vio.ate_rot_deg);
      }
    }
    auto emit = [&](const std::string& name, const std::vector<double>& t, const std::vector<double>& rot) {
      const auto [tm, ts] = meanStd(t);
      const auto [rm, rs] = meanStd(rot);
      md << "| " << track << " | " << name << " | " << pm(t, 3) << " | " << pm(rot, 2) << " | " << t.size() << " |\n";
      t2 << track << ',' << name << ',' << tm << ',' << csvNumber(ts) << ',' << rm << ',' << csvNumber(rs) << ',' << t.size() << '\n';
    };
    emit("VIO", vio_t, vio_r);
    for (const std::string& v : variants) emit(v, by_variant[v].first, by_variant[v].second);
  }

  // Table III as the paper's: one row per flight (the first profile's tracks and seeds, Dual 2.0/0.1), a column per
  // lap and the Full Track, mean ± std of the corrections at its gate crossings; the Average row: mean ± std over
  // the flights of each column's mean.
  std::vector<const AblationRow*> flights;
  size_t laps = 0;
  for (const AblationRow& r : rows) {
    if (r.profile != first_profile || r.variant != "Dual 2.0/0.1") continue;
    flights.push_back(&r);
    laps = std::max(laps, r.metrics.gate_corrections.size());
  }
  md << "\n## Table III — correction at gate crossings [m], Dual 2.0/0.1: corrected position "
     << "against the VIO put in the map at the lock, mean ± std per lap\n\n| flight |";
  for (size_t lap = 1; lap <= laps; ++lap) md << " Lap " << lap << " |";
  md << " Full Track |\n|---|";
  for (size_t lap = 0; lap <= laps; ++lap) md << "---:|";
  md << '\n';
  t3 << "flight,lap,crossings,mean_m,std_m\n";
  auto cell = [](const LapCorrection& c) {
    return c.crossings > 0 ? formatFixed(c.mean_m, 3) + " ± " + formatFixed(c.std_m, 3) : std::string("–");
  };
  std::vector<std::vector<double>> column_means(laps + 1);  // per lap, then the full track
  for (const AblationRow* r : flights) {
    const std::string name = r->seed > 0 ? r->track + " seed " + std::to_string(r->seed) : r->track;
    md << "| " << name << " |";
    for (size_t lap = 0; lap < laps; ++lap) {
      const bool flown = lap < r->metrics.gate_corrections.size();
      const LapCorrection c = flown ? r->metrics.gate_corrections[lap] : LapCorrection{};
      md << ' ' << cell(c) << " |";
      if (c.crossings > 0) column_means[lap].push_back(c.mean_m);
      if (flown) t3 << name << ',' << lap + 1 << ',' << c.crossings << ',' << csvNumber(c.mean_m) << ',' << csvNumber(c.std_m) << '\n';
    }
    const LapCorrection& full = r->metrics.full_track_correction;
    md << ' ' << cell(full) << " |\n";
    if (full.crossings > 0) column_means[laps].push_back(full.mean_m);
    t3 << name << ",full," << full.crossings << ',' << csvNumber(full.mean_m) << ',' << csvNumber(full.std_m) << '\n';
  }
  md << "| **Average** |";
  for (const std::vector<double>& means : column_means) md << ' ' << (means.empty() ? std::string("–") : pm(means, 3)) << " |";
  md << '\n';

  md << "\n## Table IV — ATE per profile (mean ± std over the seeds [m], mean reduction against the VIO)\n\n| track | "
        "configuration |";
  for (const std::string& profile : profiles) md << ' ' << profile << " |";
  md << "\n|---|---|";
  for (size_t i = 0; i < profiles.size(); ++i) md << "---:|";
  md << '\n';
  t4 << "track,configuration,profile,ate_m_mean,ate_m_std,reduction_pct_mean,runs\n";
  for (const std::string& track : tracks) {
    for (const std::string& variant : variants) {
      md << "| " << track << " | " << variant << " |";
      for (const std::string& profile : profiles) {
        std::vector<double> ate, reduction;
        for (const AblationRow& r : rows) {
          if (r.profile != profile || r.track != track || r.variant != variant) continue;
          ate.push_back(r.metrics.estimate.ate_se3_m);
          reduction.push_back(r.metrics.ate_reduction_pct);
        }
        const auto [am, as] = meanStd(ate);
        const double rm = meanStd(reduction).first;
        md << ' ' << pm(ate, 3) << " (" << formatFixed(rm, 1) << " %) |";
        t4 << track << ',' << variant << ',' << profile << ',' << am << ',' << csvNumber(as) << ',' << rm << ',' << ate.size() << '\n';
      }
      md << '\n';
    }
  }

  all << "profile,track,seed,configuration,ate_m,ate_unaligned_m,ate_4dof_m,ate_rot_deg,vio_ate_m,vio_ate_unaligned_m,"
         "vio_ate_rot_deg,keyframes,nodes,edges,opt_ms_p50,opt_ms_p95,opt_ms_max,detections,detections_used\n";
  for (const AblationRow& r : rows) {
    const RunMetrics& m = r.metrics;
    all << r.profile << ',' << r.track << ',' << r.seed << ',' << r.variant << ',' << m.estimate.ate_se3_m << ',' << m.estimate.ate_unaligned_m
        << ',' << m.estimate.ate_4dof_m << ',' << m.estimate.ate_rot_deg << ',' << m.vio.ate_se3_m << ','
        << m.vio.ate_unaligned_m << ',' << m.vio.ate_rot_deg << ',' << m.keyframes << ',' << m.nodes << ',' << m.edges
        << ',' << m.opt_ms_p50 << ',' << m.opt_ms_p95 << ',' << m.opt_ms_max << ',' << m.detections << ','
        << m.detections_used << '\n';
  }
  for (const auto& [name, text] : {std::pair{"tables.md", md.str()}, std::pair{"table1.csv", t1.str()},
                                   std::pair{"table2.csv", t2.str()}, std::pair{"table3.csv", t3.str()}, std::pair{"table4.csv", t4.str()},
                                   std::pair{"runs.csv", all.str()}}) {
    DG_RETURN_IF_ERROR(writeText(out / name, text));
  }
  return Status();
}

}  // namespace dualgraph::tools
