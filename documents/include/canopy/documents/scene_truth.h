// A tile's ground truth: truth.json, format "canopy.scene_truth", version 1 (formats/README.md
// "Scene truth"): rangetrace writes it for a rendered tile, hand labels of a real tile
// (share/real/*.truth.json) are written in it; score, topview and report read it here.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace canopy::documents {

inline constexpr const char* kSceneTruthFormat = "canopy.scene_truth";
inline constexpr int kSceneTruthVersion = 1;

// A pose in tile coordinates: x y (m) always; z (m) and heading (degrees) when given.
struct TruthPose {
  double x = 0, y = 0;
  std::optional<double> z, heading;
};

struct TrueVehicle {
  std::int64_t instance = 0;                     // unique in the document
  std::string model, cls;                        // "model" and "class" ("" when null or absent)
  std::string visibility;                        // hand labels: clear, partial, ... ("" when absent)
  std::optional<TruthPose> pose;                 // bottom centre of the bounding box
  std::optional<double> canopy_cover;            // in [0, 1]
  std::vector<std::array<double, 2>> footprint;  // 3 to 64 corners; empty when absent
};

// An object the labeller could not decide (hand labels): its centre.
struct UncertainObject {
  double x = 0, y = 0;
};

struct SceneTruth {
  std::optional<std::array<double, 2>> extent;  // X Y (m), both > 0
  std::vector<TrueVehicle> vehicles;
  std::vector<UncertainObject> uncertain;
};

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1, "vehicles" missing or not an array, a vehicle
// without an integer instance >= 0 or with one that repeats, a pose without finite x and y, a
// canopy_cover outside [0, 1], a footprint not 3 to 64 [x, y] corners, an extent that is not
// two positive numbers, an uncertain object without a pose, any member of another type.
SceneTruth read_scene_truth(const std::string& text, const std::string& name);
SceneTruth read_scene_truth_file(const std::string& path);

}  // namespace canopy::documents
