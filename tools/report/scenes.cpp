// The report's scene-experiment section: stage times from the .time files, and the Markdown
// rendering of score.json (whose numbers `score` computed).
#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "canopy/documents/match_result.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/verdict.h"
#include "report/clutter_section.h"
#include "report/report.h"
#include "report/score_cells.h"

namespace canopy::report {
namespace {

using documents::SceneScore;
using documents::ScoreRow;
using documents::ScoreValue;

// A rate of the score (a number or null) as a percentage; null = "–".
std::string rate(const ScoreValue& v) {
  return v.is_number() ? format_number("%.1f%%", 100 * v.as_number()) : "–";
}
std::string num(const ScoreValue& v, const char* f) {
  return v.is_number() ? format_number(f, v.as_number()) : "–";
}
std::string num(const std::optional<double>& v, const char* f) { return v ? format_number(f, *v) : "–"; }
// A rate of `row` with score's 95% interval (<key>_lo, <key>_hi): "95.0% [91.2, 97.8]"; the
// rate alone when the score has no interval (one written before score computed them).
std::string rate_ci(const ScoreRow& row, const std::string& key) {
  return score_ci(row, key, "%.1f%%", "%.1f", 100);
}
// The same for a number per unit ("1.2 [0.4, 3.1]").
std::string num_ci(const ScoreRow& row, const std::string& key, const char* f) {
  return score_ci(row, key, f, f, 1);
}
// A count and, when the score counts it, its distinct part: "24 (12)" (true vehicles over
// noise levels that reuse a render; tiles over renders).
std::string count_distinct(const ScoreRow& row, const char* key, const char* distinct) {
  const ScoreValue& d = score_field(row, distinct);
  return score_text(score_field(row, key)) + (d.is_number() ? " (" + score_text(d) + ")" : std::string());
}

// Cells equal as JSON values: nulls, equal texts, equal numbers (an integer 8 equals 8.0).
bool same_value(const ScoreValue& a, const ScoreValue& b) {
  if (a.is_number() && b.is_number()) {
    if (a.kind == ScoreValue::Kind::integer && b.kind == ScoreValue::Kind::integer)
      return a.integer == b.integer;
    return a.as_number() == b.as_number();
  }
  if (a.kind != b.kind) return false;
  return a.kind == ScoreValue::Kind::null || a.text == b.text;
}

// The PCL baseline's methods (issue 17; mk/scenes.mk SCENE_BASELINE), in the tables' order.
// (fpfh-verify: the FPFH poses scored by verify, an ablation of canopy's gmatch, issue 29; its
// score lives beside the methods' as baseline-fpfh-verify/.)
const char* const kBaselineMethods[] = {"vfh", "fpfh", "size", "fpfh-verify"};

// Methods that are ablations of canopy rather than baselines (issue 29): left out of issue 17's goal.
bool canopy_ablation(const std::string& method) {
  return method == "size" || method == "verify-ablation" || method == "fpfh-verify";
}

struct BaselineScore {
  std::string method;
  std::string path;
  SceneScore score;
  std::string label;  // the tables' name of the row
};

// Whether two scores are of the same runs (the same run directories in the same order): a score
// beside canopy's is shown only then; otherwise it is stale (a run over other tiles).
bool same_runs(const SceneScore& a, const SceneScore& b) {
  const auto dirs = [](const SceneScore& s) {
    std::vector<std::string> d;
    for (const auto& r : scene_runs(s)) d.push_back(r.dir);
    return d;
  };
  return dirs(a) == dirs(b);
}

// The baseline's scores beside canopy's: <dir>/baseline-<method>/score.json, where <dir> is
// where `score` wrote canopy's CSVs (the score's --csv parameter: results/scenes/). Only scores
// of exactly canopy's runs are shown; others (a stale run over other tiles) are named in
// `stale`. methods: those that ran (null: every one with a score.json).
std::vector<BaselineScore> baseline_scores(const SceneScore& score, std::vector<std::string>& stale,
                                           const SceneVerifyAblation& verify_ablation,
                                           const std::vector<std::string>* methods) {
  std::vector<BaselineScore> out;
  std::string csv;
  for (const auto& [k, v] : score.parameters) {
    if (k == "csv") csv = v;
  }
  if (!csv.empty()) {
    const std::filesystem::path dir = std::filesystem::path(csv).parent_path();
    for (const char* m : kBaselineMethods) {
      if (methods != nullptr && std::find(methods->begin(), methods->end(), m) == methods->end()) continue;
      const std::string path = (dir / ("baseline-" + std::string(m)) / "score.json").string();
      std::error_code ec;
      if (!std::filesystem::is_regular_file(path, ec)) continue;
      BaselineScore b{m, path, documents::read_scene_score_file(path), method_label(m)};
      if (!same_runs(b.score, score)) {
        stale.push_back(path);
        continue;
      }
      out.push_back(std::move(b));
    }
  }
  // verify again with other options (the scene experiment's verify ablation, --tile-verify-ablation:
  // another top-k), after the baseline's methods.
  if (verify_ablation.score != nullptr) {
    if (same_runs(*verify_ablation.score, score))
      out.push_back({"verify-ablation", verify_ablation.path, *verify_ablation.score,
                     "verify `" + verify_ablation.options + "` (ablation)"});
    else
      stale.push_back(verify_ablation.path);
  }
  return out;
}

// A score's row of `table` whose keys equal `row`'s (summary: cover and noise_mm; models:
// model and cover; cover_bins: cover_lo and noise_mm); null when it has none.
const ScoreRow& same_row(const std::vector<ScoreRow>& table, const ScoreRow& row, const char* k1,
                         const char* k2) {
  static const ScoreRow no_row;
  for (const ScoreRow& r : table) {
    if (same_value(score_field(r, k1), score_field(row, k1)) &&
        same_value(score_field(r, k2), score_field(row, k2)))
      return r;
  }
  return no_row;
}

// Mean wall time of a stage's runs (cpu: its CPU, user + system, over the runs with CPU columns);
// runs = how many.
double stage_mean(const std::vector<SceneStageTime>& times, const std::string& stage, int& runs,
                  bool cpu = false) {
  for (const auto& t : times) {
    if (t.stage == stage) {
      runs = cpu ? t.cpu_runs : t.runs;
      return runs > 0 ? (cpu ? t.cpu_seconds : t.seconds) / runs : 0;
    }
  }
  runs = 0;
  return 0;
}

// The side-by-side tables: canopy and each baseline method per cover and noise level, per
// model, per measured cover bin; the goal; time per candidate.
void baseline_rows(std::ostringstream& md, const SceneScore& score, const std::vector<BaselineScore>& bl) {
  md << "| cover | noise (mm) | true | method | detections | precision | recall | identification | "
        "recognition "
        "| position error median (m) | heading error median (°) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ScoreRow& s : score.summary) {
    auto row = [&](const std::string& label, const ScoreRow& r, bool heading) {
      md << "| " << score_text(score_field(s, "cover")) << " | " << score_text(score_field(s, "noise_mm"))
         << " | " << count_distinct(s, "true", "true_distinct") << " | " << label << " | "
         << score_text(score_field(r, "detections")) << " | " << rate_ci(r, "precision") << " | "
         << rate_ci(r, "recall") << " | " << rate_ci(r, "identification") << " | " << rate_ci(r, "recognition")
         << " | " << num(score_field(r, "position_error_median_m"), "%.2f") << " | "
         << (heading ? num(score_field(r, "heading_error_median_deg"), "%.1f") : std::string("–")) << " |\n";
    };
    row("canopy", s, true);
    for (const auto& b : bl) {
      row(b.label, same_row(b.score.summary, s, "cover", "noise_mm"), b.method != "vfh" && b.method != "size");
    }
  }
  md << "\n";
}

void baseline_recognition(std::ostringstream& md, const SceneScore& score,
                          const std::vector<BaselineScore>& bl) {
  md << "Recognition (right model within the match radius / true vehicles) per model and per measured canopy "
        "cover bin:\n\n| model | cover | true | canopy";
  for (const auto& b : bl) md << " | " << b.label;
  md << " |\n|---|---|---|---";
  for (std::size_t i = 0; i < bl.size(); ++i) md << "|---";
  md << "|\n";
  for (const ScoreRow& m : score.models) {
    md << "| " << score_text(score_field(m, "model")) << " | " << score_text(score_field(m, "cover")) << " | "
       << count_distinct(m, "true", "true_distinct") << " | " << rate_ci(m, "recognition");
    for (const auto& b : bl)
      md << " | " << rate_ci(same_row(b.score.models, m, "model", "cover"), "recognition");
    md << " |\n";
  }
  md << "\n| canopy cover | noise (mm) | true | canopy";
  for (const auto& b : bl) md << " | " << b.label;
  md << " |\n|---|---|---|---";
  for (std::size_t i = 0; i < bl.size(); ++i) md << "|---";
  md << "|\n";
  for (const ScoreRow& c : score.cover_bins) {
    md << "| " << num(score_field(c, "cover_lo"), "%.2f") << "–" << num(score_field(c, "cover_hi"), "%.2f")
       << " | " << score_text(score_field(c, "noise_mm")) << " | "
       << count_distinct(c, "true", "true_distinct") << " | " << rate_ci(c, "recognition");
    for (const auto& b : bl) {
      md << " | " << rate_ci(same_row(b.score.cover_bins, c, "cover_lo", "noise_mm"), "recognition");
    }
    md << " |\n";
  }
  md << "\n";
}

void baseline_goal(std::ostringstream& md, const SceneScore& score, const std::vector<BaselineScore>& bl) {
  // The goal, on recognition over all runs.
  const ScoreRow all_key = {{"cover", "all"}, {"noise_mm", "all"}};
  const ScoreRow& canopy_all = same_row(score.summary, all_key, "cover", "noise_mm");
  const ScoreValue& c_rec = score_field(canopy_all, "recognition");
  double best = -1;
  std::string best_method;
  for (const auto& b : bl) {
    if (canopy_ablation(b.method)) continue;  // an ablation of canopy, not a baseline (below)
    const ScoreValue& r = score_field(same_row(b.score.summary, all_key, "cover", "noise_mm"), "recognition");
    if (r.is_number() && r.as_number() > best) {
      best = r.as_number();
      best_method = b.label;
    }
  }
  if (c_rec.is_number() && best >= 0) {
    const double gap = 100 * (c_rec.as_number() - best);
    md << "Goal of issue 17, canopy ≥ 5 points above the best baseline (recognition, all runs): canopy "
       << rate_ci(canopy_all, "recognition") << ", best baseline " << best_method << " "
       << format_number("%.1f%%", 100 * best) << ": " << format_number("%+.1f", gap) << " points, "
       << (gap >= 5 ? "met" : "**not met**") << ".\n\n";
  }
  for (const auto& b : bl) {
    if (b.method != "size") continue;
    const ScoreRow& size_all = same_row(b.score.summary, all_key, "cover", "noise_mm");
    const ScoreValue& s_rec = score_field(size_all, "recognition");
    if (!c_rec.is_number() || !s_rec.is_number()) continue;
    md << "What the model chain adds (issue 29): recognition over all runs, canopy "
       << rate_ci(canopy_all, "recognition") << " against size only " << rate_ci(size_all, "recognition")
       << " (" << format_number("%+.1f", 100 * (c_rec.as_number() - s_rec.as_number()))
       << " points); precision " << rate_ci(canopy_all, "precision") << " against "
       << rate_ci(size_all, "precision")
       << ". Where the intervals overlap, this experiment does not show that fitvox, cocone, ncut, gmatch "
          "and "
          "verify do better than picking the model of the nearest size.\n\n";
  }
}

// Which of the m models gmatch ranked a verify run with k hypotheses checked.
std::string checked(std::size_t k, std::size_t m) {
  return (k >= m ? "every one" : "gmatch's top " + std::to_string(k)) + " of the " + std::to_string(m) +
         " models";
}

// What gmatch adds (issue 29): canopy against verify with another top-k (the verify ablation: the
// ranking's share in the answer) and against verify on FPFH's ranking and poses (no gmatch at all),
// and what the ranking saves as the modelbase grows.
void gmatch_goal(std::ostringstream& md, const SceneScore& score, const std::vector<BaselineScore>& bl,
                 const std::vector<SceneStageTime>& times, const std::string& verify_options) {
  const ScoreRow all_key = {{"cover", "all"}, {"noise_mm", "all"}};
  const ScoreRow& canopy_all = same_row(score.summary, all_key, "cover", "noise_mm");
  const ScoreValue& c_rec = score_field(canopy_all, "recognition");
  const SceneRankedModels rm = scene_ranked_models(score);
  bool any = false;
  for (const auto& b : bl) {
    if (b.method != "verify-ablation" && b.method != "fpfh-verify") continue;
    // a verify ablation that checked as many hypotheses as canopy is about something else
    if (b.method == "verify-ablation" && rm.k > 0 && rm.k == rm.k_ablation) continue;
    const ScoreRow& r = same_row(b.score.summary, all_key, "cover", "noise_mm");
    const ScoreValue& r_rec = score_field(r, "recognition");
    if (!c_rec.is_number() || !r_rec.is_number()) continue;
    if (!any) {
      md << "What gmatch adds (issue 29): ";
      if (rm.m > 0 && rm.k > 0)
        md << "canopy's verify checks " << checked(rm.k, rm.m)
           << (rm.k >= rm.m ? " (its ranking chooses nothing here; its segment pairs give the start poses)" : "")
           << "; ";
    }
    md << (any ? "; " : "")
       << (b.method == "verify-ablation"
               ? "verify again with `" + verify_options + "` after its parameters" +
                     (rm.m > 0 && rm.k_ablation > 0 ? " checks " + checked(rm.k_ablation, rm.m) : std::string())
               : std::string(
                     "verify on the FPFH baseline's ranking and poses instead of gmatch's (its top-k of "
                     "FPFH's list, each from FPFH's pose, its flip and the principal axes)"))
       << ": recognition over all runs " << rate_ci(r, "recognition") << " against canopy's "
       << rate_ci(canopy_all, "recognition") << " ("
       << format_number("%+.1f", 100 * (c_rec.as_number() - r_rec.as_number()))
       << " points for canopy), precision " << rate_ci(r, "precision") << " against "
       << rate_ci(canopy_all, "precision");
    any = true;
  }
  if (!any) return;
  md << ". Where the intervals overlap, this experiment does not show a difference.";
  int g = 0, v = 0, va = 0;
  const double gmatch = stage_mean(times, "gmatch", g, true), verify = stage_mean(times, "verify", v, true),
               verify_abl = stage_mean(times, "verify-ablation", va, true);
  const std::size_t m = rm.m, k = rm.k, ka = rm.k_ablation;
  // One more hypothesis costs the two runs' difference over the difference of their hypotheses
  // (reading the points and the scorer once a candidate stay out of it); measured only when the run
  // with more hypotheses cost more.
  const bool measured = g > 0 && v > 0 && va > 0 && m > 0 && k > 0 && ka > 0 && ka != k &&
                        (ka > k) == (verify_abl > verify) && verify_abl != verify;
  if (measured) {
    // gmatch: its CPU over the m models it ranked, a model's share an upper bound of its per-model
    // cost (a fixed part per candidate counted in it).
    const double per_g = gmatch / static_cast<double>(m),
                 per_v = (verify_abl - verify) / (static_cast<double>(ka) - static_cast<double>(k));
    const auto at = [&](double n) {
      return format_number("%.1f", n * per_g + verify) + " s against " +
             format_number("%.1f", verify + (n - static_cast<double>(k)) * per_v) + " s";
    };
    md << " Cost, the CPU per candidate measured here: gmatch " << format_number("%.3f", gmatch) << " s ("
       << format_number("%.4f", per_g) << " s a model, at most), verify " << format_number("%.3f", verify)
       << " s on " << checked(k, m) << ", " << format_number("%.3f", verify_abl) << " s on " << checked(ka, m)
       << " (" << format_number("%.3f", per_v) << " s a hypothesis)"
       << (k >= m ? "; canopy checks every model here, so the ranking saves nothing yet" : "")
       << "; with N models canopy (top-k = " << k << ") would cost about N × " << format_number("%.4f", per_g)
       << " s + " << format_number("%.2f", verify) << " s a candidate against "
       << format_number("%.2f", verify) << " s + (N − " << k << ") × " << format_number("%.3f", per_v)
       << " s for verify over every model: at 100 models " << at(100) << ", at 1 000 models " << at(1000)
       << " (linear in N; gmatch's per-model cost is its graph match, verify's an ICP and the free-space "
          "test per hypothesis).";
  }
  md << "\n\n";
}

void baseline_times(std::ostringstream& md, const std::vector<BaselineScore>& bl,
                    const std::vector<SceneStageTime>& times) {
  // Time per candidate: mean wall time of each stage's runs (.time files).
  md << "Time per candidate (mean wall s over the candidates' `.time` files; on a shared machine wall "
        "includes waiting for the CPU): ";
  int n = 0, fitvox_n = 0;
  const double fitvox_s = stage_mean(times, "fitvox", fitvox_n);
  double chain_s = 0;  // fitvox + cocone + ncut + gmatch: what verify (and verify over every model) reads
  for (const char* s : {"fitvox", "cocone", "ncut", "gmatch"}) chain_s += stage_mean(times, s, n);
  const double canopy_s = chain_s + stage_mean(times, "verify", n);
  md << "canopy " << format_number("%.2f", canopy_s) << " s (fitvox " << format_number("%.2f", fitvox_s)
     << " + cocone + ncut + gmatch + verify)";
  for (const auto& b : bl) {
    if (b.method == "verify-ablation") {
      const double s = stage_mean(times, "verify-ablation", n);
      if (n == 0) continue;
      md << "; " << b.label << " " << format_number("%.2f", chain_s + s)
         << " s (fitvox + cocone + ncut + gmatch + " << format_number("%.2f", s) << " s verify, " << n
         << " runs)";
      continue;
    }
    if (b.method == "fpfh-verify") {
      int f = 0;
      const double s = stage_mean(times, "verify-fpfh", n), fp = stage_mean(times, "baseline-fpfh", f);
      if (n == 0 || f == 0) continue;
      md << "; " << b.label << " " << format_number("%.2f", fitvox_s + fp + s) << " s (fitvox + "
         << format_number("%.2f", fp) << " s FPFH + " << format_number("%.2f", s) << " s verify, " << n
         << " runs)";
      continue;
    }
    const double s = stage_mean(times, "baseline-" + b.method, n);
    if (n == 0) continue;
    md << "; " << b.label << " " << format_number("%.2f", fitvox_s + s) << " s (fitvox + "
       << format_number("%.2f", s) << " s baseline, " << n << " runs)";
  }
  md << ".\n\n";
}

std::string baseline_markdown(const SceneScore& score, const std::vector<BaselineScore>& bl,
                              const std::vector<SceneStageTime>& times, const std::string& verify_options) {
  std::ostringstream md;
  md << "### canopy beside the PCL baseline (issue 17)\n\n"
        "The same candidates (detect's, each one's fitvox `samples.pcd`), the same modelbase and the same "
        "`collect` and `score`: per candidate `baseline --verdict <method>` answers the best model of its "
        "method, or none when the method's score is below its acceptance threshold "
        "(docs/decisions/baseline.md §4). **VFH** (global descriptor, nearest model view) has no pose: its "
        "detection stands at detect's candidate frame (the footprint's centre), so its position error is "
        "detect's and it has no heading error. **FPFH** (local: correspondences + RANSAC + ICP, ground "
        "pose). **size only** is an ablation of canopy, not a baseline (issue 29): no model chain and none "
        "of "
        "classify's decisions; every candidate whose object classify measured becomes a detection of the "
        "modelbase model nearest to that length, width and height when each lies within 25% of the model's "
        "(`collect --size-only`; heading from the measured rectangle, front and back unknown, so no heading "
        "error is shown). Tables: `scenes/baseline-<method>/*.csv`.\n\n";
  baseline_rows(md, score, bl);
  baseline_recognition(md, score, bl);
  baseline_goal(md, score, bl);
  gmatch_goal(md, score, bl, times, verify_options);
  baseline_times(md, bl, times);
  return md.str();
}

// The section's parts, in the order scene_markdown writes them.
void scene_intro(std::ostringstream& md, const SceneScore& score, const ScoreRow* all, std::size_t renders) {
  md << "## Scene experiment (issue 16)\n\n";
  md << "Whole tiles (docs/decisions/scene-experiment.md): " << renders << " rendered tiles, "
     << score.tiles.size() << " runs (tile × noise level)";
  if (all != nullptr) {
    md << ", " << num(score_field(*all, "area_ha"), "%.2f") << " ha in all, "
       << score_text(score_field(*all, "true")) << " true vehicles, "
       << score_text(score_field(*all, "candidates")) << " candidates verified";
  }
  md << ". A detection matches a true vehicle whose centre lies within "
     << num(score.params.match_radius_m, "%g")
     << " m of its own (one to one, most confident first); identification = right model among the matched "
        "detections; recognition = right model found / true vehicles; pose errors over the identified "
        "detections. Tables: `scenes/*.csv`. Rates carry score's 95% interval in brackets: the hull of a "
        "percentile bootstrap over the rendered tiles (2 000 draws; vehicles of one tile and the noise "
        "levels "
        "of one render are not independent) and Wilson's interval (exact Poisson for false alarms per "
        "hectare) at the effective count, n × renders / runs (formats/README.md \"Scene scores\"). "
        "Counts in parentheses are distinct: renders among the tiles, vehicles counted once over their "
        "noise levels.\n\n";
}

void detection_table(std::ostringstream& md, const std::vector<ScoreRow>& summary) {
  md << "### Detection, identification and pose\n\n"
        "| cover | noise (mm) | tiles (renders) | mean vehicle cover | true (distinct) | candidates | "
        "detections | TP | FP | FN | "
        "precision | recall | F1 | false alarms / ha | identification | recognition | position error median "
        "/ "
        "p90 (m) | heading error median / p90 (°) | flips |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ScoreRow& s : summary) {
    md << "| " << score_text(score_field(s, "cover")) << " | " << score_text(score_field(s, "noise_mm"))
       << " | " << count_distinct(s, "tiles", "renders") << " | "
       << num(score_field(s, "mean_vehicle_cover"), "%.2f") << " | "
       << count_distinct(s, "true", "true_distinct") << " | " << score_text(score_field(s, "candidates"))
       << " | " << score_text(score_field(s, "detections")) << " | " << score_text(score_field(s, "tp"))
       << " | " << score_text(score_field(s, "fp")) << " | " << score_text(score_field(s, "fn")) << " | "
       << rate_ci(s, "precision") << " | " << rate_ci(s, "recall") << " | " << rate(score_field(s, "f1"))
       << " | " << num_ci(s, "false_alarms_per_ha", "%.1f") << " | " << rate_ci(s, "identification") << " | "
       << rate_ci(s, "recognition") << " | " << num(score_field(s, "position_error_median_m"), "%.2f")
       << " / " << num(score_field(s, "position_error_p90_m"), "%.2f") << " | "
       << num(score_field(s, "heading_error_median_deg"), "%.1f") << " / "
       << num(score_field(s, "heading_error_p90_deg"), "%.1f") << " | " << score_text(score_field(s, "flips"))
       << " |\n";
  }
  md << "\n";
}

void targets_table(std::ostringstream& md, const std::vector<ScoreRow>& summary, const ScoreRow* all) {
  // The targets, judged on the same numbers.
  md << "Targets of the issue (reported whatever they are):\n\n| target | measured | met |\n|---|---|---|\n";
  auto judge = [&](const char* what, const char* key, double bound, bool at_least) {
    std::string measured;
    bool met = true, any = false;
    for (const ScoreRow& s : summary) {
      const std::string c = score_text(score_field(s, "cover")), n = score_text(score_field(s, "noise_mm"));
      if ((c != "light" && c != "medium") || (n != "0" && n != "8")) continue;
      const ScoreValue& v = score_field(s, key);
      measured += (measured.empty() ? "" : ", ") + c + " " + n + " mm " + rate_ci(s, key);
      any = true;
      if (!v.is_number() || (at_least ? v.as_number() < bound : v.as_number() > bound)) met = false;
    }
    md << "| " << what << " | " << (any ? measured : "no light/medium run at 0–8 mm") << " | "
       << (any ? (met ? "yes" : "**no**") : "–") << " |\n";
  };
  judge("recall ≥ 95% at light and medium cover, 0–8 mm", "recall", 0.95, true);
  judge("precision ≥ 95% at light and medium cover, 0–8 mm", "precision", 0.95, true);
  if (all != nullptr) {
    const ScoreValue& id = score_field(*all, "identification");
    md << "| identification ≥ 90% of matched detections (all runs) | " << rate_ci(*all, "identification")
       << " | " << (id.is_number() ? (id.as_number() >= 0.9 ? "yes" : "**no**") : "–") << " |\n";
    const ScoreValue& he = score_field(*all, "heading_error_median_deg");
    md << "| heading error median ≤ 2° (all runs) | " << num(he, "%.2f°") << " | "
       << (he.is_number() ? (he.as_number() <= 2 ? "yes" : "**no**") : "–") << " |\n";
  }
  md << "\n";
}

void models_table(std::ostringstream& md, const SceneScore& score) {
  md << "### Identification per model\n\n"
        "| model | cover | true (distinct) | matched | identified | recall | identification | recognition |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const ScoreRow& m : score.models) {
    md << "| " << score_text(score_field(m, "model")) << " | " << score_text(score_field(m, "cover")) << " | "
       << count_distinct(m, "true", "true_distinct") << " | " << score_text(score_field(m, "matched"))
       << " | " << score_text(score_field(m, "identified")) << " | " << rate_ci(m, "recall") << " | "
       << rate_ci(m, "identification") << " | " << rate_ci(m, "recognition") << " |\n";
  }
  md << "\n";
}

void cover_table(std::ostringstream& md, const SceneScore& score, const std::string& fig) {
  md << "### Recognition against the measured canopy cover\n\n"
        "Per vehicle, the share of its footprint under vegetation seen from straight above (rangetrace's "
        "nadir image, `canopy_cover` in truth.json), binned; all noise levels, then per noise level.\n\n"
        "| canopy cover | noise (mm) | true (distinct) | detected | recognised | recall | recognition |\n"
        "|---|---|---|---|---|---|---|\n";
  for (const ScoreRow& b : score.cover_bins) {
    md << "| " << num(score_field(b, "cover_lo"), "%.2f") << "–" << num(score_field(b, "cover_hi"), "%.2f")
       << " | " << score_text(score_field(b, "noise_mm")) << " | "
       << count_distinct(b, "true", "true_distinct") << " | " << score_text(score_field(b, "detected"))
       << " | " << score_text(score_field(b, "recognised")) << " | " << rate_ci(b, "recall") << " | "
       << rate_ci(b, "recognition") << " |\n";
  }
  md << "\n![recognition against canopy cover](" << fig << "/cover.png)\n\n![recognition against noise]("
     << fig << "/noise.png)\n\n";
}

// Why the vehicles found at neither level were missed (score's fate, report::fate_label), one
// column per cover level in the score's order, every noise level's run counted.
void missed_table(std::ostringstream& md, const SceneScore& score, const std::vector<std::string>& covers) {
  std::map<std::string, std::map<std::string, int>> n;  // fate -> cover -> vehicle-runs
  for (const documents::ScoreMatch& m : score.matches) {
    if (m.outcome != "missed") continue;
    const auto tile = static_cast<std::size_t>(m.tile);
    n[fate_label(m)][tile < score.tiles.size() ? score.tiles[tile].cover.value_or("–") : "–"]++;
  }
  if (n.empty()) return;
  md << "### Why the vehicles were missed\n\n"
        "The vehicles found at neither level, by `score`'s fate (formats/README.md \"Scene score\"): the "
        "candidate nearest the vehicle within the match radius or its outline decides — none: no candidate; "
        "a rejection: refused, with its reason; a detection of another vehicle: taken; an unmatched "
        "detection: off centre. Vehicle-runs (each noise level's run counted), per cover level.\n\n| fate |";
  for (const std::string& c : covers) md << " " << c << " |";
  md << " all |\n|---|";
  for (std::size_t i = 0; i <= covers.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& [fate, by_cover] : n) {
    int all = 0;
    md << "| " << fate << " |";
    for (const std::string& c : covers) {
      const auto it = by_cover.find(c);
      md << " " << (it == by_cover.end() ? 0 : it->second) << " |";
    }
    for (const auto& [c, k] : by_cover) all += k;
    md << " " << all << " |\n";
  }
  md << "\n";
}

void pr_table(std::ostringstream& md, const SceneScore& score) {
  // Precision-recall: at most 12 rows (every k-th threshold and the last); all of it in pr.csv.
  const std::vector<ScoreRow>& pr = score.pr;
  md << "### Precision and recall over the confidence\n\n";
  if (pr.empty()) {
    md << "No detection: no curve.\n\n";
  } else {
    md << "Detections at or above each confidence threshold (all runs; " << pr.size()
       << " thresholds, every one in `scenes/pr.csv`).\n\n| confidence ≥ | detections | TP | FP | precision "
          "| recall |\n"
          "|---|---|---|---|---|---|\n";
    const std::size_t step = (pr.size() + 11) / 12;
    for (std::size_t i = 0; i < pr.size(); ++i) {
      if (i % step != 0 && i + 1 != pr.size()) continue;
      const ScoreRow& r = pr[i];
      md << "| " << num(score_field(r, "threshold"), "%.3f") << " | "
         << score_text(score_field(r, "detections")) << " | " << score_text(score_field(r, "tp")) << " | "
         << score_text(score_field(r, "fp")) << " | " << rate(score_field(r, "precision")) << " | "
         << rate(score_field(r, "recall")) << " |\n";
    }
    md << "\n";
  }
}

void reliability_table(std::ostringstream& md, const SceneScore& score, const SceneScore* collect_ablation,
                       const std::string& collect_ablation_path) {
  if (score.reliability.empty()) return;  // a score written before the table
  md << "### Reliability on the tiles (issue 29)\n\n"
        "Answers by the confidence they state and the share that was right (model level: the true model; "
        "class level: a class naming the truth; a false alarm is wrong; `none`: right unless a true vehicle "
        "that no detection found lies within the match radius of the rejected candidate's centre), from "
        "`scenes/reliability.csv`. The issue's target: within ±10 points of the stated confidence in every "
        "bin of at least 20 answers (judged on the mean stated confidence of the bin).\n\n";
  const int off = reliability_rows(md, score);
  if (!collect_ablation) return;
  if (!same_runs(*collect_ablation, score)) {
    md << "(" << collect_ablation_path << " scores other runs than canopy's: a stale collect ablation, not "
       << "shown.)\n\n";
    return;
  }
  md << "Collect's ablation, the same verdicts and class answers collected with one `none` map for every "
        "verify none (`collect --coarse-none-below 0`, mk/scenes.mk `SCENE_COLLECT_ABLATION`: the "
        "statement before docs/decisions/verify.md §19; by default verify's none of a candidate under 370 "
        "object points/m², the density rule's coarse candidates, states its own map), scored the same way "
        "(`scenes/collect-ablation/reliability.csv`). Which answer is given is the same; only the stated "
        "confidences of the nones differ.\n\n";
  if (collect_ablation->reliability.empty()) {
    md << "(" << collect_ablation_path << " has no reliability table.)\n\n";
    return;
  }
  const int ablation_off = reliability_rows(md, *collect_ablation);
  md << "Bins of at least 20 answers outside ±10 points: canopy " << off << ", the ablation " << ablation_off
     << ".\n\n";
}

// classify's ablations beside canopy (classify_ablations: the first, the second), per noise level
// when there are several, then over all of them (score_cells.h class_ablation_table).
void classify_ablations_table(std::ostringstream& md, const SceneScore& score,
                              const std::vector<SceneClassifyAblation>& ablations) {
  md << "### classify's ablations on the scene experiment\n\n"
        "Each default of the simulated tiles' classify parameters (`share/params/classify-sim.ini`) that "
        "changed keeps its ablation: the same candidates classified again with the ablation's parameter "
        "file (its header says which default it turns off, docs/decisions/classify.md why), collected with "
        "the same verdicts of the model chain and scored like canopy's (mk/scenes.mk "
        "`SCENES_CLASSIFY_ABLATION`, `SCENES_CLASSIFY_ABLATION_2`). Found at either level of each cover's "
        "vehicles, class right and the wrong class of the found and false alarms per ha (all covers), each "
        "with its count and score's 95% interval.\n\n";
  std::vector<std::string> noises;
  for (const ScoreRow& r : score.summary) {
    const std::string n = score_text(score_field(r, "noise_mm"));
    if (score_text(score_field(r, "cover")) == "all" && n != "all") noises.push_back(n);
  }
  if (noises.size() < 2) noises.clear();  // one noise level: its rows are the "all" rows
  noises.push_back("all");
  for (std::size_t i = 0; i < std::max<std::size_t>(ablations.size(), 2); ++i) {
    const std::string name = "classify's " + ablation_name(static_cast<int>(i) + 1);
    const SceneClassifyAblation* a = i < ablations.size() ? &ablations[i] : nullptr;
    if (a == nullptr || a->score == nullptr) {
      md << "**" << name << "**: not run (mk/scenes.mk `SCENES_CLASSIFY_ABLATION" << (i == 0 ? "" : "_2")
         << "` empty; report --tile-classify-ablation" << (i == 0 ? "" : "-2") << " not given).\n\n";
      continue;
    }
    if (!same_runs(*a->score, score)) {
      md << "**" << name << "** (`" << a->config << "`): " << a->path
         << " scores other runs than canopy's: a stale ablation, not shown.\n\n";
      continue;
    }
    md << "**" << name << "**, the candidates classified with `" << a->config << "` (" << a->path << "):\n\n";
    std::vector<AblationRung> rungs;
    for (const std::string& n : noises) rungs.push_back({n, &score, a->score, n});
    md << class_ablation_table("noise (mm)", rungs) << "\n";
  }
}

void baselines(std::ostringstream& md, const SceneScore& score, const std::vector<SceneStageTime>& times,
               const SceneVerifyAblation& verify_ablation, const std::vector<std::string>* methods) {
  std::vector<std::string> stale;
  const auto bl = baseline_scores(score, stale, verify_ablation, methods);
  if (!bl.empty()) md << baseline_markdown(score, bl, times, verify_ablation.options);
  for (const auto& p : stale) {
    md << "(" << p << " scores other runs than canopy's: a stale baseline run, not shown.)\n\n";
  }
}

void pictures(std::ostringstream& md, const std::vector<std::string>& covers, const std::string& fig) {
  md << "### The tiles from above\n\n"
        "Per cover level: rows = noise levels, columns = the first tiles; outlines: right model green, wrong "
        "model orange, false alarm magenta, missed vehicle yellow, found vehicle's true footprint white.\n\n";
  for (const auto& c : covers) md << "![" << c << " cover](" << fig << "/top-" << c << ".png)\n\n";
}

}  // namespace

bool is_scene_baseline_method(const std::string& method) {
  return std::find(std::begin(kBaselineMethods), std::end(kBaselineMethods), method) !=
         std::end(kBaselineMethods);
}

std::string scene_markdown(const SceneScore& score, const std::vector<SceneStageTime>& times,
                           const std::string& fig, const SceneScore* collect_ablation,
                           const std::string& collect_ablation_path,
                           const std::vector<SceneClassifyAblation>& classify_ablations,
                           const SceneVerifyAblation& verify_ablation,
                           const std::vector<std::string>* baseline_methods) {
  std::ostringstream md;
  const std::vector<ScoreRow>& summary = score.summary;
  std::vector<std::string> covers;
  std::set<std::string> renders;
  for (const documents::ScoreTile& t : score.tiles) {
    const std::string c = t.cover.value_or("–");
    if (std::find(covers.begin(), covers.end(), c) == covers.end() && c != "–") covers.push_back(c);
    renders.insert(std::filesystem::path(t.detections).parent_path().parent_path().string());
  }
  const ScoreRow* all = nullptr;
  for (const ScoreRow& s : summary) {
    if (score_text(score_field(s, "cover")) == "all" && score_text(score_field(s, "noise_mm")) == "all")
      all = &s;
  }
  scene_intro(md, score, all, renders.size());
  detection_table(md, summary);
  targets_table(md, summary, all);
  models_table(md, score);
  cover_table(md, score, fig);
  missed_table(md, score, covers);
  pr_table(md, score);
  reliability_table(md, score, collect_ablation, collect_ablation_path);
  classify_ablations_table(md, score, classify_ablations);
  md << clutter_markdown(score);
  baselines(md, score, times, verify_ablation, baseline_methods);
  md << scene_times_markdown(times);
  pictures(md, covers, fig);
  return md.str();
}

}  // namespace canopy::report
