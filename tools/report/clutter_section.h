// The report's "False alarms by clutter kind" table (issue 29, "unseen clutter"): score.json's
// "clutter" table (tools/score/clutter.h) rendered in the scene section, each kind marked seen
// (a kind verify's acceptance and classify's thresholds were fitted on) or unseen.
#pragma once

#include <string>

#include "canopy/documents/scene_score.h"

namespace canopy::report {

// True for the kinds the thresholds were fitted on: boulder, shed, container, fence, logs
// (docs/decisions/scene-experiment.md "Unseen clutter").
bool clutter_kind_seen(const std::string& kind);

// What a kind of the table is: "seen", "**unseen**", "a true vehicle, off its centre" (score's
// `vehicle` row) or "terrain, vegetation" (`none`).
std::string clutter_kind_mark(const std::string& kind);

// The Markdown subsection; "" when the score has no clutter table (a score written before it).
std::string clutter_markdown(const documents::SceneScore& score);

}  // namespace canopy::report
