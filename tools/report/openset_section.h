// The report's "Open set: unseen vehicles" section (issue 29; mk/openset.mk,
// docs/decisions/open-set.md): the scene experiment's tiles with vehicles drawn from the vehicle
// library's test instances only, recognised against a modelbase of its other instances.
#pragma once

#include <string>

#include "canopy/documents/scene_score.h"

namespace canopy::report {

// The section (Markdown) from the open-set score: per cover level the rates with their 95%
// intervals (recall, precision, class right, false alarms per ha: either level), and per test
// instance what the answers were (found, at which level, the classes answered).
std::string openset_markdown(const documents::SceneScore& score, const std::string& score_path);

}  // namespace canopy::report
