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

#include "canopy/formats/provenance.h"

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
  std::optional<double> confidence;   // null or absent: nullopt
  // The candidate's centre in tile coordinates ("position": {"x", "y"}; absent before issue 29).
  std::optional<std::array<double, 2>> position;
  // The object's density in points per m² ("density"; null or absent: nullopt).
  std::optional<double> density;
};

struct Detections {
  int version = 0;
  std::string index;  // the candidates index collect read, as it named it ("" when absent)
  std::string tile;
  std::optional<int> candidates, found, none, failed;             // counts
  std::optional<int> model_chain_ran, model_chain_failed;         // absent before stop 70
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

// Writing (collect writes version 2). One detection as collect placed it in the tile.
struct DetectionRecord {
  std::string candidate;
  bool model_level = true;        // "level": model (the model chain's verdict named a model) or class
  std::string model, cls, group;  // "" = null ("class" written when named; "group" when named or
                                  // at class level)
  double confidence = 0;
  std::array<double, 16> matrix{};  // model (or class) frame -> tile frame, row-major
  std::array<double, 3> euler{};    // heading, pitch, roll (degrees) of matrix
  // Class level only: the heading's ambiguity (degrees), the size L W H, the object density.
  double heading_ambiguity = 180;
  std::optional<std::array<double, 3>> size;
  std::optional<double> density;
  std::vector<std::array<double, 2>> footprint;  // counter-clockwise corners
  std::string footprint_from;                    // model, class or candidate
  std::string verdict;                           // the verdict file it came from
};

// A candidate no level answered, and why.
struct RejectionRecord {
  std::string candidate, reason;
  std::optional<std::string> detail;  // nullopt = null
  std::optional<double> confidence, density;
  bool classified = false;  // classify answered: "density_needed" and "model_chain" are written
  bool has_density_needed = false;
  std::optional<double> density_class, density_model;  // "density_needed" when has_density_needed
  std::optional<std::string> model_chain;              // failed, none, or nullopt = null (not run)
  std::string verdict;
  std::optional<std::array<double, 2>> position;  // the candidate's centre, tile coordinates
};

struct DetectionsRecord {
  formats::Provenance provenance;
  std::string index, tile, crs;  // crs "" = null
  // Where the CRS came from ("--crs", or "tile: " and the index's crs_from); written after "crs"
  // (and as the GeoJSON's "crs_from") only when not "": a document without it is as before.
  std::string crs_from;
  std::size_t candidates = 0;
  int found = 0, none = 0, failed = 0, model_level = 0, class_level = 0;
  // The candidates whose model chain ran and of them those whose chain failed, whatever answered
  // them (stop 70): written after "failed" when set, not at all otherwise (a document as before).
  std::optional<int> model_chain_ran, model_chain_failed;
  std::map<std::string, int> by_reason;
  nlohmann::ordered_json density;  // the index's density object, written as is (null otherwise)
  std::string warning;             // "" = null
  std::vector<DetectionRecord> detections;
  std::vector<RejectionRecord> rejected;
};

// detections.json (canopy.detections v2), byte-identical to collect's before the move.
// common::Error "collect: refusing to write a non-finite number" for a non-finite position,
// matrix, footprint corner, size, density or ambiguity.
std::string serialize_detections(const DetectionsRecord& record);
// The detections as a GeoJSON FeatureCollection: one Feature per detection, its footprint
// polygon (closed ring) and properties; the 2008 "crs" member when crs is EPSG:<code>, and
// then "crs_from" (a foreign member, RFC 7946 §6.1) when crs_from is not "".
std::string serialize_detections_geojson(const DetectionsRecord& record);

// The tile's density for messages: the density object's "ground" when a number, else "all".
std::optional<double> open_ground_density(const nlohmann::ordered_json& density);
// Which of the density object's keys open_ground_density reads ("ground" or "all"; nullptr for
// none), for a message that names the density it states.
const char* open_ground_density_key(const nlohmann::ordered_json& density);
// The area (ha) of the density object's occupied cells ("occupied_cells" of "cell" m, 1 m when
// absent); none when it has no such count.
std::optional<double> occupied_hectares(const nlohmann::ordered_json& density);

}  // namespace canopy::documents
