#include "report/baseline_section.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/csv_table.h"
#include "canopy/formats/match_result.h"

namespace canopy::report {
namespace {

using formats::format_number;

std::string rate(int k, int n) {
  if (n == 0) return "–";
  return std::to_string(k) + "/" + std::to_string(n) + " (" + format_number("%.0f%%", 100.0 * k / n) + ")";
}

// The rank-1 model of each method in a canopy.baseline document ("" when the method is absent).
std::map<std::string, std::string> rank1(const std::string& text, const std::string& path) {
  std::map<std::string, std::string> out;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) { throw common::DataError(path, std::string("not JSON: ") + e.what()); }
  if (j.value("format", "") != "canopy.baseline")
    throw common::DataError(path, "not a canopy.baseline document");
  for (const auto& m : j.at("methods")) {
    const auto& models = m.at("models");
    out[m.at("method").get<std::string>()] = models.empty() ? "" : models[0].at("model").get<std::string>();
  }
  return out;
}

struct Tally {
  int n = 0, canopy = 0, verify = 0, vfh = 0, fpfh = 0;
};

// verify's answer in a trial's verdict.json: "" for none, a missing file or a failed run.
std::string verify_answer(const std::string& path) {
  if (!std::filesystem::exists(path)) return "";
  const std::string text = common::read_file(path);
  if (text.empty()) return "";
  try {
    const auto j = nlohmann::json::parse(text);
    return j.contains("model") && j["model"].is_string() ? j["model"].get<std::string>() : "";
  } catch (const std::exception& e) { throw common::DataError(path, std::string("not JSON: ") + e.what()); }
}

}  // namespace

BaselineSection baseline_section(const std::string& out_dir, const std::vector<std::string>& objects,
                                 const std::vector<std::string>& scenes, const std::vector<int>& noises) {
  namespace fs = std::filesystem;
  BaselineSection b;
  std::ostringstream csv;
  csv << "object,scene,noise_mm,canopy_model,canopy_correct,verify_model,verify_correct,vfh_model,"
         "vfh_correct,fpfh_model,fpfh_correct,baseline_s,baseline_peak_mb\n";
  std::map<std::string, Tally> by_object;
  std::map<int, Tally> by_noise;
  std::map<std::string, Tally> by_scene;
  Tally all;
  int missing = 0, failed = 0, timed = 0, verified = 0;
  double seconds = 0, peak = 0;
  for (const auto& o : objects) {
    for (const auto& s : scenes) {
      for (int n : noises) {
        const std::string dir = out_dir + "/" + o + "/" + s + "/noise-" + std::to_string(n);
        const std::string path = dir + "/baseline.json";
        if (!fs::exists(path)) {
          ++missing;
          continue;
        }
        const std::string text = common::read_file(path);
        std::map<std::string, std::string> r;
        if (text.empty()) {
          ++failed;
        } else {
          r = rank1(text, path);
        }
        const formats::MatchResult m = formats::read_match_result(dir + "/match.json");
        const std::string canopy = m.models.empty() ? "" : m.models.front().model;
        const std::string verdict = dir + "/verdict.json";
        verified += fs::exists(verdict) ? 1 : 0;
        const std::string answer = verify_answer(verdict);
        double sec = 0, kib = 0;
        std::ifstream t(path + ".time");
        const bool has_time = static_cast<bool>(t >> sec >> kib);
        if (has_time) {
          ++timed;
          seconds += sec;
          peak = std::max(peak, kib / 1024.0);
        }
        const bool c = canopy == o, a = answer == o, v = r["vfh"] == o, f = r["fpfh"] == o;
        for (Tally* x : {&by_object[o], &by_noise[n], &by_scene[s], &all}) {
          ++x->n;
          x->canopy += c;
          x->verify += a;
          x->vfh += v;
          x->fpfh += f;
        }
        csv << o << ',' << s << ',' << n << ',' << canopy << ',' << c << ',' << answer << ',' << a << ','
            << r["vfh"] << ',' << v << ',' << r["fpfh"] << ',' << f << ','
            << (has_time ? format_number("%.3f", sec) : "") << ','
            << (has_time ? format_number("%.1f", kib / 1024.0) : "") << '\n';
      }
    }
  }
  if (all.n == 0) return b;
  std::ostringstream md;
  md << "\n## PCL baseline beside canopy (issue 17)\n\n"
     << "`baseline` (tools/baseline, docs/decisions/baseline.md) on the same candidates (each trial's "
        "`samples.pcd` above the ground cut) and the same modelbase (`<model>.pcd` surfaces): **VFH** "
        "nearest model view (global) and **FPFH** correspondences + RANSAC + ICP ranked by fitness "
        "(local). canopy: gmatch's rank-1 model (`match.json`) and verify's answer (`verdict.json`; "
        "none or no verdict counts as wrong). Rank-1 = the true model answered first.\n\n";
  md << "| object | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |\n"
        "|---|---:|---:|---:|---:|---:|\n";
  for (const auto& o : objects) {
    const Tally& x = by_object[o];
    md << "| " << o << " | " << x.n << " | " << rate(x.canopy, x.n) << " | " << rate(x.verify, x.n) << " | "
       << rate(x.vfh, x.n) << " | " << rate(x.fpfh, x.n) << " |\n";
  }
  md << "| all | " << all.n << " | " << rate(all.canopy, all.n) << " | " << rate(all.verify, all.n) << " | "
     << rate(all.vfh, all.n) << " | " << rate(all.fpfh, all.n) << " |\n\n";
  md << "| noise (mm) | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |\n"
        "|---:|---:|---:|---:|---:|---:|\n";
  for (int n : noises) {
    const Tally& x = by_noise[n];
    md << "| " << n << " | " << x.n << " | " << rate(x.canopy, x.n) << " | " << rate(x.verify, x.n) << " | "
       << rate(x.vfh, x.n) << " | " << rate(x.fpfh, x.n) << " |\n";
  }
  md << "\n| scene | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |\n"
        "|---|---:|---:|---:|---:|---:|\n";
  for (const auto& s : scenes) {
    const Tally& x = by_scene[s];
    md << "| " << s << " | " << x.n << " | " << rate(x.canopy, x.n) << " | " << rate(x.verify, x.n) << " | "
       << rate(x.vfh, x.n) << " | " << rate(x.fpfh, x.n) << " |\n";
  }
  md << "\nBaseline time (both methods, one process per trial): ";
  if (timed > 0) {
    md << "mean " << format_number("%.2f", seconds / timed) << " s wall per trial, total "
       << format_number("%.1f", seconds) << " s, peak " << format_number("%.0f", peak) << " MB.";
  } else {
    md << "not recorded (no baseline.json.time).";
  }
  if (verified < all.n) md << " verify was not run on " << all.n - verified << " of them.";
  if (missing > 0) md << " " << missing << " trials have no baseline.json and are left out.";
  if (failed > 0) md << " " << failed << " baseline runs failed (empty baseline.json), counted as wrong.";
  md << " Per trial: `baseline.csv`.\n";
  b.markdown = md.str();
  b.csv = csv.str();
  return b;
}

}  // namespace canopy::report
