// famscore: confusion matrix and accuracies of the families protocol (famscore.h).
#include "famscore/famscore.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/documents/baseline_ranking.h"
#include "canopy/documents/family_tables.h"
#include "canopy/documents/modelbase.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/stage_time.h"
#include "canopy/documents/stage_outcome.h"
#include "canopy/sim/families.h"

namespace canopy::famscore {

using common::DataError;

namespace {

Eigen::Vector3d size_of(const std::string& cls, int instance) {
  const auto f = sim::make_family_instance(cls, instance);
  return f.hi - f.lo;
}

}  // namespace

std::string nearest_by_size(const std::string& cls, int instance, const std::vector<Entry>& entries) {
  const Eigen::Vector3d target = size_of(cls, instance);
  std::string best;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& e : entries) {
    const std::string prefix = cls + "-";
    if (e.vehicle_class != cls || e.model.rfind(prefix, 0) != 0) continue;
    const std::string num = e.model.substr(prefix.size());
    if (num.empty() || num.size() > 9 || num.find_first_not_of("0123456789") != std::string::npos) continue;
    const double d = (size_of(cls, std::stoi(num)) - target).norm();
    if (d < best_d) {
      best_d = d;
      best = e.model;
    }
  }
  return best;
}

std::vector<std::string> class_order(const std::vector<std::string>& classes) {
  std::vector<std::string> out, rest;
  for (const auto& c : sim::family_classes()) {
    if (std::find(classes.begin(), classes.end(), c.name) != classes.end()) out.push_back(c.name);
  }
  for (const auto& c : classes) {
    if (std::find(out.begin(), out.end(), c) == out.end() &&
        std::find(rest.begin(), rest.end(), c) == rest.end() && c != "none") {
      rest.push_back(c);
    }
  }
  std::sort(rest.begin(), rest.end());
  out.insert(out.end(), rest.begin(), rest.end());
  return out;
}

std::string confusion_csv(const std::vector<Trial>& trials, const std::vector<Entry>& entries) {
  std::vector<std::string> truth, answered;
  for (const auto& t : trials) {
    truth.push_back(t.run.vehicle_class);
    answered.push_back(t.answered_class);
  }
  for (const auto& e : entries) answered.push_back(e.vehicle_class);
  const auto rows = class_order(truth);
  auto cols = class_order(answered);
  cols.push_back("none");
  std::map<std::pair<std::string, std::string>, int> n;
  for (const auto& t : trials) ++n[{t.run.vehicle_class, t.answered_class}];
  documents::FamilyConfusion table{cols, {}};
  for (const auto& r : rows) {
    documents::FamilyConfusion::Row row{"", r, {}};
    for (const auto& c : cols) row.answered.push_back(n[{r, c}]);
    table.rows.push_back(std::move(row));
  }
  return documents::serialize_family_confusion(table, false);
}

std::string accuracy_csv(const std::vector<Trial>& trials) {
  struct Count {
    int trials = 0, right = 0, accepted = 0, accepted_right = 0, nearest = 0, failed = 0;
  };
  std::vector<std::pair<std::string, std::string>> keys;
  std::map<std::pair<std::string, std::string>, Count> counts;
  auto add = [&](const std::pair<std::string, std::string>& k, const Trial& t) {
    if (!counts.count(k)) keys.push_back(k);
    Count& c = counts[k];
    const bool right = t.answered_class == t.run.vehicle_class;
    ++c.trials;
    c.right += right;
    c.accepted += t.accepted;
    c.accepted_right += t.accepted && right;
    c.nearest += !t.expected_nearest.empty() && t.nearest == t.expected_nearest;
    c.failed += t.failed;
  };
  for (const auto& t : trials) add({t.run.cover, t.run.noise}, t);
  for (const auto& t : trials) add({"all", "all"}, t);
  std::vector<documents::FamilyAccuracyRow> rows;
  for (const auto& k : keys) {
    const Count& c = counts[k];
    rows.push_back({k.first, k.second, c.trials, c.right, c.accepted, c.accepted_right, c.nearest, c.failed});
  }
  return documents::serialize_family_accuracy(rows);
}

const std::vector<std::string>& methods() {
  static const std::vector<std::string> m = {"gmatch", "verify", "vfh", "fpfh"};
  return m;
}

std::vector<std::string> method_stages(const std::string& method) {
  if (method == "gmatch") return {"mesh.ply", "segments.json", "match.json"};
  if (method == "verify") return {"mesh.ply", "segments.json", "match.json", "verdict.json"};
  if (method == "vfh") return {"baseline-vfh.json"};
  if (method == "fpfh") return {"baseline-fpfh.json"};
  throw std::invalid_argument("famscore: unknown method " + method);
}

std::vector<Entry> read_entries(const std::string& modelbase) {
  namespace fs = std::filesystem;
  std::error_code ec;
  documents::require_modelbase_dir(modelbase, "<model>.class files");
  std::vector<fs::path> files;
  for (const auto& f : fs::directory_iterator(modelbase)) {
    if (f.path().extension() == ".class") files.push_back(f.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Entry> entries;
  for (const auto& f : files) {
    const std::string model = f.stem().string();
    const auto cls = documents::read_model_class(modelbase, model);
    if (!cls) throw DataError(f.string(), "vanished while the modelbase was read");
    entries.push_back({model, *cls});
  }
  if (entries.empty()) throw DataError(modelbase, "no <model>.class file: the modelbase carries no classes");
  return entries;
}

namespace {

// A stage's wall seconds from its .time file; false when absent, unreadable or not a duration.
bool stage_seconds(const std::string& artifact, double& seconds) {
  const documents::StageTime t = documents::read_stage_time(artifact);
  if (!t.present || !std::isfinite(t.seconds) || t.seconds < 0) return false;
  seconds = t.seconds;
  return true;
}

// The rank-1 model of `method` in a canopy.baseline document; "" when it ranks no model or its
// best score is 0 (FPFH: RANSAC found no pose for any model).
std::string baseline_rank1(const std::string& text, const std::string& path, const std::string& method) {
  for (const auto& m : documents::parse_baseline_ranking(text, path)) {
    if (m.method != method) continue;
    if (m.models.empty()) return "";
    const auto& best = m.models.front();
    if (!best.score)
      throw DataError(path, "malformed canopy.baseline: " + method + "'s rank-1 model has no score");
    return *best.score > 0 ? best.model : "";
  }
  throw DataError(path, "no method '" + method + "' in the baseline document");
}

std::string class_of(const std::string& model, const std::vector<Entry>& entries) {
  for (const auto& e : entries) {
    if (e.model == model) return e.vehicle_class;
  }
  return "none";  // no model, or a model without a class file
}

}  // namespace

Trial read_trial(const Run& r, const std::vector<Entry>& entries, bool with_methods) {
  namespace fs = std::filesystem;
  Trial t;
  t.run = r;
  t.expected_nearest = nearest_by_size(r.vehicle_class, r.instance, entries);
  const documents::StageVerdict sv = documents::parse_stage_verdict(common::read_file(r.verdict), r.verdict);
  if (sv.outcome == documents::StageOutcome::failed) {  // a stage failed on this trial
    t.answered_class = "none";
    t.failed = true;
  } else {
    const documents::Verdict& v = sv.verdict;
    if (!v.has_classes) throw DataError(r.verdict, "verdict names no class (modelbase without classes?)");
    t.answered_class = v.vehicle_class.empty() ? "none" : v.vehicle_class;
    t.nearest = v.nearest_instance;
    t.accepted = !v.model.empty();
  }
  if (!with_methods) return t;
  const std::string dir = fs::path(r.verdict).parent_path().string();
  const std::string in = dir.empty() ? "" : dir + "/";
  for (const auto& m : methods()) {
    Answer a;
    if (m == "verify") {
      a.model = t.nearest;
      a.answered_class = t.answered_class;
      a.failed = t.failed;
    } else {
      const std::string path = in + (m == "gmatch" ? "match.json" : "baseline-" + m + ".json");
      std::error_code ec;
      if (!fs::exists(path, ec)) throw DataError(path, "missing (the " + m + " answer of the trial)");
      const std::string text = common::read_file(path);
      if (text.empty()) {
        a.failed = true;
      } else if (m == "gmatch") {
        const documents::MatchResult mr = documents::parse_match_result(text, path);
        if (!mr.models.empty()) a.model = mr.models.front().model;
      } else {
        a.model = baseline_rank1(text, path, m);
      }
      a.answered_class = a.model.empty() ? "none" : class_of(a.model, entries);
    }
    a.timed = true;
    for (const auto& stage : method_stages(m)) {
      double s = 0;
      if (!stage_seconds(in + stage, s)) {
        a.timed = false;
        a.seconds = 0;
        break;
      }
      a.seconds += s;
    }
    t.answers.push_back(a);
  }
  return t;
}

std::string methods_csv(const std::vector<Trial>& trials) {
  struct Count {
    int trials = 0, right = 0, nearest = 0, failed = 0, timed = 0;
    double seconds = 0;
  };
  std::vector<documents::FamilyMethodRow> rows;
  std::vector<std::string> truth, covers, noises;
  for (const auto& t : trials) {
    truth.push_back(t.run.vehicle_class);
    if (std::find(covers.begin(), covers.end(), t.run.cover) == covers.end()) covers.push_back(t.run.cover);
    if (std::find(noises.begin(), noises.end(), t.run.noise) == noises.end()) noises.push_back(t.run.noise);
  }
  std::vector<std::array<std::string, 3>> keys = {{"all", "all", "all"}};
  for (const auto& c : class_order(truth)) keys.push_back({c, "all", "all"});
  for (const auto& v : covers) keys.push_back({"all", v, "all"});
  for (const auto& z : noises) keys.push_back({"all", "all", z});
  for (std::size_t m = 0; m < methods().size(); ++m) {
    for (const auto& k : keys) {
      Count c;
      for (const auto& t : trials) {
        if (t.answers.size() != methods().size())
          throw std::logic_error("famscore: methods_csv needs trials read with their methods");
        if ((k[0] != "all" && t.run.vehicle_class != k[0]) || (k[1] != "all" && t.run.cover != k[1]) ||
            (k[2] != "all" && t.run.noise != k[2]))
          continue;
        const Answer& a = t.answers[m];
        ++c.trials;
        c.right += a.answered_class == t.run.vehicle_class;
        c.nearest += !t.expected_nearest.empty() && a.model == t.expected_nearest;
        c.failed += a.failed;
        if (a.timed) {
          ++c.timed;
          c.seconds += a.seconds;
        }
      }
      if (c.trials == 0) continue;
      rows.push_back({methods()[m], k[0], k[1], k[2], c.trials, c.right, c.nearest, c.failed, c.timed,
                      c.timed > 0 ? c.seconds / c.timed : 0.0});
    }
  }
  return documents::serialize_family_methods(rows);
}

std::string methods_confusion_csv(const std::vector<Trial>& trials, const std::vector<Entry>& entries) {
  std::vector<std::string> truth, answered;
  for (const auto& t : trials) {
    truth.push_back(t.run.vehicle_class);
    for (const auto& a : t.answers) answered.push_back(a.answered_class);
  }
  for (const auto& e : entries) answered.push_back(e.vehicle_class);
  const auto rows = class_order(truth);
  auto cols = class_order(answered);
  cols.push_back("none");
  documents::FamilyConfusion table{cols, {}};
  for (std::size_t m = 0; m < methods().size(); ++m) {
    std::map<std::pair<std::string, std::string>, int> n;
    for (const auto& t : trials) {
      if (t.answers.size() != methods().size())
        throw std::logic_error("famscore: methods_confusion_csv needs trials read with their methods");
      ++n[{t.run.vehicle_class, t.answers[m].answered_class}];
    }
    for (const auto& r : rows) {
      documents::FamilyConfusion::Row row{methods()[m], r, {}};
      for (const auto& c : cols) row.answered.push_back(n[{r, c}]);
      table.rows.push_back(std::move(row));
    }
  }
  return documents::serialize_family_confusion(table, true);
}

Outputs run(const Params& params, const Inputs& inputs) {
  validate(params);
  const auto runs = documents::parse_family_runs(inputs.runs_text, inputs.runs_name);
  const std::vector<Entry> entries = read_entries(inputs.modelbase);
  std::vector<Trial> trials;
  for (const auto& r : runs) {
    // A class the families do not know is the manifest's error (it was a usage error, exit 2,
    // naming no file: "unknown vehicle class 'car' (classes: …)").
    try {
      sim::make_family_instance(r.vehicle_class, r.instance);
    } catch (const common::UsageError& e) {
      throw DataError(inputs.runs_name, "line " + std::to_string(r.line) + ": " + e.what());
    }
    trials.push_back(read_trial(r, entries, params.with_methods));
  }
  Outputs out;
  out.confusion = confusion_csv(trials, entries);
  out.accuracy = accuracy_csv(trials);
  if (params.with_methods) {
    out.methods = methods_csv(trials);
    out.methods_confusion = methods_confusion_csv(trials, entries);
  }
  out.trials = trials.size();
  out.entries = entries.size();
  return out;
}

}  // namespace canopy::famscore
