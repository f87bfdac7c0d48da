#include "report/score_cells.h"

#include "report/report.h"

namespace canopy::report {

using documents::ScoreRow;
using documents::ScoreValue;

const ScoreValue& score_field(const ScoreRow& row, const std::string& key) {
  static const ScoreValue null_value;
  const ScoreValue* v = documents::score_cell(row, key);
  return v != nullptr ? *v : null_value;
}

std::optional<double> score_number(const ScoreRow& row, const std::string& key) {
  const ScoreValue& v = score_field(row, key);
  return v.is_number() ? std::optional<double>(v.as_number()) : std::nullopt;
}

std::string score_text(const ScoreValue& v) {
  switch (v.kind) {
    case ScoreValue::Kind::text: return v.text;
    case ScoreValue::Kind::integer: return std::to_string(v.integer);
    case ScoreValue::Kind::number: return format_number("%g", v.number);
    case ScoreValue::Kind::null: break;
  }
  return "–";
}

std::string score_count(const ScoreRow& row, const std::string& key) {
  const auto v = score_number(row, key);
  return v ? format_number("%.0f", *v) : "–";
}

std::string score_ci(const ScoreRow& row, const std::string& key, const char* f, const char* fb, double scale) {
  const auto v = score_number(row, key), lo = score_number(row, key + "_lo"),
             hi = score_number(row, key + "_hi");
  if (!v) return "–";
  std::string out = format_number(f, scale * *v);
  if (lo && hi) out += " [" + format_number(fb, scale * *lo) + ", " + format_number(fb, scale * *hi) + "]";
  return out;
}

std::vector<const ScoreRow*> cover_rows(const documents::SceneScore& s) {
  std::vector<const ScoreRow*> rows;
  const ScoreRow* all = nullptr;
  for (const ScoreRow& r : s.summary) {
    const ScoreValue &c = score_field(r, "cover"), &n = score_field(r, "noise_mm");
    if (n.kind != ScoreValue::Kind::text || n.text != "all" || c.kind != ScoreValue::Kind::text) continue;
    if (c.text == "all")
      all = &r;
    else
      rows.push_back(&r);
  }
  if (all != nullptr) rows.push_back(all);
  return rows;
}

}  // namespace canopy::report
