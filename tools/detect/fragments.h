// Fragments under a crown (docs/decisions/detect.md §24): clusters of the clustering too small to
// be objects that are the sparse returns of a vehicle's part hidden by a crown, merged into the
// accepted object they belong to (Params::merge_fragments, off by default).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detect/detect.h"
#include "detect/objects.h"

namespace canopy::detect {

// A cluster of the clustering rejected as too small (fewer than min_points, or shorter, narrower
// or lower than the vehicle ranges), with its examination's number (Objects::examined; -1 without
// object_field).
struct Fragment {
  std::vector<std::uint32_t> points;  // rows of the tile
  std::int32_t examination = -1;
};

// Merges into `objects` the fragments that lie under a crown and belong to one of them (the rule
// at merge_fragments' definition in fragments.cpp); returns how many merged. `x`, `y`: every tile
// point in the local frame; `height`: above the DTM. Nothing without params.merge_fragments.
std::size_t merge_fragments(const std::vector<double>& x, const std::vector<double>& y,
                            const std::vector<float>& height, const Params& params,
                            const std::vector<Fragment>& fragments, std::vector<Object>& objects);

}  // namespace canopy::detect
