// The score of detections against the truth of one or many tiles: score.json, format
// "canopy.scene_score", version 1 (formats/README.md "Scene scores"). score writes it (and its
// CSV tables); report (real tiles) and topview (outcome colours) read it here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

inline constexpr const char* kSceneScoreFormat = "canopy.scene_score";
inline constexpr int kSceneScoreVersion = 1;

// A cell of the score's tables (summary, pr, models, cover_bins): null, an integer, a number
// or a text, written as such (an integer 3 as "3", a number 3 as "3.0").
struct ScoreValue {
  enum class Kind { null, integer, number, text };
  Kind kind = Kind::null;
  std::int64_t integer = 0;
  double number = 0;
  std::string text;

  ScoreValue() = default;
  ScoreValue(std::nullptr_t) {}  // NOLINT(google-explicit-constructor): a table cell from any value
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  ScoreValue(T v) : kind(Kind::integer), integer(static_cast<std::int64_t>(v)) {}  // NOLINT
  ScoreValue(double v) : kind(Kind::number), number(v) {}                          // NOLINT
  ScoreValue(const char* v) : kind(Kind::text), text(v) {}                         // NOLINT
  ScoreValue(std::string v) : kind(Kind::text), text(std::move(v)) {}              // NOLINT

  bool is_number() const { return kind == Kind::integer || kind == Kind::number; }
  double as_number() const { return kind == Kind::integer ? static_cast<double>(integer) : number; }
};

// A table row: its columns in order.
using ScoreRow = std::vector<std::pair<std::string, ScoreValue>>;
// The value of `key` in `row`, nullptr when the row has no such column.
const ScoreValue* score_cell(const ScoreRow& row, const std::string& key);

struct ScoreParams {
  std::optional<double> match_radius_m;  // > 0
  std::vector<double> cover_bins;
  std::optional<double> flip_threshold_deg;
};

// One tile scored. score writes every member; a reader type-checks those present.
struct ScoreTile {
  std::string detections, truth;  // the files, as given ("" when absent)
  std::optional<std::string> cover;
  std::optional<double> noise_mm;
  std::optional<double> area_ha;  // >= 0
  std::optional<std::int64_t> true_count, tp, fp, fn, class_detections, class_tp, class_fp, fn_any_level;
};

// One row of "matches": a detection (by falling confidence, model level then class level) or a
// missed true vehicle.
struct ScoreMatch {
  std::int64_t tile = 0;                 // index into tiles
  std::optional<std::string> candidate;  // detections' candidate id; null for a missed vehicle
  std::optional<std::string> level, model, cls;
  std::optional<double> confidence, x, y, heading;
  std::string outcome;                   // right, wrong, false_alarm or missed
  std::optional<std::int64_t> instance;  // the true vehicle (right, wrong, missed)
  std::optional<std::string> true_model;
  std::optional<double> cover, distance_m, heading_error_deg;
  // A missed vehicle's fate (stop 71; null on other rows and in older scores): "no_candidate",
  // "refused", "taken" or "off_centre" (formats/README.md "Scene score"), the candidate it
  // names, a refusal's reason and that candidate's object density (points per m²).
  std::optional<std::string> fate, fate_candidate, fate_reason;
  std::optional<double> fate_density;
};

struct SceneScore {
  // Reading: provenance.parameters whose values are texts, in order (report finds score's --csv
  // there); the writer takes its provenance apart and ignores this.
  std::vector<std::pair<std::string, std::string>> parameters;
  bool has_params = false;
  ScoreParams params;
  std::vector<ScoreTile> tiles;
  std::vector<ScoreRow> summary, pr, models, cover_bins;
  std::vector<ScoreRow> reliability;  // absent in scores written before issue 29's table: empty
  std::vector<ScoreRow> clutter;      // false alarms by clutter kind (issue 29); older scores: empty
  std::vector<ScoreMatch> matches;
};

// The text score writes (one space indent, a final newline): format, version, `provenance`,
// params, tiles, summary, pr, models, cover_bins, reliability, clutter, matches. Throws common::Error when
// params or a tile's counts are missing (a writer's bug).
std::string write_scene_score(const SceneScore& s, const formats::Provenance& provenance);

// A table of the score as CSV: "summary", "pr", "models", "cover_bins", "reliability", "clutter" or
// "matches"; the columns of the first row, numbers with %.10g, integers as they are, null empty, texts quoted
// when they hold a comma, quote or newline. "" for an empty table; common::Error for another name.
std::string scene_score_csv(const SceneScore& s, const std::string& table);

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1, "tiles" or "matches" missing or not arrays, a tile
// that is not an object, a match whose tile is not one of the tiles, whose outcome is not right,
// wrong, false_alarm or missed, a detection's row without a candidate (or a candidate with a
// second outcome in its tile), a right, wrong or missed row without an integer instance >= 0, a
// table row that is not an object of scalars, any member of a wrong type. Members score writes
// that a hand-written score leaves out are optional (params, a tile's counts, x, y, ...).
SceneScore read_scene_score(const std::string& text, const std::string& name);
SceneScore read_scene_score_file(const std::string& path);

}  // namespace canopy::documents
