#include "report/clutter_section.h"

#include <sstream>
#include <vector>

#include "report/score_cells.h"
#include "report/report.h"

namespace canopy::report {
using documents::ScoreRow;
using documents::ScoreValue;

std::string clutter_kind_mark(const std::string& kind) {
  if (kind == "none") return "terrain, vegetation";
  if (kind == "vehicle") return "a true vehicle, off its centre";
  return clutter_kind_seen(kind) ? "seen" : "**unseen**";
}

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
        "true vehicle whose footprint seen from above holds its position (`vehicle`: an answer on a part, "
        "a merge or a fragment of a vehicle beyond the match radius of its centre, or a second answer on "
        "one), else on the clutter object whose box seen from above holds it, else on the nearest whose "
        "centre lies within the match radius, else on `none` (terrain, vegetation). *Seen* kinds are those "
        "verify's "
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
    const std::string kind = score_text(score_field(r, "kind"));
    const ScoreValue& objects = score_field(r, "objects");
    std::string objects_cell = "–", share = "–";
    if (objects.is_number()) {
      objects_cell = score_text(objects) + " (" + score_text(score_field(r, "objects_distinct")) + ")";
      share = score_text(score_field(r, "answered")) + "/" + score_text(objects) + " = " +
              score_ci(r, "answered_share", "%.1f%%", "%.1f", 100);
    }
    md << "| " << score_text(score_field(r, "cover")) << " | " << kind << " | " << clutter_kind_mark(kind)
       << " | " << objects_cell << " | " << score_text(score_field(r, "false_alarms")) << " ("
       << score_text(score_field(r, "model_level")) << " + " << score_text(score_field(r, "class_level"))
       << ") | " << score_ci(r, "false_alarms_per_ha", "%.1f", "%.1f", 1) << " | " << share << " |\n";
  }
  md << "\n";
  return md.str();
}

}  // namespace canopy::report
