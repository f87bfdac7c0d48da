// JSON documents of canopy: segment graph (format "canopy.segment_graph", version 1) and
// match result (format "canopy.match_result", version 1). See formats/README.md.
// Readers check "format" and "version", every integer's type and range, that numbers are
// finite, that segment ids are unique and adjacency edges join two different listed segments
// (a < b, no duplicates), and name the file and the key in every error.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace canopy::formats {

// Who wrote a document and from what.
struct Provenance {
  std::string tool;
  std::string version;
  std::vector<std::pair<std::string, std::string>> parameters;  // option name -> value text
  std::vector<std::string> inputs;                               // input paths as given
};

using Vec3 = std::array<double, 3>;

struct Segment {
  int segment_id = 0;
  int vertex_count = 0;
  double area = 0;          // m^2
  Vec3 radii{};             // sqrt of PCA eigenvalues, largest first (m)
  double thickness = 0;     // sqrt(l3 / l1)
  double elongation = 0;    // sqrt(l2 / l1)
  Vec3 centroid{};          // area-weighted (m, world frame)
  Vec3 normal{};            // unit; smallest PCA axis, oriented like the vertex normals
  int label = 0;            // majority ground-truth label (formats/labels.h)
  double label_purity = 0;  // share of the segment's area carrying that label
  std::vector<int> vertices;  // mesh vertex indices (0-based), ascending
};

struct SegmentEdge {
  int a = 0, b = 0;        // segment ids, a < b
  int shared_edges = 0;    // mesh edges between the two segments
};

struct SegmentGraph {
  Provenance provenance;
  std::string mesh;  // the mesh the segments index into, as given
  std::vector<Segment> segments;
  std::vector<SegmentEdge> adjacency;
};

struct SegmentPair {
  int object_segment = 0;   // segment id in the object graph
  int model_segment = -1;   // segment id in the model graph; -1 = NULL match
  double unary_error = 0;
};

struct ModelScore {
  std::string model;   // model name (file stem in the modelbase)
  double score = 0;    // S = 1 - E
  int rank = 0;        // 1 = best
  double error_unary = 0, error_orientation = 0, error_distance = 0, error_coverage = 0;
  double error_total = 0;
  std::vector<SegmentPair> pairs;
};

struct MatchResult {
  Provenance provenance;
  std::string object;  // object segment graph path, as given
  std::string error_form;  // "bounded" or "thesis"
  std::vector<ModelScore> models;  // sorted by rank
  double entropy = 0;  // bits
};

SegmentGraph read_segment_graph(const std::string& path);
SegmentGraph parse_segment_graph(const std::string& text, const std::string& name);
void write_segment_graph(const SegmentGraph& graph, const std::string& path);
std::string serialize_segment_graph(const SegmentGraph& graph);

// Score of the rank-1 model minus that of the rank-2 model (the "margin" key of the file,
// null there when fewer than two models); NaN when fewer than two models.
double match_margin(const MatchResult& result);

MatchResult read_match_result(const std::string& path);
MatchResult parse_match_result(const std::string& text, const std::string& name);
void write_match_result(const MatchResult& result, const std::string& path);
std::string serialize_match_result(const MatchResult& result);

}  // namespace canopy::formats
