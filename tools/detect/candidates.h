// detect's candidates (step 5 of detect.h, docs/decisions/detect.md §4): per accepted object a
// rigid frame on the ground plane under it, its size and pose, and the crop of the tile's points
// around it in that frame.
#pragma once

#include <cstddef>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "detect/detect.h"
#include "detect/frame.h"
#include "detect/ground.h"
#include "detect/objects.h"

namespace canopy::detect {

// The candidates sorted by their centre (x, then y) and numbered c0001, ...
struct Placed {
  std::vector<Candidate> candidates;
};

// `examined` and `trims` (Objects::examined and trim_rests) mark with params.object_field the crop's
// points of other objects 2 (detect.md §17), those a trim cut off the object 3 (detect.md §18);
// `examined` empty: every point not the object's is 0.
Placed place_candidates(const formats::PointCloud& tile, const LocalFrame& l, const Ground& g,
                        const std::vector<Object>& objects, const Params& params,
                        const std::vector<std::int32_t>& examined = {},
                        const std::vector<TrimRest>& trims = {});

}  // namespace canopy::detect
