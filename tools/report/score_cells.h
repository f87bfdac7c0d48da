// The cells of a scene score's rows (documents/scene_score.h) as the report's sections show
// them: the scene experiment, the PCL baseline beside it, the clutter table, the density ladder
// and the open set.
#pragma once

#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/documents/scene_score.h"

namespace canopy::report {

// The cell `key` of `row`; a null value when the row has none.
const documents::ScoreValue& score_field(const documents::ScoreRow& row, const std::string& key);
// The cell as a number; nullopt when it is null, absent or text.
std::optional<double> score_number(const documents::ScoreRow& row, const std::string& key);
// A cell as text: a text as it is, an integer, a number ("%g"); "–" for null.
std::string score_text(const documents::ScoreValue& v);
// A whole count ("%.0f"); "–" when the cell is not a number.
std::string score_count(const documents::ScoreRow& row, const std::string& key);
// The cell `key` with score's 95% interval (<key>_lo, <key>_hi): the value with format `f`, the
// bounds with `fb`, each times `scale` ("95.0% [91.2, 97.8]" with "%.1f%%", "%.1f", 100); the
// value alone when the interval is missing; "–" when the value is not a number.
std::string score_ci(const documents::ScoreRow& row, const std::string& key, const char* f, const char* fb,
                     double scale);
// The summary rows over every noise level ("noise_mm" "all"): the covers in the score's order,
// then the row of every cover ("cover" "all").
std::vector<const documents::ScoreRow*> cover_rows(const documents::SceneScore& score);
// The summary row of cover label `cover` (a level, or "all") at noise `noise` ("all", or a level as
// score_text writes it: "0", "8"); nullptr when the score has none.
const documents::ScoreRow* summary_row(const documents::SceneScore& score, const std::string& cover,
                                       const std::string& noise = "all");

// A missed vehicle's fate as the report names it (score's matches, formats/README.md "Scene
// score"): "no candidate", "refused: <reason>" ("refused: no reason" when it has none), "taken",
// "off centre"; "unknown" for a row without one (a score written before stop 71).
std::string fate_label(const documents::ScoreMatch& missed);

// The rows of a score's reliability table (score's reliability.csv: level, confidence bin, answers,
// right with its 95% interval, mean stated confidence), the bins with answers only, each judged
// against the target when it holds >= 20 answers (right within ±10 points of the mean
// stated confidence); returns the number of such bins outside ±10 points.
int reliability_rows(std::ostringstream& md, const documents::SceneScore& score);

// Counts behind a rate: "k/n" of the cells k and n ("–" when either is not a number).
std::string counts(const documents::ScoreRow& r, const char* k, const char* n);
// A rate's cell: "k/n = x% [lo, hi]" (the rate `key` with score's interval); "–" for no row.
std::string rate_cell(const documents::ScoreRow* r, const char* key, const char* k, const char* n);
// False alarms per ha of a score row with their count: model-level false alarms (fp) + class
// answers on no vehicle (class_fp), "n = x [lo, hi]"; "–" for no row.
std::string false_alarm_cell(const documents::ScoreRow* r);

// One rung of a table of an ablation beside canopy: its label (a density level, a noise level),
// canopy's score and the ablation's on the same candidates, and the noise level of their summary
// rows to read ("all": over every noise level).
struct AblationRung {
  std::string label;
  const documents::SceneScore* canopy = nullptr;
  const documents::SceneScore* ablation = nullptr;
  std::string noise = "all";
};
// The table of a classify ablation beside canopy (the density ladder's, the scene experiment's),
// `rung` its first column's title: per rung, found at either level of each cover's vehicles
// (light, medium, dense, those either score has), then over all covers class right and the wrong
// class of the found, and false alarms per ha; each "k/n = rate [lo, hi]" with score's 95%
// interval (a false alarm count before its rate per ha).
std::string class_ablation_table(const std::string& rung, const std::vector<AblationRung>& rungs);

// An ablation's name by its place `n` among the ablations of one stage (1: the first): "ablation",
// "second ablation" to "sixth ablation", then "ablation 7", ... The density ladder's classify
// ablations (the rung's own, then its classify_more), the real tiles' and the scene experiment's.
std::string ablation_name(int n);

// Whether an ablation's entry (mk/density.mk's DENSITY_DETECT_ABLATIONS, mk/real.mk's
// REAL_CLASSIFY_ABLATIONS) sets the model level, TILE_MODEL_DENSITY=<value>, rather than naming a
// parameter file: the density ladder's and the real tiles' sections give it its own table.
bool model_level_entry(const std::string& entry);

}  // namespace canopy::report
