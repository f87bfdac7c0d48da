// The verdict's pose member as JSON, shared by the verdict writer and classify's (private to
// canopy_documents).
#pragma once

#include <nlohmann/json.hpp>

#include "canopy/formats/pose.h"

namespace canopy::documents::verdict_json {

// {"matrix": 16 numbers row-major, "translation", "heading_deg", "pitch_deg", "roll_deg"};
// common::Error "refusing to write non-finite pose" for a non-finite matrix entry.
nlohmann::ordered_json pose_json(const formats::Pose& pose);

}  // namespace canopy::documents::verdict_json
