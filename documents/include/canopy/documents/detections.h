// A tile's detections: detections.json, format "canopy.detections", versions 1 and 2
// (formats/README.md "Detections"). collect writes version 2; score, topview and report read
// both (version 2 adds each detection's level and the rejections' reasons).
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace canopy::documents {

inline constexpr const char* kDetectionsFormat = "canopy.detections";
inline constexpr int kDetectionsVersion = 2;  // the newest; 1 is read too

// Where a detection puts the vehicle in the tile (the pose's translation, heading in degrees).
struct DetectionPose {
  double x = 0, y = 0, z = 0, heading = 0;
};

struct Detection {
  std::string candidate;  // the candidate's id (unique in the document)
  // "model" or "class": "level" when given (required from version 2 on), else "class" when
  // "model" is there and null, else "model".
  std::string level;
  std::string model, cls, group;     // "" when null or absent
  std::optional<double> confidence;  // in [0, 1]
  std::optional<DetectionPose> pose;
  std::vector<std::array<double, 2>> footprint;  // 3 to 64 corners; empty when absent
};

// A candidate no level answered.
struct Rejection {
  std::string candidate;
  std::optional<std::string> reason;  // none, failed, too_sparse, ...; absent in early version 1
};

struct Detections {
  int version = 0;
  std::string index;  // the candidates index collect read, as it named it ("" when absent)
  std::string tile;
  std::optional<int> candidates, found, none, failed;             // counts
  std::optional<std::map<std::string, int>> by_level, by_reason;  // version 2
  // "warning": absent (nullopt), null (""), or a sentence.
  std::optional<std::string> warning;
  nlohmann::ordered_json density;  // the tile's density object as written, or null
  std::vector<Detection> detections;
  bool has_rejected = false;  // "rejected" is there (an early version 1 document has none)
  std::vector<Rejection> rejected;

  // density.all when it is a number > 0.
  std::optional<double> density_all() const;
};

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1 or 2, "detections" missing
// or not an array, an entry not an object, a candidate not a string or repeated, a level other
// than model or class (or missing from version 2 on), a confidence outside [0, 1], a pose
// without finite x y z heading, a footprint not 3 to 64 [x, y] corners, counts that are not
// integers >= 0, a warning neither a sentence nor null, any member of another type.
Detections read_detections(const std::string& text, const std::string& name);
// The file at `path` (common::read_file), then read_detections.
Detections read_detections_file(const std::string& path);

}  // namespace canopy::documents
