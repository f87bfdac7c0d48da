// collect's messages of a tile: the one-line summary (collect's stderr; `make tile` shows it)
// and the warning (detections.json's "warning", also on stderr). formats/README.md "Detections".
#pragma once

#include <string>
#include <vector>

#include "collect/collect.h"

namespace canopy::collect {

// One sentence, or "": led by what detect warned about the tile (the index's warnings, "detect
// warned: ..."); for a tile without candidates why (its area and density against kClassDensity,
// or no object of a vehicle's size); else, joined by "; ", the model chain's failure on more than
// half the candidates it ran on (naming the first failed stage's log of one, Verdict::failed_log),
// the reason more than half the candidates were rejected for (reasons[i]: candidate i's, "" for a
// detection) with what would help, and that no candidate ran the model chain (not with size_only,
// which reads no verdict on purpose), then "; see docs/decisions/classify.md".
std::string warning_of(const Index& index, const std::vector<Answers>& answers, const Outputs& out,
                       const std::vector<std::string>& reasons, bool size_only);

// "3 candidates: 2 vehicles found (1 model level, 1 class level); rejected: too_sparse 1" (the
// singular for 1), and "; model chain failed on F of the N candidates it ran on" when F > 0.
std::string summary_line(const Index& index, const Outputs& out);

}  // namespace canopy::collect
