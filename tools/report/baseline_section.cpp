#include "report/baseline_section.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/documents/baseline_ranking.h"
#include "canopy/formats/csv_table.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/stage_outcome.h"
#include "canopy/documents/stage_time.h"
#include "report/report.h"

namespace canopy::report {
namespace {

using formats::format_number;

// The rank-1 model of each method in a canopy.baseline document ("" when the method is absent).
std::map<std::string, std::string> rank1(const std::string& text, const std::string& path) {
  std::map<std::string, std::string> out;
  for (const auto& m : documents::parse_baseline_ranking(text, path))
    out[m.method] = m.models.empty() ? "" : m.models.front().model;
  return out;
}

struct Tally {
  int n = 0, canopy = 0, verify = 0, vfh = 0, fpfh = 0;
};

// verify's answer in a trial's verdict.json: "" for none, a missing file or a failed run.
std::string verify_answer(const std::string& path) {
  const documents::StageVerdict v = documents::read_stage_verdict(path);
  return v.outcome == documents::StageOutcome::written ? v.verdict.model : "";
}

}  // namespace

namespace {

// Every trial's answers counted, and the per-trial CSV.
struct Counts {
  std::map<std::string, Tally> by_object;
  std::map<int, Tally> by_noise;
  std::map<std::string, Tally> by_scene;
  Tally all;
  int missing = 0, failed = 0, timed = 0, verified = 0;
  double seconds = 0, peak = 0, cpu = 0;
  int cpu_timed = 0;
  std::ostringstream csv;
};

// One trial: its baseline.json (absent: not counted), gmatch's and verify's answers, the time.
void count_trial(Counts& k, const std::string& dir, const std::string& o, const std::string& s, int n) {
  namespace fs = std::filesystem;
  const std::string path = dir + "/baseline.json";
  const documents::StageOutput baseline = documents::read_stage_output(path);
  if (baseline.outcome == documents::StageOutcome::missing) {
    ++k.missing;
    return;
  }
  std::map<std::string, std::string> r;
  if (baseline.outcome == documents::StageOutcome::failed) {
    ++k.failed;
  } else {
    r = rank1(baseline.text, path);
  }
  const documents::MatchResult m = documents::read_match_result(dir + "/match.json");
  const std::string canopy = m.models.empty() ? "" : m.models.front().model;
  const std::string verdict = dir + "/verdict.json";
  k.verified += fs::exists(verdict) ? 1 : 0;
  const std::string answer = verify_answer(verdict);
  const documents::StageTime t = documents::read_stage_time(path);
  if (t.present) {
    ++k.timed;
    k.seconds += t.seconds;
    k.peak = std::max(k.peak, t.peak_mb);
    if (t.has_cpu) {
      ++k.cpu_timed;
      k.cpu += t.cpu_seconds();
    }
  }
  const bool c = canopy == o, a = answer == o, v = r["vfh"] == o, f = r["fpfh"] == o;
  for (Tally* x : {&k.by_object[o], &k.by_noise[n], &k.by_scene[s], &k.all}) {
    ++x->n;
    x->canopy += c;
    x->verify += a;
    x->vfh += v;
    x->fpfh += f;
  }
  k.csv << o << ',' << s << ',' << n << ',' << canopy << ',' << c << ',' << answer << ',' << a << ','
        << r["vfh"] << ',' << v << ',' << r["fpfh"] << ',' << f << ','
        << (t.present ? format_number("%.3f", t.seconds) : "") << ','
        << (t.present ? format_number("%.1f", t.peak_mb) : "") << ','
        << (t.has_cpu ? format_number("%.3f", t.cpu_seconds()) : "") << '\n';
}

// A tally of the map, or an empty one (every trial of that key missing).
template <class Map, class Key>
Tally tally_of(const Map& m, const Key& key) {
  const auto it = m.find(key);
  return it == m.end() ? Tally{} : it->second;
}

// A row's rates with Wilson 95% intervals at `copies` trials per distinct render (the noise
// levels of an (object, scene) are copies of one render: a row pooling them has n / copies
// units; a row of one noise level, 1 copy).
void tally_row(std::ostringstream& md, const std::string& label, const Tally& x, double copies) {
  const double u = x.n / copies;
  md << "| " << label << " | " << x.n << " | " << rate_ci_units(x.canopy, x.n, u) << " | "
     << rate_ci_units(x.verify, x.n, u) << " | " << rate_ci_units(x.vfh, x.n, u) << " | "
     << rate_ci_units(x.fpfh, x.n, u) << " |\n";
}

std::string baseline_markdown(const Counts& k, const std::vector<std::string>& objects,
                              const std::vector<std::string>& scenes, const std::vector<int>& noises) {
  std::ostringstream md;
  md << "\n## PCL baseline beside canopy (issue 17)\n\n"
     << "`baseline` (tools/baseline, docs/decisions/baseline.md) on the same candidates (each trial's "
        "`samples.pcd` above the ground cut) and the same modelbase (`<model>.pcd` surfaces): **VFH** "
        "nearest model view (global) and **FPFH** correspondences + RANSAC + ICP ranked by fitness "
        "(local). canopy: gmatch's rank-1 model (`match.json`) and verify's answer (`verdict.json`; "
        "none or no verdict counts as wrong). Rank-1 = the true model answered first. Rates: k/n with "
        "Wilson's 95% interval at the distinct renders (the noise levels of an (object, scene) are copies "
        "of one render: rows pooling them have trials / noise levels units).\n\n";
  const double copies = static_cast<double>(std::max<std::size_t>(1, noises.size()));
  md << "| object | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |\n"
        "|---|---:|---:|---:|---:|---:|\n";
  for (const auto& o : objects) tally_row(md, o, tally_of(k.by_object, o), copies);
  tally_row(md, "all", k.all, copies);
  md << "\n| noise (mm) | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |\n"
        "|---:|---:|---:|---:|---:|---:|\n";
  for (int n : noises) tally_row(md, std::to_string(n), tally_of(k.by_noise, n), 1);
  md << "\n| scene | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |\n"
        "|---|---:|---:|---:|---:|---:|\n";
  for (const auto& s : scenes) tally_row(md, s, tally_of(k.by_scene, s), copies);
  md << "\nBaseline time (both methods, one process per trial): ";
  if (k.timed > 0) {
    md << "mean " << format_number("%.2f", k.seconds / k.timed) << " s wall per trial, total "
       << format_number("%.1f", k.seconds) << " s wall"
       << (k.cpu_timed > 0 ? ", CPU " + cpu_cell(format_number("%.1f", k.cpu) + " s", k.cpu_timed, k.timed) : "")
       << ", peak " << format_number("%.0f", k.peak) << " MB.";
  } else {
    md << "not recorded (no baseline.json.time).";
  }
  if (k.verified < k.all.n) md << " verify was not run on " << k.all.n - k.verified << " of them.";
  if (k.missing > 0) md << " " << k.missing << " trials have no baseline.json and are left out.";
  if (k.failed > 0) md << " " << k.failed << " baseline runs failed (empty baseline.json), counted as wrong.";
  md << " Per trial: `baseline.csv`.\n";
  return md.str();
}

}  // namespace

BaselineSection baseline_section(const documents::ExperimentManifest& manifest) {
  const auto& objects = manifest.objects;
  const auto& scenes = manifest.scenes;
  const auto& noises = manifest.noises;
  BaselineSection b;
  Counts k;
  k.csv << "object,scene,noise_mm,canopy_model,canopy_correct,verify_model,verify_correct,vfh_model,"
           "vfh_correct,fpfh_model,fpfh_correct,baseline_s,baseline_peak_mb,baseline_cpu_s\n";
  for (const auto& o : objects) {
    for (const auto& s : scenes) {
      for (int n : noises) count_trial(k, manifest.trial_dir(o, s, n), o, s, n);
    }
  }
  if (k.all.n == 0) return b;
  b.markdown = baseline_markdown(k, objects, scenes, noises);
  b.csv = k.csv.str();
  return b;
}

}  // namespace canopy::report
