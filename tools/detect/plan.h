#pragma once
// Top-view helpers of detect's object steps (objects.cpp, fragments.cpp): points addressed by
// index into the tile's x and y (local frame, m).
#include <cstdint>
#include <vector>

#include "detect/footprint.h"

namespace canopy::detect {

// Pieces merged (merge_pieces, merge_fragments) make a union at most this much wider than the wider
// piece (m).
inline constexpr double kMergeWiden = 0.3;
// Clusters stacked in height (join_stacked; merge_fragments' beside test) share at most this share
// of the smaller one's top-view cells: they meet along a line, one is not over the other.
inline constexpr double kStackOverlay = 0.25;

// The key of the top-view cell of side v holding (x, y).
std::uint64_t column_key(double x, double y, double v);

// True when a point of `a` lies within `reach` of one of `b` horizontally (a hash of b's points in
// cells of `reach`).
bool touch_in_plan(const std::vector<double>& x, const std::vector<double>& y,
                   const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b, double reach);

// True when more than kStackOverlay of the top-view cells (of side `cell`) holding points of `own`
// also hold points of `other`: `own` lies over `other`, not beside it (join_stacked's test).
bool over_in_plan(const std::vector<double>& x, const std::vector<double>& y,
                  const std::vector<std::uint32_t>& own, const std::vector<std::uint32_t>& other, double cell);

// The minimum-area rectangle of the points `pts` in the top view.
Footprint plan_footprint(const std::vector<double>& x, const std::vector<double>& y,
                         const std::vector<std::uint32_t>& pts);

}  // namespace canopy::detect
