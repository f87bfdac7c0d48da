// Where the target's surface area goes through one trial: areas.json, format "canopy.areas",
// version 1 (issue 19; formats/README.md). areas writes it; report reads it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace canopy::documents {

inline constexpr const char* kAreasFormat = "canopy.areas";
inline constexpr int kAreasVersion = 1;
inline constexpr int kAreasMaxSegments = 100000;        // bound of max_segments (areas' --max-segments)
inline constexpr long long kAreasMaxCount = 1LL << 53;  // bound of the counts

// All areas in m²; label 1 = target.
struct Areas {
  double visible = 0;   // target surface in the noise-free scan
  double samples = 0;   // fitvox target samples
  double mesh = 0;      // cocone mesh, target triangles
  double segments = 0;  // ncut, every target segment
  double matched = 0;   // the `max_segments` largest segments' target area
  double spacing = 0, cell = 0, voxel = 0;
  int max_segments = 0;
  std::size_t target_points = 0, target_samples = 0;
};

// The text of areas.json as areas writes it (provenance: tool "areas", `inputs` as given).
// Throws common::Error for a non-finite number (a writer's bug).
std::string write_areas(const Areas& a, const std::vector<std::string>& inputs);

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1, a member missing, an area not a number >= 0, spacing,
// cell or voxel not > 0, max_segments not an integer in [1, 100000], a count not an integer in
// [0, 2^53].
Areas read_areas(const std::string& text, const std::string& name);
Areas read_areas_file(const std::string& path);

// A number as the canopy JSON writers write it: the shortest text that reads back to the same
// double ("0.045", "1e-06", "-1e+308"); for messages that quote a value of the document.
std::string number_text(double v);

}  // namespace canopy::documents
