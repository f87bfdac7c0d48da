// The truth statistics of detect's candidates (index.json's "truth" and "instances"): when the
// tile carries a ground-truth instance field (rangetrace's tiles), which labelled vehicle each
// candidate holds and which candidates hold each vehicle. Not used by the recogniser's path.
#pragma once

#include <vector>

#include "canopy/formats/point_cloud.h"
#include "detect/candidates.h"
#include "detect/detect.h"
#include "detect/objects.h"

namespace canopy::detect {

struct TileTruthStats {
  bool has_truth = false;                // the tile has params.instance_field
  std::vector<Truth> candidates;         // per placed candidate (empty without truth)
  std::vector<InstanceTruth> instances;  // every labelled vehicle of the tile, by id
};

// `placed` from place_candidates over `objects`. A point's instance counts only where the
// label field (when present) says vehicle (formats::kLabelTarget).
TileTruthStats truth_of(const formats::PointCloud& tile, const Params& params,
                        const std::vector<Object>& objects, const Placed& placed);

}  // namespace canopy::detect
