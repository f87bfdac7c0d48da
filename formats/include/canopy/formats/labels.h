// Ground-truth labels carried by the "label" field of scans, samples and meshes.
#pragma once

#include <cstdint>

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

}  // namespace canopy::formats
