// collect's messages: the one-line summary and the warning of a tile (formats/README.md
// "Detections": `warning`; docs/decisions/classify.md §11, real-tiles.md stop 70).
#include "collect/messages.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "canopy/documents/detections.h"

namespace canopy::collect {
namespace {

std::string fmt_density(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", d);
  return buf;
}

// "1 candidate", "3 candidates" (word: the singular; its plural adds an s).
std::string counted(long n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// The tile's density for messages: open ground's, else all points' (detect.md §7).
std::optional<double> tile_density(const Index& index) {
  return documents::open_ground_density(index.density);
}

// A density for the sentences of a tile without candidates: one decimal below 10 (a tile of
// 0.4 points/m² must not read "0").
std::string fmt_low_density(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, d < 10 ? "%.1f" : "%.0f", d);
  return buf;
}

// Why a tile has no candidate, in one sentence: its area, and its density against what the class
// level needs (too sparse), else that detect found no object of a vehicle's size.
std::string no_candidate(const Index& index, const std::optional<double>& td, bool ground) {
  std::string s = "no candidate on this tile";
  if (const auto ha = documents::occupied_hectares(index.density)) {
    char buf[48];
    std::snprintf(buf, sizeof buf, *ha < 1 ? " of %.2f ha" : " of %.1f ha", *ha);
    s += buf;
  }
  // (a tile in feet: detect read them as metres, and so are its area and density)
  if (!index.warnings.empty() && td) s += " (its area and density as detect read its coordinates)";
  if (!td) return s + " (the index states no density: an older detect)";
  const std::string density = ground ? "open-ground density " + fmt_low_density(*td) + " points/m²"
                                     : "tile density " + fmt_low_density(*td) + " points/m² (all returns)";
  if (*td < kClassDensity) {
    return s + ": its " + density + " is below the " + fmt_density(kClassDensity) +
           " points/m² the class level needs on an object (classify --min-density): too sparse for "
           "vehicles to be found; " +
           (index.warnings.empty() ? "a denser survey is the remedy" : "see detect's warning first");
  }
  return s + " (" + density +
         "): detect found no object of a vehicle's size and height between the ground and the canopy "
         "(detect's log counts the objects it rejected)";
}

// The warning on failed model chains: when the chain failed on most (or all) of the candidates it
// ran on, with the log of the first failed stage of the first such candidate; "" otherwise.
std::string chain_warning(const Index& index, const std::vector<Answers>& answers, const Outputs& out) {
  if (out.chain_ran == 0 || 2 * out.chain_failed <= out.chain_ran) return "";
  std::string example;
  for (std::size_t i = 0; i < answers.size() && example.empty(); ++i) {
    const Verdict& v = answers[i].model;
    if (!v.present || !v.failed) continue;
    example = index.candidates[i].id + ": " + (v.failed_log.empty() ? v.name + ".log" : v.failed_log);
  }
  std::string s = "the model chain failed on ";
  if (out.chain_failed == out.chain_ran) {
    s += out.chain_ran == 1 ? std::string("the one candidate")
                            : "all " + std::to_string(out.chain_ran) + " candidates";
    s += " it ran on: the model level decided nothing here, the answers are classify's alone";
  } else {
    s += std::to_string(out.chain_failed) + " of the " + std::to_string(out.chain_ran) +
         " candidates it ran on: those are answered by classify alone";
  }
  return s + " (the log of the first failed stage of " + example + ")";
}

}  // namespace

// One sentence when most candidates were rejected for one reason (with what would help), when
// no candidate reached the model level because the data is too sparse for it, when the model
// chain failed on most candidates it ran on, when the tile has no candidate (why); led by what
// detect warned about the tile (its index's "warnings": coordinates in feet, ...).
std::string warning_of(const Index& index, const std::vector<Answers>& answers, const Outputs& out,
                       const std::vector<std::string>& reasons, bool size_only) {
  const int n = static_cast<int>(index.candidates.size());
  const auto td = tile_density(index);
  // Which density it is: the open ground's (detect's "ground", what its density rule reads), else
  // all returns'; the picture's legend states all returns' (15.7 on ahn3_delft_1, whose open
  // ground has 11: "tile density 11" beside it read as a contradiction).
  const char* key = documents::open_ground_density_key(index.density);
  const bool ground = key != nullptr && std::string(key) == "ground";
  const std::string tile = !td      ? ""
                           : ground ? "open-ground density " + fmt_density(*td) + " points/m²"
                                    : "tile density " + fmt_density(*td) + " points/m² (all returns)";
  // detect's warnings first: they may explain all that follows (a tile in feet).
  std::vector<std::string> detect_parts;
  for (const auto& w : index.warnings) detect_parts.push_back("detect warned: " + w);
  auto joined = [](const std::vector<std::string>& ps) {
    std::string w;
    for (const auto& p : ps) w += (w.empty() ? "" : "; ") + p;
    return w;
  };
  if (n == 0) {
    detect_parts.push_back(no_candidate(index, td, ground));
    return joined(detect_parts);
  }
  // Densities and thresholds of the candidates classify answered.
  std::vector<double> dens;
  std::optional<double> need_class, need_model;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const Verdict& k = answers[i].cls;
    if (!k.present || k.failed) continue;
    if (reasons[i] == "too_sparse" && k.density) dens.push_back(*k.density);
    if (k.density_class) need_class = k.density_class;
    if (k.density_model) need_model = k.density_model;
  }
  const std::string chain = chain_warning(index, answers, out);
  // A chain that could not decide first: the rejections' reasons below are classify's alone.
  std::vector<std::string> parts;
  if (!chain.empty()) parts.push_back(chain);
  std::string top;
  int top_n = 0;
  for (const auto& [r, k] : out.by_reason) {
    if (k > top_n) top = r, top_n = k;
  }
  const bool mostly_sparse = 2 * top_n > n && top == "too_sparse";
  if (2 * top_n > n) {
    std::string s = std::to_string(top_n) + " of " + counted(n, "candidate") + " rejected as " + top;
    if (top == "too_sparse") {
      std::sort(dens.begin(), dens.end());
      if (!dens.empty()) {
        const std::size_t h = dens.size() / 2;
        const double median = dens.size() % 2 ? dens[h] : 0.5 * (dens[h - 1] + dens[h]);
        s += " (median object density " + fmt_density(median) + " points/m²";
      }
      if (need_class)
        s += std::string(dens.empty() ? " (" : ", ") + "class level needs " + fmt_density(*need_class);
      if (need_model) s += ", model level " + fmt_density(*need_model);
      if (!dens.empty() || need_class) s += ")";
      s += ": the survey is too sparse for these objects; a denser survey is the remedy";
    } else if (top == "failed") {
      // (the chain's warning above names the log)
      if (chain.empty()) s += ": a stage of the model chain failed; see cands/<id>/*.log";
    } else if (top == "none") {
      s += ": the model chain found no model of the modelbase in them";
    } else if (top == kLowConfidence) {
      s += ": their class answers state a confidence below collect --class-accept";
    } else if (top == "vegetation_like") {
      s += ": most candidates look like vegetation (porous, rough, pulses through them)";
    } else {
      s += " by classify's size and shape gates";
    }
    parts.push_back(s);
  }
  // No model chain ran (every candidate class level) because the objects are too sparse.
  int model_runs = 0;
  for (const auto& a : answers) model_runs += a.model.present ? 1 : 0;
  // (--size-only reads no verdict on purpose; a tile dense enough whose model chain did not
  // run is said so, not blamed on its density.)
  if (model_runs == 0 && !size_only) {
    const double need = need_model ? *need_model : kModelDensity;
    if (td && *td >= need) {
      parts.push_back(tile +
                      ": dense enough for model-level recognition, but no candidate has a model-chain "
                      "verdict; class-level answers only");
    } else {
      parts.push_back((tile.empty() ? std::string("the objects' density") : tile) + ": below the " +
                      fmt_density(need) + " points/m² that model-level recognition needs; " +
                      // Most candidates too sparse even for a class (said above): "only" would
                      // promise class answers the tile mostly cannot give.
                      (mostly_sparse ? "class-level answers at most" : "class-level answers only"));
    }
  }
  if (parts.empty()) return joined(detect_parts);
  detect_parts.insert(detect_parts.end(), parts.begin(), parts.end());
  return joined(detect_parts) + "; see docs/decisions/classify.md";
}

std::string summary_line(const Index& index, const Outputs& out) {
  std::string s = counted(static_cast<long>(index.candidates.size()), "candidate") + ": " +
                  counted(out.found, "vehicle") + " found (" + std::to_string(out.model_level) +
                  " model level, " + std::to_string(out.class_level) + " class level)";
  if (!out.by_reason.empty()) {
    s += "; rejected:";
    bool first = true;
    for (const auto& [r, k] : out.by_reason) {
      s += std::string(first ? " " : ", ") + r + " " + std::to_string(k);
      first = false;
    }
  }
  // A failed chain is said whatever answered the candidate (a class answer hides it from the
  // counts above): a tile where the chain could not decide must not read as one where it did.
  if (out.chain_failed > 0) {
    s += "; model chain failed on " + std::to_string(out.chain_failed) + " of the " +
         counted(out.chain_ran, "candidate") + " it ran on";
  }
  return s;
}

}  // namespace canopy::collect
