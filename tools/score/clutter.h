// score's false alarms by clutter kind (issue 29, "unseen clutter"; formats/README.md "Scene
// score", key "clutter"): which truth clutter object each false alarm fell on.
#pragma once

#include <string>
#include <vector>

#include "canopy/documents/scene_score.h"
#include "score/score.h"

namespace canopy::score {

// The clutter object of `truth` a false alarm at (x, y) is put on: one whose box seen from above
// holds the point (the nearest centre among several), else the nearest whose centre lies within
// `radius`; -1 when none (terrain or vegetation).
int clutter_at(const Truth& truth, double x, double y, double radius);

// The true vehicle of `truth` whose footprint seen from above holds (x, y) (the nearest centre
// among several), -1 when none does or no vehicle has a footprint. A false alarm there is an
// answer on a vehicle beyond the match radius of its centre (a part, a merge, a fragment) or a
// second answer on one; it is put on the vehicle before any clutter object.
int vehicle_at(const Truth& truth, double x, double y);

// Per cover label ("all", then each label of the tiles) and per clutter kind of the truths (in
// name order), then "vehicle" (when a truth's vehicle has a footprint) and "none": the false
// alarms (detections matched to no vehicle, model and class level) put on objects of that kind
// (vehicle_at, then clutter_at), the objects present (per run and per distinct
// render), false alarms per hectare with its 95% interval, and the share of the objects that drew
// at least one false alarm ("answered" as a vehicle) with its interval (add_interval: the hull of
// the bootstrap over renders and the exact Poisson / Wilson interval at the effective count).
std::vector<documents::ScoreRow> clutter_table(const std::vector<Tile>& tiles,
                                               const std::vector<TileMatch>& matches, double radius);

}  // namespace canopy::score
