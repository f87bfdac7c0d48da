#include "report/score_cells.h"

#include <cmath>
#include <iterator>
#include <sstream>

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

const ScoreRow* summary_row(const documents::SceneScore& score, const std::string& cover,
                            const std::string& noise) {
  for (const ScoreRow& r : score.summary) {
    const ScoreValue &c = score_field(r, "cover"), &n = score_field(r, "noise_mm");
    if (c.kind == ScoreValue::Kind::text && c.text == cover && score_text(n) == noise) return &r;
  }
  return nullptr;
}

std::string counts(const ScoreRow& r, const char* k, const char* n) {
  const auto a = score_number(r, k), b = score_number(r, n);
  return a && b ? format_number("%.0f", *a) + "/" + format_number("%.0f", *b) : "–";
}

std::string rate_cell(const ScoreRow* r, const char* key, const char* k, const char* n) {
  if (r == nullptr) return "–";
  return counts(*r, k, n) + " = " + score_ci(*r, key, "%.1f%%", "%.1f", 100);
}

namespace {

// The found whose class is wrong: found - class right of found, 1 - class right's rate and its
// interval turned over.
std::string wrong_class_cell(const ScoreRow* r) {
  if (r == nullptr) return "–";
  const auto found = score_number(*r, "found_any_level"), right = score_number(*r, "class_right_any_level"),
             v = score_number(*r, "class_accuracy_any_level"),
             lo = score_number(*r, "class_accuracy_any_level_lo"),
             hi = score_number(*r, "class_accuracy_any_level_hi");
  std::string out = found && right
                        ? format_number("%.0f", *found - *right) + "/" + format_number("%.0f", *found)
                        : std::string("–");
  if (!v) return out + " = –";
  out += " = " + format_number("%.1f%%", 100 * (1 - *v));
  if (lo && hi)
    out += " [" + format_number("%.1f", 100 * (1 - *hi)) + ", " + format_number("%.1f", 100 * (1 - *lo)) + "]";
  return out;
}

}  // namespace

std::string false_alarm_cell(const ScoreRow* r) {
  if (r == nullptr) return "–";
  const auto a = score_number(*r, "fp"), b = score_number(*r, "class_fp");
  return (a && b ? format_number("%.0f", *a + *b) + " = " : std::string()) +
         score_ci(*r, "false_alarms_any_level_per_ha", "%.1f", "%.1f", 1);
}

std::string ablation_name(int n) {
  static const char* const nth[] = {"second", "third", "fourth", "fifth", "sixth"};
  if (n <= 1) return "ablation";
  if (static_cast<std::size_t>(n - 2) < std::size(nth)) return std::string(nth[n - 2]) + " ablation";
  return "ablation " + std::to_string(n);
}

bool model_level_entry(const std::string& entry) { return entry.rfind("TILE_MODEL_DENSITY=", 0) == 0; }

std::string class_ablation_table(const std::string& rung, const std::vector<AblationRung>& rungs) {
  std::string md = "| " + rung + " | measure | canopy | ablation |\n|---|---|---|---|\n";
  const auto row = [](const documents::SceneScore* s, const std::string& cover, const std::string& noise) {
    return s == nullptr ? nullptr : summary_row(*s, cover, noise);
  };
  for (const AblationRung& g : rungs) {
    const std::string head = "| " + g.label + " | ";
    for (const char* cover : {"light", "medium", "dense"}) {
      const ScoreRow* c = row(g.canopy, cover, g.noise);
      const ScoreRow* b = row(g.ablation, cover, g.noise);
      if (c == nullptr && b == nullptr) continue;
      md += head + "recall, " + cover + " | " + rate_cell(c, "recall_any_level", "found_any_level", "true") +
            " | " + rate_cell(b, "recall_any_level", "found_any_level", "true") + " |\n";
    }
    const ScoreRow* c = row(g.canopy, "all", g.noise);
    const ScoreRow* b = row(g.ablation, "all", g.noise);
    md += head + "class right (all) | " +
          rate_cell(c, "class_accuracy_any_level", "class_right_any_level", "found_any_level") + " | " +
          rate_cell(b, "class_accuracy_any_level", "class_right_any_level", "found_any_level") + " |\n";
    md += head + "wrong class (all) | " + wrong_class_cell(c) + " | " + wrong_class_cell(b) + " |\n";
    md += head + "false alarms/ha (all) | " + false_alarm_cell(c) + " | " + false_alarm_cell(b) + " |\n";
  }
  return md;
}

int reliability_rows(std::ostringstream& md, const documents::SceneScore& score) {
  md << "| level | confidence | answers | right | mean stated | within ±10 points |\n"
        "|---|---|---|---|---|---|\n";
  int off = 0;
  for (const ScoreRow& r : score.reliability) {
    const ScoreValue& n = score_field(r, "answers");
    if (!n.is_number() || n.as_number() <= 0) continue;
    const auto rate = score_number(r, "rate"), mean = score_number(r, "mean_confidence");
    std::string within = "– (< 20)";
    if (n.as_number() >= 20 && rate && mean) {
      const bool ok = std::fabs(*rate - *mean) <= 0.1;
      within = ok ? "yes" : "**no**";
      off += !ok;
    }
    const auto lo = score_number(r, "confidence_lo"), hi = score_number(r, "confidence_hi");
    md << "| " << score_text(score_field(r, "level")) << " | " << (lo ? format_number("%.1f", *lo) : "–")
       << "–" << (hi ? format_number("%.1f", *hi) : "–") << " | " << score_text(n) << " | "
       << score_text(score_field(r, "right")) << " = " << score_ci(r, "rate", "%.1f%%", "%.1f", 100) << " | "
       << (mean ? format_number("%.1f%%", 100 * *mean) : "–") << " | " << within << " |\n";
  }
  md << "\n";
  return off;
}

std::string fate_label(const documents::ScoreMatch& m) {
  if (!m.fate) return "unknown";
  if (*m.fate == "refused") return "refused: " + m.fate_reason.value_or("no reason");
  if (*m.fate == "no_candidate") return "no candidate";
  if (*m.fate == "off_centre") return "off centre";
  return *m.fate;
}

}  // namespace canopy::report
