// score's intervals and distinct counts (issue 29; formats/README.md "Scene scores"): the
// renders among a row's tiles, the 95% interval of a rate over them, and the reliability table.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "canopy/common/stats.h"
#include "canopy/documents/scene_score.h"
#include "score/score.h"

namespace canopy::score {

// a / b, or null when b <= 0 (a rate with nothing to count).
documents::ScoreValue ratio(double a, double b);

// The renders among `which`: tiles that share one truth file are one rendered scene (the scene
// experiment's noise levels add noise to one render), in order of first appearance. The
// intervals resample renders, not tiles: their vehicles, canopy and clutter are the same.
std::vector<std::vector<std::size_t>> renders_of(const std::vector<Tile>& tiles,
                                                 const std::vector<std::size_t>& which);

// The true vehicles of the distinct renders (a vehicle counted once over its noise levels).
int distinct_vehicles(const std::vector<Tile>& tiles, const std::vector<std::vector<std::size_t>>& renders);

// Inserts `cells` into `row` right after the column `key` (std::logic_error when there is none).
void insert_after(documents::ScoreRow& row, const std::string& key,
                  std::initializer_list<std::pair<std::string, documents::ScoreValue>> cells);

enum class RateKind { proportion, per_area };

// The 95% interval of a rate sum(num) / sum(den) of a row whose runs fall in renders, written
// as <key>_lo, <key>_hi after <key> (null when the rate is): the hull of (a) the percentile
// bootstrap over renders (common::cluster_bootstrap: vehicles of one tile and noise levels of
// one render are not independent) and (b) the interval of the counts at their effective size,
// n x renders / runs of the row (Wilson for a proportion, exact Poisson for a count per
// hectare). (b) alone would treat correlated runs as independent; (a) alone collapses to a
// point when every render gives the same rate (100% on 3 renders is no certainty) and is
// undefined for one render.
void add_interval(documents::ScoreRow& row, const std::string& key,
                  const std::vector<common::ClusterSum>& per_render, double runs_per_render, RateKind kind);

// Reliability (issue 29, "calibration where it is used"): the answers of each level (model,
// class, none) by stated confidence, in bins of 0.1 ([0.9, 1] closed), and the share that is
// right, with its interval over renders. A detection is right when its outcome is "right" (the
// true model, or a class naming the truth; a false alarm and a wrong model or class are
// wrong). A rejection ("none", with its confidence and the candidate's centre) is right unless
// a true vehicle that no detection found lies within `radius` of the candidate's centre (a
// rejected fragment of a vehicle found by another candidate costs nothing).
std::vector<documents::ScoreRow> reliability_table(const std::vector<Tile>& tiles,
                                                   const std::vector<documents::ScoreMatch>& matches,
                                                   const std::vector<TileMatch>& pairing, double radius);

}  // namespace canopy::score
