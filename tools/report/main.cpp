// report: reads the experiment's artifacts (where its manifest says) and writes results/report.md and CSVs.
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/share.h"
#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/stage_outcome.h"
#include "canopy/documents/stage_time.h"
#include "report/baseline_section.h"
#include "report/density_section.h"
#include "report/disk_section.h"
#include "report/openset_section.h"
#include "report/families_section.h"
#include "report/real_section.h"
#include "report/report.h"

using namespace canopy;

namespace {

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

// One trial's artifacts, in the directory the manifest names (its stages' outputs by name).
report::Case read_case(const documents::ManifestTrial& t) {
  report::Case c;
  c.object = t.object;
  c.scene = t.scene;
  c.noise_mm = t.noise_mm;
  const std::string& dir = t.path;
  c.match = documents::read_match_result(dir + "/match.json");
  c.segments = documents::read_segment_graph(dir + "/segments.json");
  c.times["addnoise"] = documents::read_stage_time(dir + "/scan.pcd");
  c.times["fitvox"] = documents::read_stage_time(dir + "/samples.pcd");
  c.times["cocone"] = documents::read_stage_time(dir + "/mesh.ply");
  c.times["ncut"] = documents::read_stage_time(dir + "/segments.json");
  c.times["gmatch"] = documents::read_stage_time(dir + "/match.json");
  c.times["verify"] = documents::read_stage_time(dir + "/verdict.json");
  c.areas = report::read_areas(dir + "/areas.json");
  // verify's answer: absent = not run; empty = verify failed (tools/stagerun
  // --record-failure), counted as a failed trial (documents/stage_outcome.h).
  const documents::StageVerdict v = documents::read_stage_verdict(dir + "/verdict.json");
  if (v.outcome == documents::StageOutcome::failed) c.verdict_status = report::VerdictStatus::failed;
  if (v.outcome == documents::StageOutcome::written) {
    c.verdict = v.verdict;
    c.verdict_status = report::VerdictStatus::read;
  }
  return c;
}

// An ablation variant: the rank of the right model in each of its trials.
report::Ablation read_ablation(const documents::ManifestAblation& spec) {
  report::Ablation a;
  a.name = spec.name;
  a.change = spec.change;
  for (const auto& t : spec.trials) {
    const std::string key = t.object + "/" + t.scene + "/" + std::to_string(t.noise_mm);
    // An empty match.json records a stage that failed in this variant (tools/stagerun
    // --record-failure): the trial counts as not recognised (rank 0).
    const std::string text = common::read_file(t.path);
    int rank = 0;
    if (text.empty()) {
      a.correct_rank[key] = 0;
      ++a.failed;
      continue;
    }
    const documents::MatchResult m = documents::parse_match_result(text, t.path);
    for (const auto& ms : m.models) {
      if (ms.model == t.object) rank = ms.rank;
    }
    a.correct_rank[key] = rank;
  }
  return a;
}

// Everything the report reads of the thesis protocol (the manifest's trials, models, renders,
// ablations and figures) and the thesis table.
report::Inputs read_inputs(const documents::ExperimentManifest& m, const std::string& thesis) {
  report::Inputs in;
  in.objects = m.objects;
  in.scenes = m.scenes;
  in.noises = m.noises;
  in.thesis = report::parse_thesis_csv(common::read_file(thesis), thesis);
  for (const auto& [object, graph] : m.models) {
    if (exists(graph)) in.models[object] = documents::read_segment_graph(graph);
  }
  for (const auto& [key, scan] : m.renders) in.render_times[key] = documents::read_stage_time(scan);
  // The cases in grid order (objects x scenes x noises), whatever the manifest's line order.
  for (const auto& o : in.objects) {
    for (const auto& s : in.scenes) {
      for (int n : in.noises) {
        for (const auto& t : m.trials) {
          if (t.object == o && t.scene == s && t.noise_mm == n) in.cases.push_back(read_case(t));
        }
      }
    }
  }
  for (const auto& a : m.ablations) in.ablations.push_back(read_ablation(a));
  for (const auto& s : in.scenes) {
    const auto r = m.renders.find(in.objects.front() + "/" + s);
    in.render_views[s] = r == m.renders.end() ? 0 : report::render_views(r->second);
  }
  in.figures = m.figures;
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

// The score.json an option names, or none when the option is empty.
std::optional<documents::SceneScore> optional_score(const std::string& path) {
  if (path.empty()) return std::nullopt;
  return documents::read_scene_score_file(path);
}

// An open-set classify ablation: its name (report's openset_classify_ablation_names), its tiles'
// score.json and its crops' ("" when not given).
struct NamedAblation {
  std::string name, tiles, crops;
};

// An open-set classify ablation's subsection from its tiles' score.json and, when given, its crops'.
std::string openset_classify_ablation_section(const NamedAblation& a) {
  const std::optional<documents::SceneScore> c = optional_score(a.crops);
  return report::openset_classify_ablation_markdown(a.name, documents::read_scene_score_file(a.tiles),
                                                    a.tiles, c ? &*c : nullptr, a.crops);
}

// An open-set collect ablation's subsection from its tiles' score.json, its crops' when given and
// its options (report's openset_collect_ablation_markdown).
std::string openset_collect_ablation_section(const std::string& tiles, const std::string& crops,
                                             const std::string& options) {
  const std::optional<documents::SceneScore> c = optional_score(crops);
  return report::openset_collect_ablation_markdown(documents::read_scene_score_file(tiles), tiles,
                                                   c ? &*c : nullptr, crops, options);
}

// A classify ablation of the scene experiment (--tile-classify-ablation[-2] and its -config).
struct ClassifyAblationArgs {
  std::string score, config;
};
// The option of the scene experiment's i-th classify ablation (0: the first, 1: the second).
std::string classify_ablation_option(std::size_t i) {
  return i == 0 ? "--tile-classify-ablation" : "--tile-classify-ablation-2";
}

// An option given without the one it builds on: a usage error naming both.
void needs(const std::string& given, const std::string& given_option, const std::string& base,
           const std::string& base_option) {
  if (base.empty() && !given.empty()) throw common::UsageError(given_option + " needs " + base_option);
}

// The scene experiment's section (--tile-score); its times.csv goes beside score.json.
std::string scenes_section(const std::string& tile_score, const std::string& collect_ablation,
                           const std::vector<ClassifyAblationArgs>& classify_ablations,
                           const std::string& verify_ablation, const std::string& verify_ablation_options,
                           const std::vector<std::string>* baselines, const std::string& scene_dir,
                           const std::string& results, common::OutputSet& outputs) {
  common::log::Phase scenes_phase("scenes");
  const documents::SceneScore score = documents::read_scene_score_file(tile_score);
  const auto times = report::scene_times(report::scene_runs(score));
  const std::optional<documents::SceneScore> ablation = optional_score(collect_ablation);
  std::vector<std::optional<documents::SceneScore>> classify_scores;
  for (const auto& a : classify_ablations) classify_scores.push_back(optional_score(a.score));
  std::vector<report::SceneClassifyAblation> classify;
  for (std::size_t i = 0; i < classify_ablations.size(); ++i)
    classify.push_back({classify_ablations[i].config, classify_ablations[i].score,
                        classify_scores[i] ? &*classify_scores[i] : nullptr});
  const std::optional<documents::SceneScore> verify_all = optional_score(verify_ablation);
  const std::string markdown =
      "\n" + report::scene_markdown(
                 score, times, relative_to(scene_dir, results), ablation ? &*ablation : nullptr,
                 collect_ablation, classify,
                 {verify_ablation_options, verify_ablation, verify_all ? &*verify_all : nullptr}, baselines);
  outputs.set(scene_dir + "/times.csv", report::scene_times_csv(times));
  scenes_phase.done(std::to_string(report::scene_runs(score).size()) + " runs");
  return markdown;
}

// The real tiles' section: the manifest's real tiles in its order.
std::string real_section(const std::vector<documents::ManifestRealTile>& real, int timeout_s) {
  common::log::Phase real_phase("real tiles");
  std::vector<report::RealTile> tiles;
  // classify's k-th ablation (k = 0, 1, …), beside the tiles that have one, and its parameters
  std::vector<std::vector<report::RealTile>> ablations;
  std::vector<std::string> configs;
  for (const auto& r : real) {
    tiles.push_back(report::read_real_tile({r.name, r.dir, r.truth}));
    for (std::size_t k = 0; k < r.ablations.size(); ++k) {
      if (ablations.size() <= k) {
        ablations.emplace_back();
        configs.push_back(r.ablations[k].config);
      }
      ablations[k].push_back(report::read_real_tile({r.name, r.ablations[k].dir, r.truth}));
    }
  }
  real_phase.done(std::to_string(tiles.size()) + " tiles");
  std::string md = "\n" + report::real_markdown(tiles, timeout_s);
  for (std::size_t k = 0; k < ablations.size(); ++k)
    md += report::real_ablation_markdown(tiles, ablations[k], configs[k], static_cast<int>(k));
  return md;
}

// The density ladder's section (the manifest's `density` records); its table as ladder.csv in the
// directory above the levels' score directories (results/density/), when a level has run.
std::string density_section(const std::vector<documents::ManifestDensity>& density,
                            const std::vector<documents::ManifestDensity>& density_sensor,
                            const std::string& results, common::OutputSet& outputs) {
  common::log::Phase density_phase("density ladder");
  const std::vector<report::DensityLevel> levels = report::read_density_levels(density);
  const std::vector<report::DensityLevel> sensor = report::read_density_levels(density_sensor);
  std::vector<std::string> figures;
  for (const auto& l : levels) {
    if (!l.scored) continue;
    const std::string dir = parent_dir(parent_dir(l.score_path));
    for (const char* part : {"all", "rates", "errors"}) {
      const std::string csv =
          dir + (std::string(part) == "all" ? "/ladder.csv" : "/ladder-" + std::string(part) + ".csv");
      outputs.add(csv, "--manifest");
      outputs.set(csv, report::density_csv(levels, part));
    }
    figures = {relative_to(dir, results) + "/ladder-rates.png",
               relative_to(dir, results) + "/ladder-errors.png"};
    break;
  }
  density_phase.done(std::to_string(levels.size()) + " levels, " + std::to_string(sensor.size()) +
                     " on the sensor");
  return report::density_markdown(levels, figures, sensor);
}

// The options beside the trials' sources.
struct Sources {
  std::string manifest, results = "results";
  std::string thesis;  // default: <share>/thesis/results.csv
  std::string tile_collect_ablation;
  std::string tile_verify_ablation, tile_verify_ablation_options;
  std::string openset_verify_ablation, openset_verify_ablation_options;
  std::vector<std::string> tile_baselines;  // --tile-baselines (tile_baselines_given: it was given)
  bool tile_baselines_given = false;
  // the open set's collect ablations in order: each one's score.json, options and crops' score.json
  std::vector<std::string> openset_collect_ablations, openset_collect_ablation_options,
      openset_crops_collect_ablations;
  std::vector<ClassifyAblationArgs> tile_classify_ablations = std::vector<ClassifyAblationArgs>(2);
  // the open set's classify ablations in order, each NAME=SCORE, and their crops' (NAME=SCORE)
  std::vector<std::string> openset_classify_ablations, openset_crops_classify_ablations;
  std::string tile_score, families, disk, openset, openset_crops, openset_distances;
  int real_timeout = 0;
};

// The open set's collect ablations' options: each needs --openset; the crops' and the options,
// when given, one per ablation (the options may be left out for a single one); every options
// text is collect options.
void check_collect_ablations(const Sources& src) {
  const std::size_t n = src.openset_collect_ablations.size();
  if (n > 0 && src.openset.empty()) throw common::UsageError("--openset-collect-ablation needs --openset");
  if (n == 0 && !src.openset_crops_collect_ablations.empty())
    throw common::UsageError("--openset-crops-collect-ablation needs --openset-collect-ablation");
  if (n == 0 && !src.openset_collect_ablation_options.empty())
    throw common::UsageError("--openset-collect-ablation-options needs --openset-collect-ablation");
  const auto count = [&](const std::vector<std::string>& v, const std::string& option, bool optional_one) {
    if (v.empty() && (optional_one ? n <= 1 : true)) return;
    if (v.size() != n)
      throw common::UsageError(option + " given " + std::to_string(v.size()) +
                               " times: one per --openset-collect-ablation (" + std::to_string(n) + ")");
  };
  count(src.openset_crops_collect_ablations, "--openset-crops-collect-ablation", false);
  count(src.openset_collect_ablation_options, "--openset-collect-ablation-options", true);
  for (const std::string& o : src.openset_collect_ablation_options) report::collect_ablation_options(o);
}

// NAME=SCORE of `option` split at its first "=": a usage error naming the option when either side
// is empty or the name is not an ablation's.
std::pair<std::string, std::string> named_score(const std::string& arg, const std::string& option) {
  const std::size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == arg.size())
    throw common::UsageError(option + ": \"" + arg + "\" is not NAME=SCORE");
  const std::string name = arg.substr(0, eq);
  const auto& names = report::openset_classify_ablation_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw common::UsageError(option + ": no ablation named \"" + name + "\" (the names: " + known + ")");
  }
  return {name, arg.substr(eq + 1)};
}

// The open set's classify ablations in the order given, each with its crops' score when given:
// each needs --openset, a name once, and a crops' score only for a name given to the tiles.
std::vector<NamedAblation> classify_ablations(const Sources& src) {
  if (!src.openset_classify_ablations.empty() && src.openset.empty())
    throw common::UsageError("--openset-classify-ablation needs --openset");
  std::vector<NamedAblation> out;
  for (const std::string& arg : src.openset_classify_ablations) {
    const auto [name, score] = named_score(arg, "--openset-classify-ablation");
    for (const NamedAblation& a : out)
      if (a.name == name) throw common::UsageError("--openset-classify-ablation: " + name + " given twice");
    out.push_back({name, score, ""});
  }
  for (const std::string& arg : src.openset_crops_classify_ablations) {
    const auto [name, score] = named_score(arg, "--openset-crops-classify-ablation");
    const auto a = std::find_if(out.begin(), out.end(), [&](const NamedAblation& x) { return x.name == name; });
    if (a == out.end())
      throw common::UsageError("--openset-crops-classify-ablation " + name +
                               " needs --openset-classify-ablation " + name);
    if (!a->crops.empty())
      throw common::UsageError("--openset-crops-classify-ablation: " + name + " given twice");
    a->crops = score;
  }
  return out;
}

void bind(common::Tool& tool, Sources& src, report::Params& p) {
  tool.add("--manifest", &src.manifest,
           "the experiment's manifest (Makefile.experiments writes out/experiment.txt; "
           "documents/experiment_manifest.h): the trials, models, renders, ablations, figures and real tiles")
      ->required();
  tool.add("--results", &src.results,
           "directory for report.md, cases.csv, scores.csv, times.csv, areas.csv, verdicts.csv");
  tool.add("--thesis", &src.thesis, "the thesis's results table (CSV; default: share/thesis/results.csv)");
  tool.add(
      "--tile-score", &src.tile_score,
      "the scene experiment's score.json (canopy.scene_score v1): adds its section to report.md and writes "
      "times.csv beside it; its stages' .time files are found through its tiles");
  tool.add("--tile-collect-ablation", &src.tile_collect_ablation,
           "the scene experiment's collect ablation's score.json (mk/scenes.mk SCENE_COLLECT_ABLATION: "
           "collect --coarse-none-below 0, one none map): its reliability table beside canopy's");
  tool.add("--tile-verify-ablation", &src.tile_verify_ablation,
           "the scene experiment's verify ablation's score.json (mk/scenes.mk SCENES_VERIFY_ABLATION, "
           "--top-k=3: verify on gmatch's top 3, the default before stop 65): a row beside the baseline's "
           "methods and "
           "what gmatch adds (with --tile-verify-ablation-options)");
  tool.add("--tile-verify-ablation-options", &src.tile_verify_ablation_options,
           "the verify options that ablation ran with (shown in the report)");
  tool.add("--tile-baselines", &src.tile_baselines,
           "the scene experiment's baseline methods that ran, comma-separated (vfh, fpfh, size, fpfh-verify; "
           "`none`: none; mk/scenes.mk): only their scores beside canopy's are read; without it every "
           "method whose results/scenes/baseline-<method>/score.json is there")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->each([&src](const std::string&) { src.tile_baselines_given = true; });
  for (std::size_t i = 0; i < src.tile_classify_ablations.size(); ++i) {
    const std::string opt = classify_ablation_option(i);
    const std::string var = i == 0 ? "SCENES_CLASSIFY_ABLATION" : "SCENES_CLASSIFY_ABLATION_2";
    tool.add(
        opt, &src.tile_classify_ablations[i].score,
        "the scene experiment's " + std::string(i == 0 ? "" : "second ") +
            "classify ablation's score.json (mk/scenes.mk " + var +
            ": the same candidates classified with another parameter file): a subsection beside canopy's "
            "(with " +
            opt + "-config)");
    tool.add(opt + "-config", &src.tile_classify_ablations[i].config,
             "the parameter file that ablation classified with (named in the subsection; with " + opt + ")");
  }
  tool.add("--families", &src.families,
           "the families protocol's results directory (confusion.csv, accuracy.csv from famscore; "
           "mk/families.mk): adds the \"Vehicle families\" section to report.md");
  tool.add("--real-timeout", &src.real_timeout,
           "the time box of a real tile, s (mk/real.mk REAL_TIMEOUT; 0 unknown); the real tiles are the "
           "manifest's `real` records, and the \"Real tiles\" section is written when it has any");
  tool.add("--openset", &src.openset,
           "the open-set experiment's score.json (mk/openset.mk): adds the section \"Open set: unseen "
           "vehicles\"");
  tool.add("--openset-crops", &src.openset_crops,
           "the open set's single-vehicle crops' score.json (mk/openset.mk): a subsection of the open set's");
  std::string names;
  for (const std::string& n : report::openset_classify_ablation_names())
    names += (names.empty() ? "" : ", ") + n;
  tool.add("--openset-classify-ablation", &src.openset_classify_ablations,
           "an open-set classify ablation as NAME=SCORE: its score.json (mk/openset.mk "
           "OPENSET_CLASSIFY_ABLATION[_2|_3|_4]: the same candidates classified with other parameters) and "
           "its name, which picks the subsection's heading (" +
               names + "); repeated, one subsection each beside the default, in the order given")
      ->allow_extra_args(false);
  tool.add("--openset-crops-classify-ablation", &src.openset_crops_classify_ablations,
           "the same ablation's score.json on the single-vehicle crops, as NAME=SCORE (NAME one of "
           "--openset-classify-ablation's); repeated, at most one per name")
      ->allow_extra_args(false);
  tool.add("--openset-collect-ablation", &src.openset_collect_ablations,
           "an open-set collect ablation's score.json (mk/openset.mk OPENSET_COLLECT_ABLATIONS: the same "
           "verdicts and class answers collected with other options): a subsection of the open set's beside "
           "the default, named by what --openset-collect-ablation-options turn off; repeated, one subsection "
           "each in order")
      ->allow_extra_args(false);
  tool.add("--openset-collect-ablation-options", &src.openset_collect_ablation_options,
           "the collect options of each --openset-collect-ablation, in the same order (the list's entry: "
           "--name=value options joined by commas, given as --openset-collect-ablation-options=ENTRY); "
           "without it a single --openset-collect-ablation is the model answer first "
           "(--contradicted-below=0,--refused-below=0)")
      ->allow_extra_args(false);
  tool.add("--openset-crops-collect-ablation", &src.openset_crops_collect_ablations,
           "the same ablation's score.json on the single-vehicle crops: none, or one per "
           "--openset-collect-ablation in the same order")
      ->allow_extra_args(false);
  tool.add("--openset-verify-ablation", &src.openset_verify_ablation,
           "the open set's verify ablation's score.json (mk/openset.mk OPENSET_VERIFY_ABLATION: the tiles' "
           "model-level candidates verified again with other options): a subsection of the open set's "
           "(with --openset-verify-ablation-options)");
  tool.add("--openset-verify-ablation-options", &src.openset_verify_ablation_options,
           "the verify options that ablation ran with, as --name=value words (its subsection's heading)");
  tool.add("--openset-distances", &src.openset_distances,
           "the vehicle library's distances.csv (scripts/vehicles/distance.py): the open set's nearest "
           "modelbase instances and instance accuracy");
  tool.add("--disk", &src.disk,
           "the experiment's output directory: adds the \"Disk\" section (bytes per part when the report is "
           "written)");
  tool.add("--max-segments", &p.max_segments, "largest object segments examined for spurious area");
  tool.add("--overseg-ratio", &p.overseg_ratio, "over-segmented when target segments exceed this x model's");
  tool.add("--missing-area-ratio", &p.missing_area_ratio,
           "missing area when target area is below this x model's");
  tool.add("--spurious-share", &p.spurious_share, "spurious when non-target area share exceeds this");
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("report",
                    "Write the experiment report (Markdown + CSV) from the artifacts its manifest names.");
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
    if (src.real_timeout < 0) throw common::UsageError("--real-timeout: must be >= 0 s");
    needs(src.tile_collect_ablation, "--tile-collect-ablation", src.tile_score, "--tile-score");
    needs(src.tile_verify_ablation, "--tile-verify-ablation", src.tile_score, "--tile-score");
    if (src.tile_verify_ablation.empty() != src.tile_verify_ablation_options.empty())
      throw common::UsageError("--tile-verify-ablation and --tile-verify-ablation-options go together");
    needs(src.tile_baselines_given ? "given" : "", "--tile-baselines", src.tile_score, "--tile-score");
    for (const std::string& m : src.tile_baselines) {
      if (m != "none" && !report::is_scene_baseline_method(m))
        throw common::UsageError("--tile-baselines: unknown method '" + m +
                                 "' (vfh, fpfh, size, fpfh-verify or none)");
      if (m == "none" && src.tile_baselines.size() > 1)
        throw common::UsageError("--tile-baselines: none with other methods");
    }
    if (src.tile_baselines == std::vector<std::string>{"none"}) src.tile_baselines.clear();
    for (std::size_t i = 0; i < src.tile_classify_ablations.size(); ++i) {
      const std::string opt = classify_ablation_option(i);
      const ClassifyAblationArgs& a = src.tile_classify_ablations[i];
      needs(a.score, opt, src.tile_score, "--tile-score");
      if (a.score.empty() != a.config.empty())
        throw common::UsageError(opt + " and " + opt + "-config go together");
    }
    needs(src.openset_verify_ablation, "--openset-verify-ablation", src.openset, "--openset");
    if (src.openset_verify_ablation.empty() != src.openset_verify_ablation_options.empty())
      throw common::UsageError("--openset-verify-ablation and --openset-verify-ablation-options go together");
    const std::vector<NamedAblation> openset_classify = classify_ablations(src);
    check_collect_ablations(src);
    common::log::Phase phase("read");
    const documents::ExperimentManifest manifest = documents::read_experiment_manifest(src.manifest);
    const report::Inputs in = read_inputs(manifest, src.thesis);
    phase.done(std::to_string(in.cases.size()) + " trials, " + std::to_string(in.models.size()) + " models");
    const report::Outputs r = report::run(p, in);
    // The PCL baseline beside canopy (issue 17), when the trials have baseline.json.
    const auto bl = report::baseline_section(manifest);
    if (!bl.markdown.empty()) {
      outputs.add(results + "/baseline.csv", "--results");
      outputs.set(results + "/baseline.csv", bl.csv);
    }
    std::string markdown = r.markdown + bl.markdown;
    if (!src.families.empty()) markdown += families_section(src.families);
    if (!src.tile_score.empty())
      markdown += scenes_section(src.tile_score, src.tile_collect_ablation, src.tile_classify_ablations,
                                 src.tile_verify_ablation, src.tile_verify_ablation_options,
                                 src.tile_baselines_given ? &src.tile_baselines : nullptr, scene_dir, results,
                                 outputs);
    if (!manifest.real.empty()) markdown += real_section(manifest.real, src.real_timeout);
    if (!manifest.density.empty() || !manifest.density_sensor.empty())
      markdown += density_section(manifest.density, manifest.density_sensor, results, outputs);
    if (!src.openset.empty()) {
      const std::optional<documents::SceneScore> crops = optional_score(src.openset_crops);
      const report::OpensetDistances distances =
          src.openset_distances.empty() ? report::OpensetDistances{}
                                        : report::parse_openset_distances(
                                              common::read_file(src.openset_distances), src.openset_distances);
      markdown += report::openset_markdown(documents::read_scene_score_file(src.openset), src.openset,
                                           crops ? &*crops : nullptr, src.openset_crops, distances,
                                           src.openset_distances);
      for (const NamedAblation& a : openset_classify) markdown += openset_classify_ablation_section(a);
      for (std::size_t k = 0; k < src.openset_collect_ablations.size(); ++k)
        markdown += openset_collect_ablation_section(
            src.openset_collect_ablations[k],
            src.openset_crops_collect_ablations.empty() ? "" : src.openset_crops_collect_ablations[k],
            src.openset_collect_ablation_options.empty() ? "" : src.openset_collect_ablation_options[k]);
      if (!src.openset_verify_ablation.empty())
        markdown += report::openset_verify_ablation_markdown(
            documents::read_scene_score_file(src.openset_verify_ablation), src.openset_verify_ablation,
            src.openset_verify_ablation_options);
    }
    if (!src.disk.empty())
      markdown += report::disk_markdown(report::disk_parts(src.disk, manifest.objects), src.disk);
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
