// famscore: confusion matrix and accuracies of the families protocol (famscore.h).
#include "famscore/famscore.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "canopy/common/error.h"
#include "rangetrace/families.h"

namespace canopy::famscore {

using common::DataError;

std::vector<Run> parse_runs(const std::string& text, const std::string& name) {
  std::vector<Run> runs;
  std::istringstream in(text);
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    line = line.substr(0, line.find('#'));
    std::istringstream ls(line);
    std::vector<std::string> w;
    for (std::string s; ls >> s;) w.push_back(s);
    if (w.empty()) continue;
    const std::string where = "line " + std::to_string(no) + ": ";
    if (w.size() != 5) throw DataError(name, where + "expected <verdict> <class> <instance> <cover> <noise>");
    if (w[2].empty() || w[2].size() > 9 || w[2].find_first_not_of("0123456789") != std::string::npos) {
      throw DataError(name, where + "instance '" + w[2] + "' is not a number 0..999999999");
    }
    Run r;
    r.verdict = w[0];
    r.vehicle_class = w[1];
    r.instance = std::stoi(w[2]);
    r.cover = w[3];
    r.noise = w[4];
    r.line = no;
    runs.push_back(r);
  }
  if (runs.empty()) throw DataError(name, "no trial in the runs manifest");
  return runs;
}

namespace {

Eigen::Vector3d size_of(const std::string& cls, int instance) {
  const auto f = rangetrace::make_family_instance(cls, instance);
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
  for (const auto& c : rangetrace::family_classes()) {
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
  std::string out = "true_class";
  for (const auto& c : cols) out += "," + c;
  out += "\n";
  for (const auto& r : rows) {
    out += r;
    for (const auto& c : cols) out += "," + std::to_string(n[{r, c}]);
    out += "\n";
  }
  return out;
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
  std::string out =
      "cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,"
      "nearest_accuracy,failed\n";
  char buf[256];
  for (const auto& k : keys) {
    const Count& c = counts[k];
    std::snprintf(buf, sizeof buf, "%s,%s,%d,%d,%.4f,%d,%d,%d,%.4f,%d\n", k.first.c_str(), k.second.c_str(),
                  c.trials, c.right, static_cast<double>(c.right) / c.trials, c.accepted, c.accepted_right,
                  c.nearest, static_cast<double>(c.nearest) / c.trials, c.failed);
    out += buf;
  }
  return out;
}

}  // namespace canopy::famscore
