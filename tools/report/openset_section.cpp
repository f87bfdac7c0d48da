#include "report/openset_section.h"

#include <cstdlib>
#include <map>
#include <sstream>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/units.h"
#include "canopy/formats/csv_table.h"
#include "report/report.h"
#include "report/score_cells.h"

namespace canopy::report {

namespace {

// The per-cover rows of a score, then a per-instance table of what the answers were.
void rates_table(std::ostringstream& md, const documents::SceneScore& score, const std::string& label) {
  md << "| " << label
     << " | tiles | vehicles | found (model + class) | recall | precision | class right (of found) | "
        "false alarms/ha |\n|---|---|---|---|---|---|---|---|\n";
  for (const documents::ScoreRow* r : cover_rows(score)) {
    const documents::ScoreValue* c = documents::score_cell(*r, "cover");
    md << "| " << (c ? c->text : "") << " | " << score_count(*r, "tiles") << " | " << score_count(*r, "true")
       << " | " << score_count(*r, "found_any_level") << " (" << score_count(*r, "tp") << " + "
       << score_count(*r, "class_tp") << ") | " << score_ci(*r, "recall_any_level", "%.1f%%", "%.1f", 100)
       << " | " << score_ci(*r, "precision_any_level", "%.1f%%", "%.1f", 100) << " | "
       << score_count(*r, "class_right_any_level") << "/" << score_count(*r, "found_any_level") << " = "
       << score_ci(*r, "class_accuracy_any_level", "%.1f%%", "%.1f", 100) << " | "
       << score_ci(*r, "false_alarms_any_level_per_ha", "%.1f", "%.1f", 1) << " |\n";
  }
}

// The crops' table: one vehicle per tile, so every crop is an independent trial and the rates
// take Wilson's interval on their counts (score's own intervals resample tiles, which with one
// vehicle a tile and a handful of tiles give [0, 100]).
void crops_table(std::ostringstream& md, const documents::SceneScore& score) {
  md << "| class | crops | found (model + class) | recall | class right (of found) | class right (of all "
        "crops) | "
        "wrong class (of found) | false alarms |\n|---|---|---|---|---|---|---|---|\n";
  const auto count = [](const documents::ScoreRow& r, const std::string& key) {
    return static_cast<int>(score_number(r, key).value_or(0) + 0.5);
  };
  for (const documents::ScoreRow* r : cover_rows(score)) {
    const documents::ScoreValue* c = documents::score_cell(*r, "cover");
    const int n = count(*r, "true"), found = count(*r, "found_any_level"),
              right = count(*r, "class_right_any_level");
    md << "| " << (c ? c->text : "") << " | " << n << " | " << found << " (" << score_count(*r, "tp") << " + "
       << score_count(*r, "class_tp") << ") | " << rate_ci_units(found, n, n) << " | "
       << rate_ci_units(right, found, found) << " | " << rate_ci_units(right, n, n) << " | "
       << rate_ci_units(found - right, found, found) << " | " << count(*r, "fp") + count(*r, "class_fp")
       << " |\n";
  }
}

void instance_table(std::ostringstream& md, const documents::SceneScore& score, const OpensetDistances& d) {
  struct Tally {
    int all = 0, found = 0, model = 0, cls = 0, nearest = 0;
    std::map<std::string, int> answers;
  };
  std::map<std::string, Tally> per;
  for (const documents::ScoreMatch& m : score.matches) {
    if (!m.true_model || m.outcome == "false_alarm") continue;
    Tally& t = per[*m.true_model];
    ++t.all;
    if (m.outcome != "right" && m.outcome != "wrong") continue;
    ++t.found;
    const bool model = m.level.value_or("model") == "model";
    ++(model ? t.model : t.cls);
    if (model && m.model && *m.model == openset_nearest_entry(d, *m.true_model)) ++t.nearest;
    ++t.answers[(model ? "model " + m.model.value_or("?") + " (" + m.cls.value_or("no class") + ")"
                       : "class " + m.cls.value_or("?"))];
  }
  md << "\n| test instance | nearest modelbase instance (D; runner-up) | found / true | at model / class "
        "level | "
        "model answers naming the nearest | answers |\n|---|---|---|---|---|---|\n";
  for (const auto& [name, t] : per) {
    std::string answers, nearest = "–";
    for (const auto& [a, n] : t.answers)
      answers += (answers.empty() ? "" : ", ") + a + " × " + std::to_string(n);
    const auto it = d.find(name);
    if (it != d.end() && !it->second.empty()) {
      const auto& v = it->second;
      nearest = v[0].modelbase + format_number(" (%.3f m", v[0].distance_m) +
                (v.size() > 1 ? "; " + v[1].modelbase + format_number(" %.3f m)", v[1].distance_m) : ")");
    }
    md << "| " << name << " | " << nearest << " | " << t.found << "/" << t.all << " | " << t.model << " / "
       << t.cls << " | "
       << (t.model > 0 && !d.empty() ? std::to_string(t.nearest) + "/" + std::to_string(t.model) : "–")
       << " | " << (answers.empty() ? "–" : answers) << " |\n";
  }
}

std::string instance_line(const documents::SceneScore& score, const OpensetDistances& d) {
  const InstanceTally t = openset_instance_tally(score, d);
  return "**Instance accuracy** (model-level answers naming the test instance's nearest modelbase "
         "instance): " +
         rate_ci_units(t.nearest, t.model_answers, t.model_answers) + ".\n";
}

}  // namespace

OpensetDistances parse_openset_distances(const std::string& text, const std::string& name) {
  OpensetDistances out;
  const std::vector<formats::CsvRow> rows = formats::split_csv(text);
  if (rows.empty()) throw common::DataError(name, "empty (no header)");
  for (const formats::CsvRow& r : rows) {
    const std::string where = "line " + std::to_string(r.line) + ": ";
    const std::vector<std::string>& f = r.cells;
    if (&r == &rows.front()) {
      if (f != std::vector<std::string>{"test", "class", "modelbase", "distance_m", "rank"})
        throw common::DataError(name, where + "the header must be test,class,modelbase,distance_m,rank");
      continue;
    }
    if (f.size() != 5 || f[0].empty() || f[1].empty() || f[2].empty())
      throw common::DataError(name, where + "five fields test,class,modelbase,distance_m,rank expected");
    if (common::decimal_prefix(f[3]) != f[3].size() || f[3].empty() ||
        !common::decimal_problem(f[3]).empty() || f[3][0] == '-')
      throw common::DataError(name, where + "distance_m '" + f[3] + "' is not a distance in metres");
    if (f[4].empty() || f[4].size() > 6 || f[4].find_first_not_of("0123456789") != std::string::npos)
      throw common::DataError(name, where + "rank '" + f[4] + "' is not a whole number");
    std::vector<OpensetNeighbour>& v = out[f[0]];
    OpensetNeighbour n{f[2], f[1], std::strtod(f[3].c_str(), nullptr), std::atoi(f[4].c_str())};
    if (n.rank != static_cast<int>(v.size()) + 1)
      throw common::DataError(
          name, where + "rank " + f[4] + " of " + f[0] + ": ranks must run 1, 2, ... per test instance");
    if (!v.empty() && (n.distance_m < v.back().distance_m || n.cls != v.back().cls))
      throw common::DataError(name, where + f[0] + ": rows must be of one class, by distance");
    v.push_back(n);
  }
  return out;
}

std::string openset_nearest_entry(const OpensetDistances& d, const std::string& test) {
  const auto it = d.find(test);
  if (it == d.end() || it->second.empty()) return "";
  return it->second[0].cls + "__" + it->second[0].modelbase;
}

InstanceTally openset_instance_tally(const documents::SceneScore& score, const OpensetDistances& d) {
  InstanceTally t;
  for (const documents::ScoreMatch& m : score.matches) {
    if (!m.true_model || (m.outcome != "right" && m.outcome != "wrong")) continue;
    if (m.level.value_or("model") != "model" || !d.count(*m.true_model)) continue;
    ++t.model_answers;
    if (m.model && *m.model == openset_nearest_entry(d, *m.true_model)) ++t.nearest;
  }
  return t;
}

namespace {

// The open set's reliability table (score's reliability.csv of `which` answers), when the score has one.
void reliability(std::ostringstream& md, const documents::SceneScore& score, const std::string& which) {
  if (score.reliability.empty()) return;  // a score written before the table
  md << "\n**Reliability** of " << which
     << " answers (issue 29: within ±10 points of the stated confidence in every bin of at least 20 "
        "answers), judged as the scene experiment's table judges them: a model answer is right only when "
        "it names the true model, which no answer can here (every test instance is outside the "
        "modelbase), so its rows show what confidence verify states for an instance it has never seen; a "
        "class answer is right when its class is the vehicle's; a `none` unless a vehicle that no "
        "detection found lies within the match radius of its candidate.\n\n";
  const int off = reliability_rows(md, score);
  md << "Bins of at least 20 answers outside ±10 points: " << off << ".\n";
}

}  // namespace

std::string openset_markdown(const documents::SceneScore& score, const std::string& score_path,
                             const documents::SceneScore* crops, const std::string& crops_path,
                             const OpensetDistances& distances, const std::string& distances_path) {
  std::ostringstream md;
  md << "\n## Open set: unseen vehicles\n\n"
     << "The scene experiment's tiles (its recipe and cover levels, noise 0) with their vehicles drawn "
        "from the vehicle library's **test** instances only (share/vehicles/split.csv: third-party meshes "
        "never in the modelbase), recognised against a modelbase built by `make user-modelbase` from the "
        "library's **modelbase** instances (share/vehicles/modelbase/). No answer can name the right "
        "instance, so what is judged is the class: a model answer names its entry's class, a class "
        "answer its class or group (score --model-classes). Either level counts as found. Rates: k/n "
        "and score's 95% interval (mk/openset.mk; docs/decisions/open-set.md; "
     << score_path << ").\n\n";
  rates_table(md, score, "cover");
  if (!distances.empty())
    md << "\n"
       << instance_line(score, distances)
       << "The nearest instance: the modelbase instance of the test instance's class at the least symmetric "
          "chamfer distance D between the two meshes (library frame: centred, bottom at z = 0, unscaled; "
          "the better of yaw 0 and 180 deg; 4096 area-uniform surface samples each; "
          "scripts/vehicles/distance.py, "
       << distances_path << ").\n";
  instance_table(md, score, distances);
  reliability(md, score, "the tiles'");
  if (crops != nullptr) {
    md << "\n### Single-vehicle crops of the unseen test instances\n\n"
       << "Each test instance alone in an open 20 m tile (flat ground, no trees, bushes or clutter; the "
          "scene "
          "experiment's flight lines, looks and 40 mm spacing), one per seed at a seeded pose; detect's "
          "candidate is the crop, and the tile chain runs on it as `make tile` does (classify, then fitvox, "
          "cocone, ncut, gmatch and verify when dense enough, collect). Every test instance's class has "
          "other instances in the modelbase (the split rule). One row per class (the cover label is the "
          "class), then all; the issue's target: class right ≥ 80%, a wrong class ≤ 5%. Rates: k/n with "
          "Wilson's 95% interval (one vehicle per tile: independent trials; "
       << crops_path << ").\n\n";
    crops_table(md, *crops);
    if (!distances.empty()) md << "\n" << instance_line(*crops, distances);
    instance_table(md, *crops, distances);
    reliability(md, *crops, "the crops'");
  }
  return md.str();
}

namespace {

std::string ablation_markdown(const std::string& heading, const std::string& what,
                              const documents::SceneScore& tiles, const std::string& tiles_path,
                              const documents::SceneScore* crops, const std::string& crops_path) {
  std::ostringstream md;
  md << "\n### " << heading << "\n\n"
     << what << " (" << tiles_path << (crops ? ", " + crops_path : std::string()) << ").\n\n";
  rates_table(md, tiles, "cover");
  if (crops != nullptr) {
    md << "\nThe single-vehicle crops, the same ablation:\n\n";
    crops_table(md, *crops);
  }
  return md.str();
}

}  // namespace

namespace {

// One classify ablation of the open set: its name (--openset-classify-ablation NAME=SCORE), heading
// and paragraph.
struct ClassifyAblationText {
  const char* name;
  const char* heading;
  const char* what;
};
const ClassifyAblationText kClassifyAblations[] = {
    {"every-family",
     "Ablation: every classify family, no class envelope (`OPENSET_CLASSES_ONLY=0 "
     "OPENSET_CLASS_ENVELOPE=0`)",
     "The open set's default answers only the classes of the modelbase's entries (`classify "
     "--modelbase-classes-only`, docs/decisions/open-set.md, fourth round), and a class with two or more "
     "entries is also the box of their sizes +-5% (`classify --class-envelope 0.05`, eighth round); this "
     "is the same tiles, candidates and model chain with classify's every family and no envelope instead "
     "(the simulated tiles' parameters alone), run beside it on every candidate and scored the same way"},
    {"no-envelope",
     "Ablation: no class envelope, the modelbase's classes only kept (`OPENSET_CLASS_ENVELOPE=0`)",
     "The envelope alone: the open set's classify as shipped (`--modelbase-classes-only`) with no class "
     "envelope (`classify --class-envelope 0`, docs/decisions/open-set.md, eighth round), run beside the "
     "default and the ablation above on every candidate, with the same model chain, and scored the same "
     "way; against the default, what the envelope changes"},
    {"family-entries-1", "Ablation: one entry keeps its family (`OPENSET_FAMILY_ENTRIES=1`)",
     "With the modelbase's classes only, a classify family counts as a class only when two or more "
     "modelbase entries name it (`classify --family-entries 2`, docs/decisions/open-set.md, eleventh "
     "round): a class shown by one entry (the tracked APC, the bus, the tank) is that entry's own range. "
     "This is the same tiles, candidates and model chain with `--family-entries 1` (one entry keeps its "
     "family's whole range, as before) and the open set's other parameters, run beside the default on "
     "every candidate and scored the same way"},
    {"no-bed", "Ablation: no pickup bed cue (`classify --min-bed 0`)",
     "A car- or van-group answer whose top shows a pickup's bed at one end (its walls over its floor and "
     "under the cab's roof: `classify --min-bed 0.1`, docs/decisions/classify.md §39) can only be "
     "`pickup`; this is the same tiles, candidates and model chain with the cue off (`--min-bed 0`) and "
     "the open set's other parameters, run beside the default on every candidate and scored the same way"},
};

}  // namespace

const std::vector<std::string>& openset_classify_ablation_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const ClassifyAblationText& a : kClassifyAblations) v.push_back(a.name);
    return v;
  }();
  return names;
}

std::string openset_classify_ablation_markdown(const std::string& name, const documents::SceneScore& tiles,
                                               const std::string& tiles_path,
                                               const documents::SceneScore* crops,
                                               const std::string& crops_path) {
  for (const ClassifyAblationText& a : kClassifyAblations)
    if (name == a.name) return ablation_markdown(a.heading, a.what, tiles, tiles_path, crops, crops_path);
  std::string names;
  for (const std::string& n : openset_classify_ablation_names()) names += (names.empty() ? "" : ", ") + n;
  throw common::UsageError("--openset-classify-ablation: no ablation named \"" + name +
                           "\" (the names: " + names + ")");
}

std::vector<std::string> collect_ablation_options(const std::string& options) {
  std::vector<std::string> words;
  std::string word;
  const auto flush = [&] {
    if (word.empty()) return;
    if (word.rfind("--", 0) != 0 || word.size() < 3)
      throw common::UsageError("--openset-collect-ablation-options: \"" + word +
                               "\" is not a collect option (--name or --name=value)");
    const std::size_t eq = word.find('=');
    words.push_back(word.substr(0, eq));
    if (eq != std::string::npos) words.push_back(word.substr(eq + 1));
    word.clear();
  };
  for (const char c : options) {
    if (c == ',' || c == ' ' || c == '\t' || c == '\n')
      flush();
    else
      word += c;
  }
  flush();
  return words;
}

std::string openset_collect_ablation_markdown(const documents::SceneScore& tiles,
                                              const std::string& tiles_path, const documents::SceneScore* crops,
                                              const std::string& crops_path, const std::string& options) {
  const std::vector<std::string> words = collect_ablation_options(options);
  std::string shown;  // the options as collect takes them on its command line
  for (const std::string& w : words) shown += " " + w;
  const std::vector<std::string> model_first = {"--contradicted-below", "0", "--refused-below", "0"};
  const std::vector<std::string> model_first_swapped = {"--refused-below", "0", "--contradicted-below", "0"};
  if (words.empty() || words == model_first || words == model_first_swapped)
    return ablation_markdown(
        "Ablation: the model answer first (`collect --contradicted-below 0 --refused-below 0`)",
        "By default a model answer of verify's with a confidence below 0.5 whose class classify's class "
        "answer contradicts gives way to classify's answer (`collect --contradicted-below`, "
        "docs/decisions/open-set.md, sixth round), and one below 0.8 that classify refused on its shape or "
        "surface gives way to that refusal (`collect --refused-below`, seventh round); this is the same "
        "verdicts and class answers collected with the model answer always first, as before, and scored "
        "the same way",
        tiles, tiles_path, crops, crops_path);
  if (words == std::vector<std::string>{"--contradiction-level", "class"})
    return ablation_markdown(
        "Ablation: the sixth round's contradiction by class (`collect --contradiction-level class`)",
        "By default classify's class answer contradicts a doubtful model answer of verify's (below "
        "`collect --contradicted-below`) only when the two classes lie in different groups (`collect "
        "--contradiction-level group`, docs/decisions/open-set.md, thirteenth round): verify's pickup for "
        "a car that classify answers `car`, or a tank for a tracked APC, stands. This is the same verdicts "
        "and class answers collected with any other class contradicting, as from the sixth round until "
        "the thirteenth, and scored the same way",
        tiles, tiles_path, crops, crops_path);
  return ablation_markdown("Ablation: collect's options `collect" + shown + "`",
                           "The same verdicts and class answers collected with `collect" + shown +
                               "` (mk/openset.mk `OPENSET_COLLECT_ABLATIONS`) and scored the same way",
                           tiles, tiles_path, crops, crops_path);
}

std::string openset_verify_ablation_markdown(const documents::SceneScore& tiles,
                                             const std::string& tiles_path, const std::string& options) {
  if (options == "--max-tilt=180")
    return ablation_markdown(
        "Ablation: no upright bound (`verify --max-tilt=180`)",
        "By default verify scores 0 a hypothesis that no start poses upright: a model whose vertical leans "
        "more than `verify --max-tilt` (40° in share/params/verify.ini) from the tile's (on its side, on its "
        "nose, upside down; docs/decisions/verify.md §21). This is the same model-level candidates verified "
        "again without the bound, as before, collected and scored the same way (the tiles only)",
        tiles, tiles_path, nullptr, "");
  return ablation_markdown(
      "Ablation: verify's options `" + options + "`",
      "The same model-level candidates verified again with `" + options +
          "` after verify's parameters (mk/openset.mk `OPENSET_VERIFY_ABLATION`), collected "
          "and scored the same way (the tiles only)",
      tiles, tiles_path, nullptr, "");
}

}  // namespace canopy::report
