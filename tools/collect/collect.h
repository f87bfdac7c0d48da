// collect: one tile's candidates index (detect) + per-candidate verdicts (verify) ->
// detections.json (canopy.detections v1) and a GeoJSON FeatureCollection of the detections in
// the tile's coordinates (formats/README.md "Detections"; docs/decisions/scene-experiment.md).
#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::collect {

using Matrix = std::array<double, 16>;  // 4 x 4 row-major, float64
using Corner = std::array<double, 2>;

struct Candidate {
  std::string id;
  Matrix transform{};  // candidate frame -> tile frame
  double length = 0, width = 0;
};

struct Index {
  std::string name;  // file, as given
  std::string tile;  // the tile detect read, as it recorded it
  std::vector<Candidate> candidates;
};

struct Verdict {
  std::string name;       // file, as given
  bool failed = false;    // an empty file: the candidate's chain failed (stage.sh --record-failure)
  std::string candidate;  // the points verify checked ("candidate"), as it was given them
  std::string model;      // "" = none
  std::string cls;        // "class", when the verdict has one
  double confidence = 0;
  std::optional<Matrix> pose;       // model -> candidate
  std::optional<Matrix> pose_tile;  // model -> tile
};

// The top-view rectangle of a model in its own frame: x in [x0, x1], y in [y0, y1].
struct ModelBox {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

struct Params {
  std::string crs;                        // "EPSG:<code>" or ""
  std::map<std::string, ModelBox> boxes;  // by model name; a model without one uses the candidate footprint
};

// Throws common::UsageError naming --crs when crs is neither empty nor EPSG:<1-6 digits>.
void validate(const Params& params);

Index parse_index(const std::string& text, const std::string& name);
// An empty text is a failed candidate. Otherwise DataError naming the file: not a
// canopy.verdict v1, no "candidate" (a non-empty string), a model or class that is not a name
// (formats::is_model_name: a model "../../x" would be read outside the modelbase), confidence
// outside [0, 1], a malformed pose, a model without a pose.
Verdict parse_verdict(const std::string& text, const std::string& name);

// Whether a verdict's "candidate" (the points verify was given) names candidate `id`: its file
// stem is the id (detect's <id>.pcd) or its directory is named so (<id>/samples.pcd).
bool names_candidate(const std::string& points, const std::string& id);
// The verdict belongs to candidate `id` of the index in `index_dir`: DataError naming the
// verdict file unless names_candidate(); and when those points exist (seen from the working
// directory), they must be <index_dir>/<id>.pcd or lie in <index_dir>/<id>/ or in the verdict's
// own directory: another tile's candidate of the same id is refused too. Failed verdicts pass.
void check_verdict_of(const Verdict& verdict, const std::string& id, const std::string& index_dir);

// p = a * b (4 x 4 row-major).
Matrix multiply(const Matrix& a, const Matrix& b);
// Heading, pitch, roll in degrees of the rotation of m (R = Rz(heading) Ry(pitch) Rx(roll)).
std::array<double, 3> euler_degrees(const Matrix& m);

struct Output {
  std::string detections;  // canopy.detections v1
  std::string geojson;     // FeatureCollection
  int found = 0, none = 0, failed = 0;
};

// verdicts[i] belongs to index.candidates[i] (DataError naming the verdict when its candidate
// does not name it, names_candidate). `provenance` is written as is.
Output collect(const Index& index, const std::vector<Verdict>& verdicts, const Params& params,
               const nlohmann::ordered_json& provenance);

// One tile: its index, one verdict per candidate (verdicts[i] of index.candidates[i]) and who
// writes the documents from what (formats::provenance_json).
struct Inputs {
  Index index;
  std::vector<Verdict> verdicts;
  formats::Provenance provenance;
};

// collect(inputs.index, inputs.verdicts, params, the provenance as JSON).
Output run(const Params& params, const Inputs& inputs);

// The make plan of a tile: the candidate ids and each one's candidate-to-tile transform (16
// comma-separated numbers, row-major, as verify --transform takes them), as make variables
// <key>_CANDS and <key>_TRANSFORM_<id> (mk/scenes.mk). Ids are plain names (parse_index).
std::string plan(const Index& index, const std::string& key = "TILE");

}  // namespace canopy::collect
