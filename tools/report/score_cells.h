// The cells of a scene score's rows (documents/scene_score.h) as the report's sections show
// them: the scene experiment, the PCL baseline beside it, the clutter table, the density ladder
// and the open set.
#pragma once

#include <optional>
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

}  // namespace canopy::report
