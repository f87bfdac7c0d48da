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
#include "canopy/formats/pcd.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/stage_time.h"
#include "report/baseline_section.h"
#include "report/families_section.h"
#include "report/real_section.h"
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

// Decimal only: std::stoi read "0x10" as 0 and "8mm" as 8.
std::vector<int> parse_noises(const std::string& text) {
  std::vector<int> noises;
  for (const auto& n : words(text)) {
    const std::string problem = common::detail::check_integer(n, true, 0, 1000000);
    if (!problem.empty()) throw common::UsageError("--noises: " + problem + " (noise levels in whole mm)");
    noises.push_back(std::stoi(n));
  }
  return noises;
}

// One trial's artifacts: OUT/<object>/<scene>/noise-<mm>/.
report::Case read_case(const std::string& out_dir, const std::string& o, const std::string& s, int n) {
  report::Case c;
  c.object = o;
  c.scene = s;
  c.noise_mm = n;
  const std::string dir = out_dir + "/" + o + "/" + s + "/noise-" + std::to_string(n);
  c.match = documents::read_match_result(dir + "/match.json");
  c.segments = documents::read_segment_graph(dir + "/segments.json");
  c.times["addnoise"] = documents::read_stage_time(dir + "/scan.pcd");
  c.times["fitvox"] = documents::read_stage_time(dir + "/samples.pcd");
  c.times["cocone"] = documents::read_stage_time(dir + "/mesh.ply");
  c.times["ncut"] = documents::read_stage_time(dir + "/segments.json");
  c.times["gmatch"] = documents::read_stage_time(dir + "/match.json");
  c.times["verify"] = documents::read_stage_time(dir + "/verdict.json");
  c.areas = report::read_areas(dir + "/areas.json");
  // verify's answer: absent = not run; empty = verify failed (scripts/stage.sh
  // --record-failure), counted as a failed trial.
  const std::string verdict = dir + "/verdict.json";
  if (exists(verdict)) {
    const std::string text = common::read_file(verdict);
    if (text.empty()) {
      c.verdict_status = report::VerdictStatus::failed;
    } else {
      c.verdict = documents::parse_verdict(text, verdict);
      c.verdict_status = report::VerdictStatus::read;
    }
  }
  return c;
}

// An ablation variant NAME=STAGE+OPTIONS: the rank of the right model in each of its trials
// (OUT/ablation/NAME/...).
report::Ablation read_ablation(const std::string& spec, const std::string& out_dir, const report::Inputs& in) {
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
        const documents::MatchResult m = documents::parse_match_result(text, path);
        for (const auto& ms : m.models) {
          if (ms.model == o) rank = ms.rank;
        }
        a.correct_rank[o + "/" + s + "/" + std::to_string(n)] = rank;
      }
    }
  }
  return a;
}

// The figures the report links (Makefile.experiments `figures`, `pictures`).
std::vector<std::string> figure_paths(const report::Inputs& in) {
  std::vector<std::string> figures;
  for (const auto& s : in.scenes) figures.push_back("figures/grid-" + s + ".png");
  figures.push_back("figures/scores.png");
  for (const auto& o : in.objects) figures.push_back("pictures/" + o + ".png");
  // The thesis's scene picture (Fig. 2.4; Makefile.experiments `pictures`) when its object and
  // scene are in the experiment.
  const auto has = [](const std::vector<std::string>& v, const char* x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  if (has(in.objects, "tank") && has(in.scenes, "circle")) figures.push_back("pictures/tank-circle.png");
  return figures;
}

// Everything the report reads from OUT (the experiment's artifacts) and the thesis table.
report::Inputs read_inputs(const std::string& out_dir, report::Inputs in, const std::string& thesis,
                           const std::string& ablations) {
  in.thesis = report::parse_thesis_csv(common::read_file(thesis), thesis);
  for (const auto& o : in.objects) {
    const std::string mb = out_dir + "/modelbase/" + o + ".json";
    if (exists(mb)) in.models[o] = documents::read_segment_graph(mb);
    for (const auto& s : in.scenes) {
      in.render_times[o + "/" + s] = documents::read_stage_time(out_dir + "/" + o + "/" + s + "/scan.pcd");
      for (int n : in.noises) in.cases.push_back(read_case(out_dir, o, s, n));
    }
  }
  for (const auto& spec : words(ablations)) in.ablations.push_back(read_ablation(spec, out_dir, in));
  for (const auto& s : in.scenes) {
    in.render_views[s] = count_views(out_dir + "/" + in.objects.front() + "/" + s + "/scan.pcd");
  }
  in.figures = figure_paths(in);
  return in;
}

// The families protocol's section (--families), from famscore's two tables.
std::string families_section(const std::string& families) {
  const std::string confusion = families + "/confusion.csv", accuracy = families + "/accuracy.csv";
  for (const auto& f : {confusion, accuracy}) {
    if (!exists(f))
      throw common::DataError(f, "missing (--families: run `make -f Makefile.experiments families`)");
  }
  return report::families_markdown(report::summarize_families(common::read_file(confusion), confusion,
                                                              common::read_file(accuracy), accuracy));
}

// The scene experiment's section (--tile-score); its times.csv goes beside score.json.
std::string scenes_section(const std::string& tile_score, const std::string& scene_dir,
                           const std::string& results, common::OutputSet& outputs) {
  common::log::Phase scenes_phase("scenes");
  const documents::SceneScore score = documents::read_scene_score_file(tile_score);
  const auto times = report::scene_times(report::scene_runs(score));
  const std::string markdown = "\n" + report::scene_markdown(score, times, relative_to(scene_dir, results));
  outputs.set(scene_dir + "/times.csv", report::scene_times_csv(times));
  scenes_phase.done(std::to_string(report::scene_runs(score).size()) + " runs");
  return markdown;
}

// The real tiles' section (--real): per tile OUT_REAL/<name>/ and its labels, when
// LABELS/<name>.truth.json exists.
std::string real_section(const std::string& real_dir, const std::string& names, const std::string& labels,
                         int timeout_s) {
  common::log::Phase real_phase("real tiles");
  std::vector<report::RealTile> tiles;
  for (const auto& name : words(names)) {
    const std::string truth = labels + "/" + name + ".truth.json";
    tiles.push_back(report::read_real_tile({name, real_dir + "/" + name, exists(truth) ? truth : ""}));
  }
  real_phase.done(std::to_string(tiles.size()) + " tiles");
  return "\n" + report::real_markdown(tiles, timeout_s);
}

// The options beside the trials' sources.
struct Sources {
  std::string out_dir = "out", results = "results", objects, scenes, noises;
  std::string thesis;  // default: <share>/thesis/results.csv
  std::string ablations, tile_score, families;
  std::string real, real_tiles, real_labels = "share/real";
  int real_timeout = 0;
};

void bind(common::Tool& tool, Sources& src, report::Params& p) {
  tool.add("--out", &src.out_dir, "experiment artifact directory");
  tool.add("--results", &src.results,
           "directory for report.md, cases.csv, scores.csv, times.csv, areas.csv, verdicts.csv");
  tool.add("--objects", &src.objects, "objects (space separated)")->required();
  tool.add("--scenes", &src.scenes, "scenes (space separated)")->required();
  tool.add("--noises", &src.noises, "noise levels in mm (space separated)")->required();
  tool.add("--thesis", &src.thesis, "the thesis's results table (CSV; default: share/thesis/results.csv)");
  tool.add("--ablations", &src.ablations,
           "ablation variants, space separated NAME=STAGE+OPTIONS (results in OUT/ablation/NAME/)");
  tool.add(
      "--tile-score", &src.tile_score,
      "the scene experiment's score.json (canopy.scene_score v1): adds its section to report.md and writes "
      "times.csv beside it; its stages' .time files are found through its tiles");
  tool.add("--families", &src.families,
           "the families protocol's results directory (confusion.csv, accuracy.csv from famscore; "
           "mk/families.mk): adds the \"Vehicle families\" section to report.md");
  tool.add(
      "--real", &src.real,
      "the real tiles' directory (mk/real.mk: <dir>/<tile>/{tile.time, detections.json, score.json, ...}): "
      "adds the \"Real tiles\" section to report.md");
  tool.add("--real-tiles", &src.real_tiles, "the real tiles' names in the section's order (space separated)");
  tool.add("--real-labels", &src.real_labels,
           "directory of the real tiles' hand labels <tile>.truth.json (a tile without one has no vehicles)");
  tool.add("--real-timeout", &src.real_timeout,
           "the time box of a real tile, s (mk/real.mk REAL_TIMEOUT; 0 unknown)");
  tool.add("--max-segments", &p.max_segments, "largest object segments examined for spurious area");
  tool.add("--overseg-ratio", &p.overseg_ratio, "over-segmented when target segments exceed this x model's");
  tool.add("--missing-area-ratio", &p.missing_area_ratio,
           "missing area when target area is below this x model's");
  tool.add("--spurious-share", &p.spurious_share, "spurious when non-target area share exceeds this");
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("report", "Write the experiment report (Markdown + CSV) from out/ artifacts.");
  tool.without_threads();
  Sources src;
  report::Params p;
  bind(tool, src, p);
  return tool.run(argc, argv, [&] {
    report::validate(p);
    // The six outputs are written together or not at all; their directory is checked now.
    const std::string& results = src.results;
    common::OutputSet outputs;
    for (const char* n : {"report.md", "cases.csv", "scores.csv", "times.csv", "areas.csv", "verdicts.csv"})
      outputs.add(results + "/" + n, "--results");
    // The scene experiment's figures and times.csv live beside its score.json.
    const std::string scene_dir = src.tile_score.empty() ? "" : parent_dir(src.tile_score);
    if (!src.tile_score.empty()) outputs.add(scene_dir + "/times.csv", "--tile-score");
    if (src.thesis.empty()) src.thesis = common::share_dir() + "/thesis/results.csv";
    common::log::Phase phase("read");
    report::Inputs layout;
    layout.objects = words(src.objects);
    layout.scenes = words(src.scenes);
    layout.noises = parse_noises(src.noises);
    if (layout.objects.empty() || layout.scenes.empty() || layout.noises.empty()) {
      throw common::UsageError("--objects, --scenes and --noises must each name at least one");
    }
    const report::Inputs in = read_inputs(src.out_dir, std::move(layout), src.thesis, src.ablations);
    phase.done(std::to_string(in.cases.size()) + " trials, " + std::to_string(in.models.size()) + " models");
    const report::Outputs r = report::run(p, in);
    // The PCL baseline beside canopy (issue 17), when the trials have baseline.json.
    const auto bl = report::baseline_section(src.out_dir, in.objects, in.scenes, in.noises);
    if (!bl.markdown.empty()) {
      outputs.add(results + "/baseline.csv", "--results");
      outputs.set(results + "/baseline.csv", bl.csv);
    }
    std::string markdown = r.markdown + bl.markdown;
    if (!src.families.empty()) markdown += families_section(src.families);
    if (!src.tile_score.empty()) markdown += scenes_section(src.tile_score, scene_dir, results, outputs);
    if (!src.real.empty()) {
      if (words(src.real_tiles).empty())
        throw common::UsageError("--real needs --real-tiles (the tiles' names)");
      if (src.real_timeout < 0) throw common::UsageError("--real-timeout: must be >= 0 s");
      markdown += real_section(src.real, src.real_tiles, src.real_labels, src.real_timeout);
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
