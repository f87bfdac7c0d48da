// The scene section's "False alarms by clutter kind" table (issue 29): a hand-written score with
// a clutter table, rendered with each kind marked seen or unseen and score's intervals.
#include <catch2/catch.hpp>

#include <string>

#include "canopy/documents/scene_score.h"
#include "report/clutter_section.h"
#include "report/report.h"

using namespace canopy;

namespace {

const char* const kScore = R"({
  "format": "canopy.scene_score", "version": 1,
  "params": {"match_radius_m": 1.5, "cover_bins": [0, 1], "flip_threshold_deg": 90},
  "tiles": [
    {"detections": "out/scenes/light/tile-101/noise-0/detections.json", "cover": "light", "noise_mm": 0, "area_ha": 0.09},
    {"detections": "out/scenes/dense/tile-101/noise-0/detections.json", "cover": "dense", "noise_mm": 0, "area_ha": 0.09}],
  "summary": [], "pr": [], "models": [], "cover_bins": [], "reliability": [],
  "clutter": [
    {"cover": "all", "kind": "boulder", "tiles": 2, "renders": 2, "area_ha": 0.18, "objects": 4, "objects_distinct": 4,
     "false_alarms": 0, "model_level": 0, "class_level": 0, "false_alarms_per_ha": 0.0, "false_alarms_per_ha_lo": 0.0,
     "false_alarms_per_ha_hi": 20.49, "answered": 0, "answered_share": 0.0, "answered_share_lo": 0.0,
     "answered_share_hi": 0.49},
    {"cover": "all", "kind": "caravan", "tiles": 2, "renders": 2, "area_ha": 0.18, "objects": 2, "objects_distinct": 2,
     "false_alarms": 3, "model_level": 2, "class_level": 1, "false_alarms_per_ha": 16.667, "false_alarms_per_ha_lo": 3.437,
     "false_alarms_per_ha_hi": 48.71, "answered": 2, "answered_share": 1.0, "answered_share_lo": 0.3424,
     "answered_share_hi": 1.0},
    {"cover": "all", "kind": "none", "tiles": 2, "renders": 2, "area_ha": 0.18, "objects": null, "objects_distinct": null,
     "false_alarms": 1, "model_level": 1, "class_level": 0, "false_alarms_per_ha": 5.5556, "false_alarms_per_ha_lo": 0.1407,
     "false_alarms_per_ha_hi": 30.96, "answered": null, "answered_share": null, "answered_share_lo": null,
     "answered_share_hi": null}],
  "matches": []})";

}  // namespace

TEST_CASE("clutter section: false alarms by kind, seen and unseen kinds marked, with intervals") {
  const documents::SceneScore score = documents::read_scene_score(kScore, "score.json");
  REQUIRE(score.clutter.size() == 3);
  const std::string md = report::clutter_markdown(score);
  CHECK(md.find("### False alarms by clutter kind") == 0);
  CHECK(md.find("| all | boulder | seen | 4 (4) | 0 (0 + 0) | 0.0 [0.0, 20.5] | 0/4 = 0.0% [0.0, 49.0] |") !=
        std::string::npos);
  CHECK(md.find("| all | caravan | **unseen** | 2 (2) | 3 (2 + 1) | 16.7 [3.4, 48.7] | 2/2 = 100.0% [34.2, "
                "100.0] |") != std::string::npos);
  CHECK(md.find("| all | none | terrain, vegetation | – | 1 (1 + 0) | 5.6 [0.1, 31.0] | – |") !=
        std::string::npos);
  CHECK(report::clutter_kind_seen("logs"));
  CHECK(report::clutter_kind_mark("vehicle") == "a true vehicle, off its centre");
  CHECK(report::clutter_kind_mark("none") == "terrain, vegetation");
  CHECK(report::clutter_kind_mark("rock") == "**unseen**");
  CHECK(report::clutter_kind_mark("shed") == "seen");
  CHECK_FALSE(report::clutter_kind_seen("rock"));
  // In the scene section, after the reliability table's place.
  CHECK(report::scene_markdown(score, {}, "scenes").find("### False alarms by clutter kind") !=
        std::string::npos);
  // A score written before the table: no section.
  documents::SceneScore old = score;
  old.clutter.clear();
  CHECK(report::clutter_markdown(old).empty());
  CHECK(report::scene_markdown(old, {}, "scenes").find("False alarms by clutter kind") == std::string::npos);
}
