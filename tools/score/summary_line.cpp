// score: the one-line summary it logs (score.h summary_line).
#include <cmath>
#include <cstdio>
#include <string>

#include "score/score.h"

namespace canopy::score {

using documents::ScoreRow;
using documents::ScoreValue;

std::string summary_line(std::size_t tiles, const ScoreRow& all) {
  auto cell = [&](const std::string& key) {
    const ScoreValue* v = documents::score_cell(all, key);
    return v ? *v : ScoreValue();
  };
  auto count = [&](const std::string& key) {
    const ScoreValue v = cell(key);
    return v.is_number() ? std::llround(v.as_number()) : 0LL;
  };
  auto fixed = [](const ScoreValue& v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", v.as_number());
    return std::string(buf);
  };
  // "num/den = rate [lo, hi]", or "num/den (n/a)" when the rate is null (nothing to count).
  auto rate = [&](const std::string& key, long long num, long long den) {
    const ScoreValue r = cell(key), lo = cell(key + "_lo"), hi = cell(key + "_hi");
    std::string out = std::to_string(num) + "/" + std::to_string(den);
    if (!r.is_number()) return out + " (n/a)";
    out += " = " + fixed(r);
    if (lo.is_number() && hi.is_number()) out += " [" + fixed(lo) + ", " + fixed(hi) + "]";
    return out;
  };
  const long long model = count("detections"), cls = count("class_detections"),
                  found = count("found_any_level");
  auto plural = [](long long n, const char* word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
  };
  return plural(static_cast<long long>(tiles), "tile") + ", " + plural(count("true"), "true vehicle") + ", " +
         plural(model + cls, "detection") + " (" + std::to_string(model) + " model level, " +
         std::to_string(cls) + " class level): recall " + rate("recall_any_level", found, count("true")) +
         ", precision " + rate("precision_any_level", found, model + cls) + ", class right " +
         rate("class_accuracy_any_level", count("class_right_any_level"), found) + ", model identified " +
         rate("identification", count("identified"), count("tp"));
}

}  // namespace canopy::score
