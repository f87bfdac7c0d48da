// Ground-truth labels carried by the "label" field of scans, samples and meshes.
#pragma once

#include <algorithm>
#include <cstdint>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

enum Label : std::uint32_t {
  kLabelUnknown = 0,
  kLabelTarget = 1,   // the vehicle
  kLabelFoliage = 2,  // leaves (discs)
  kLabelGround = 3,   // the ground plane
  kLabelClutter = 4,  // objects that are not vehicles (rangetrace tiles: boulders, sheds, ...)
};

inline const char* label_name(std::uint32_t label) {
  switch (label) {
    case kLabelTarget: return "target";
    case kLabelFoliage: return "foliage";
    case kLabelGround: return "ground";
    case kLabelClutter: return "clutter";
    default: return "unknown";
  }
}

// Whether a cloud's "label" field carries labels: it is there and not 0 (unknown) on every row.
// fitvox writes 0 on every row of an input without labels (a tile candidate, a user's own scan),
// so such a field says nothing: a modelbase surface with it is read as one without the field
// (verify, classify, collect, baseline; docs/decisions/verify.md §22, stop 70).
inline bool carries_labels(const PointCloud& cloud) {
  if (!cloud.has("label")) return false;
  const auto& label = cloud.col("label");
  return std::any_of(label.begin(), label.end(), [](double l) { return l != kLabelUnknown; });
}

}  // namespace canopy::formats
