// report: reads the experiment's artifacts (out/...) and writes results/report.md and CSVs.
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/share.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/pcd.h"
#include "report/baseline_section.h"
#include "report/families_section.h"
#include "report/report.h"

using namespace canopy;

namespace {

std::vector<std::string> words(const std::string& s) {
  std::istringstream ss(s);
  std::vector<std::string> out;
  for (std::string w; ss >> w;) out.push_back(w);
  return out;
}

bool exists(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0;
}

// scripts/stage.sh writes "<seconds> <peak KiB>" next to each artifact.
report::StageTime read_time(const std::string& artifact) {
  report::StageTime t;
  std::ifstream in(artifact + ".time");
  double kib = 0;
  if (in >> t.seconds >> kib) {
    t.peak_mb = kib / 1024.0;
    t.present = true;
  }
  return t;
}

std::string parent_dir(const std::string& path) {
  const std::string d = std::filesystem::path(path).parent_path().string();
  return d.empty() ? "." : d;
}

// `path` as seen from directory `from` (the report's links to the scene figures).
std::string relative_to(const std::string& path, const std::string& from) {
  return std::filesystem::path(path).lexically_proximate(from).generic_string();
}

// Number of views of a rendering: 1 + the largest view_idx of its scan.
int count_views(const std::string& scan) {
  if (!exists(scan)) return 0;
  const formats::PointCloud c = formats::read_pcd(scan);
  if (!c.has("view_idx")) return 0;
  double m = -1;
  for (double v : c.col("view_idx")) m = std::max(m, v);
  return static_cast<int>(m) + 1;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("report", "Write the experiment report (Markdown + CSV) from out/ artifacts.");
  tool.without_threads();
  std::string out_dir = "out", results = "results", objects, scenes, noises;
  std::string thesis;  // default: <share>/thesis/results.csv
  report::Params p;
  tool.add("--out", &out_dir, "experiment artifact directory");
  tool.add("--results", &results,
           "directory for report.md, cases.csv, scores.csv, times.csv, areas.csv, verdicts.csv");
  tool.add("--objects", &objects, "objects (space separated)")->required();
  tool.add("--scenes", &scenes, "scenes (space separated)")->required();
  tool.add("--noises", &noises, "noise levels in mm (space separated)")->required();
  tool.add("--thesis", &thesis, "the thesis's results table (CSV; default: share/thesis/results.csv)");
  std::string ablations;
  tool.add("--ablations", &ablations,
           "ablation variants, space separated NAME=STAGE+OPTIONS (results in OUT/ablation/NAME/)");
  std::string tile_score;
  tool.add(
      "--tile-score", &tile_score,
      "the scene experiment's score.json (canopy.scene_score v1): adds its section to report.md and writes "
      "times.csv beside it; its stages' .time files are found through its tiles");
  std::string families;
  tool.add("--families", &families,
           "the families protocol's results directory (confusion.csv, accuracy.csv from famscore; "
           "mk/families.mk): adds the \"Vehicle families\" section to report.md");
  tool.add("--max-segments", &p.max_segments, "largest object segments examined for spurious area");
  tool.add("--overseg-ratio", &p.overseg_ratio, "over-segmented when target segments exceed this x model's");
  tool.add("--missing-area-ratio", &p.missing_area_ratio,
           "missing area when target area is below this x model's");
  tool.add("--spurious-share", &p.spurious_share, "spurious when non-target area share exceeds this");
  return tool.run(argc, argv, [&] {
    // The six outputs are written together or not at all; their directory is checked now.
    const std::vector<std::string> names = {"report.md", "cases.csv", "scores.csv",
                                            "times.csv", "areas.csv", "verdicts.csv"};
    common::OutputSet outputs;
    for (const auto& n : names) outputs.add(results + "/" + n, "--results");
    // The scene experiment's figures and times.csv live beside its score.json.
    const std::string scene_dir = tile_score.empty() ? "" : parent_dir(tile_score);
    if (!tile_score.empty()) outputs.add(scene_dir + "/times.csv", "--tile-score");
    if (thesis.empty()) thesis = common::share_dir() + "/thesis/results.csv";
    common::log::Phase phase("read");
    report::Inputs in;
    in.objects = words(objects);
    in.scenes = words(scenes);
    for (const auto& n : words(noises)) {
      // Decimal only: std::stoi read "0x10" as 0 and "8mm" as 8.
      const std::string problem = common::detail::check_integer(n, true, 0, 1000000);
      if (!problem.empty()) throw common::UsageError("--noises: " + problem + " (noise levels in whole mm)");
      in.noises.push_back(std::stoi(n));
    }
    if (in.objects.empty() || in.scenes.empty() || in.noises.empty()) {
      throw common::UsageError("--objects, --scenes and --noises must each name at least one");
    }
    in.thesis = report::parse_thesis_csv(common::read_file(thesis), thesis);
    for (const auto& o : in.objects) {
      const std::string mb = out_dir + "/modelbase/" + o + ".json";
      if (exists(mb)) in.models[o] = formats::read_segment_graph(mb);
      for (const auto& s : in.scenes) {
        in.render_times[o + "/" + s] = read_time(out_dir + "/" + o + "/" + s + "/scan.pcd");
        for (int n : in.noises) {
          report::Case c;
          c.object = o;
          c.scene = s;
          c.noise_mm = n;
          const std::string dir = out_dir + "/" + o + "/" + s + "/noise-" + std::to_string(n);
          c.match = formats::read_match_result(dir + "/match.json");
          c.segments = formats::read_segment_graph(dir + "/segments.json");
          c.times["addnoise"] = read_time(dir + "/scan.pcd");
          c.times["fitvox"] = read_time(dir + "/samples.pcd");
          c.times["cocone"] = read_time(dir + "/mesh.ply");
          c.times["ncut"] = read_time(dir + "/segments.json");
          c.times["gmatch"] = read_time(dir + "/match.json");
          c.times["verify"] = read_time(dir + "/verdict.json");
          c.areas = report::read_areas(dir + "/areas.json");
          // verify's answer: absent = not run; empty = verify failed (scripts/stage.sh
          // --record-failure), counted as a failed trial.
          const std::string verdict = dir + "/verdict.json";
          if (exists(verdict)) {
            const std::string text = common::read_file(verdict);
            if (text.empty()) {
              c.verdict_status = report::VerdictStatus::failed;
            } else {
              c.verdict = formats::parse_verdict(text, verdict);
              c.verdict_status = report::VerdictStatus::read;
            }
          }
          in.cases.push_back(std::move(c));
        }
      }
    }
    for (const auto& spec : words(ablations)) {
      const auto eq = spec.find('=');
      report::Ablation a;
      a.name = spec.substr(0, eq);
      a.change = eq == std::string::npos ? "" : spec.substr(eq + 1);
      std::replace(a.change.begin(), a.change.end(), '+', ' ');
      for (const auto& o : in.objects) {
        for (const auto& s : in.scenes) {
          for (int n : in.noises) {
            const std::string path = out_dir + "/ablation/" + a.name + "/" + o + "/" + s + "/noise-" +
                                     std::to_string(n) + "/match.json";
            // An empty match.json records a stage that failed in this variant (scripts/stage.sh
            // --record-failure): the trial counts as not recognised (rank 0).
            const std::string text = common::read_file(path);
            int rank = 0;
            if (text.empty()) {
              a.correct_rank[o + "/" + s + "/" + std::to_string(n)] = 0;
              ++a.failed;
              continue;
            }
            const formats::MatchResult m = formats::parse_match_result(text, path);
            for (const auto& ms : m.models) {
              if (ms.model == o) rank = ms.rank;
            }
            a.correct_rank[o + "/" + s + "/" + std::to_string(n)] = rank;
          }
        }
      }
      in.ablations.push_back(std::move(a));
    }
    for (const auto& s : in.scenes) {
      in.render_views[s] = count_views(out_dir + "/" + in.objects.front() + "/" + s + "/scan.pcd");
    }
    for (const auto& s : in.scenes) in.figures.push_back("figures/grid-" + s + ".png");
    in.figures.push_back("figures/scores.png");
    for (const auto& o : in.objects) in.figures.push_back("pictures/" + o + ".png");
    // The thesis's scene picture (Fig. 2.4; Makefile.experiments `pictures`) when its object and
    // scene are in the experiment.
    const auto has = [](const std::vector<std::string>& v, const char* x) {
      return std::find(v.begin(), v.end(), x) != v.end();
    };
    if (has(in.objects, "tank") && has(in.scenes, "circle")) in.figures.push_back("pictures/tank-circle.png");
    phase.done(std::to_string(in.cases.size()) + " trials, " + std::to_string(in.models.size()) + " models");
    const report::Output r = report::run(in, p);
    // The PCL baseline beside canopy (issue 17), when the trials have baseline.json.
    const auto bl = report::baseline_section(out_dir, in.objects, in.scenes, in.noises);
    if (!bl.markdown.empty()) {
      outputs.add(results + "/baseline.csv", "--results");
      outputs.set(results + "/baseline.csv", bl.csv);
    }
    std::string markdown = r.markdown + bl.markdown;
    if (!families.empty()) {
      const std::string confusion = families + "/confusion.csv", accuracy = families + "/accuracy.csv";
      for (const auto& f : {confusion, accuracy}) {
        if (!exists(f))
          throw common::DataError(f, "missing (--families: run `make -f Makefile.experiments families`)");
      }
      markdown += report::families_markdown(report::summarize_families(
          common::read_file(confusion), confusion, common::read_file(accuracy), accuracy));
    }
    if (!tile_score.empty()) {
      common::log::Phase scenes_phase("scenes");
      const auto score =
          formats::open_json_document(common::read_file(tile_score), tile_score, "canopy.scene_score");
      const auto times = report::scene_times(report::scene_runs(score));
      markdown += "\n" + report::scene_markdown(score, times, relative_to(scene_dir, results));
      outputs.set(scene_dir + "/times.csv", report::scene_times_csv(times));
      scenes_phase.done(std::to_string(report::scene_runs(score).size()) + " runs");
    }
    outputs.set(results + "/report.md", markdown);
    outputs.set(results + "/cases.csv", r.cases_csv);
    outputs.set(results + "/scores.csv", r.scores_csv);
    outputs.set(results + "/times.csv", r.times_csv);
    outputs.set(results + "/areas.csv", r.areas_csv);
    outputs.set(results + "/verdicts.csv", r.verdicts_csv);
    outputs.commit();
    common::log::info("wrote " + results + "/report.md");
  });
}
