#include "report/clutter_section.h"

#include <sstream>
#include <vector>

#include "report/density_section.h"
#include "report/report.h"

namespace canopy::report {
namespace {

using documents::ScoreRow;
using documents::ScoreValue;

const ScoreValue& cell(const ScoreRow& row, const std::string& key) { return score_cell_or_null(row, key); }

std::string text(const ScoreValue& v) {
  if (v.kind == ScoreValue::Kind::text) return v.text;
  if (v.kind == ScoreValue::Kind::integer) return std::to_string(v.integer);
  if (v.kind == ScoreValue::Kind::number) return format_number("%g", v.number);
  return "–";
}

// "v [lo, hi]": the value with `f`, the bounds with `fb`, each times `scale` (the value alone
// when the interval is missing); "–" for null.
std::string with_ci(const ScoreRow& row, const std::string& key, const char* f, const char* fb, double scale) {
  const ScoreValue &v = cell(row, key), &lo = cell(row, key + "_lo"), &hi = cell(row, key + "_hi");
  if (!v.is_number()) return "–";
  std::string out = format_number(f, scale * v.as_number());
  if (lo.is_number() && hi.is_number())
    out += " [" + format_number(fb, scale * lo.as_number()) + ", " +
           format_number(fb, scale * hi.as_number()) + "]";
  return out;
}

std::string mark(const std::string& kind) {
  if (kind == "none") return "terrain, vegetation";
  return clutter_kind_seen(kind) ? "seen" : "**unseen**";
}

}  // namespace

bool clutter_kind_seen(const std::string& kind) {
  for (const char* k : {"boulder", "shed", "container", "fence", "logs"}) {
    if (kind == k) return true;
  }
  return false;
}

std::string clutter_markdown(const documents::SceneScore& score) {
  if (score.clutter.empty()) return "";
  std::ostringstream md;
  md << "### False alarms by clutter kind (issue 29)\n\n"
        "Each false alarm (a detection matched to no vehicle, model or class level) is put on the truth's "
        "clutter object whose box seen from above holds its position, else on the nearest whose centre lies "
        "within the match radius, else on `none` (terrain, vegetation). *Seen* kinds are those verify's "
        "acceptance and classify's thresholds were fitted on (boulder, shed, container, fence, logs); "
        "*unseen* kinds were never part of a fit (docs/decisions/scene-experiment.md, \"Unseen clutter\"). "
        "Objects are counted per run (distinct renders in brackets); false alarms per hectare of the runs "
        "with the exact Poisson 95% interval (hull with the bootstrap over renders); the share of the "
        "objects answered as a vehicle (at least one false alarm on it) with Wilson's interval. "
        "`scenes/clutter.csv`.\n\n"
        "| cover | kind | | objects | false alarms (model + class) | per ha | objects answered as a vehicle "
        "|\n"
        "|---|---|---|---|---|---|---|\n";
  for (const ScoreRow& r : score.clutter) {
    const std::string kind = text(cell(r, "kind"));
    const ScoreValue& objects = cell(r, "objects");
    std::string objects_cell = "–", share = "–";
    if (objects.is_number()) {
      objects_cell = text(objects) + " (" + text(cell(r, "objects_distinct")) + ")";
      share = text(cell(r, "answered")) + "/" + text(objects) + " = " +
              with_ci(r, "answered_share", "%.1f%%", "%.1f", 100);
    }
    md << "| " << text(cell(r, "cover")) << " | " << kind << " | " << mark(kind) << " | " << objects_cell
       << " | " << text(cell(r, "false_alarms")) << " (" << text(cell(r, "model_level")) << " + "
       << text(cell(r, "class_level")) << ") | " << with_ci(r, "false_alarms_per_ha", "%.1f", "%.1f", 1)
       << " | " << share << " |\n";
  }
  md << "\n";
  return md.str();
}

}  // namespace canopy::report
