// detect's density rule (docs/decisions/detect.md §7): the tile's density measured on 1 m cells
// of the local frame sets the DTM cell (before the ground), the clustering voxel and the shape
// test (after it). The rule's constants and voxel_for_density & co. are in detect.h.
#pragma once

#include <vector>

#include "canopy/formats/point_cloud.h"
#include "detect/detect.h"
#include "detect/frame.h"

namespace canopy::detect {

// Points per occupied 1 m cell of the local frame, before the ground is known (for the DTM
// cell): memory O(points), whatever the extent.
double occupied_density(const LocalFrame& l);

// The tile's density after the ground (`height`: every point's height above the DTM; a cell is
// open ground when every point in it lies below min_object_height) and what the rule makes of
// it: `voxel` and `min_planarity` the rule's values where params says so (voxel_from_density,
// planarity_from_density), else params' own; `cell` = params.cell (already ruled).
Density density_rule(const formats::PointCloud& tile, const LocalFrame& l, const std::vector<float>& height,
                     const Params& params);

}  // namespace canopy::detect
