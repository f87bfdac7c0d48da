// The segment graph (JSON format "canopy.segment_graph", version 1, formats/README.md): ncut writes
// it; gmatch, verify, areas and report read it (and the modelbase holds one per model). Its
// segments with their attributes, and their adjacency.
// Readers check "format" and "version", every integer's type and range, that numbers are
// finite, that segment ids are unique and adjacency edges join two different listed
// segments (a < b, no duplicates), and name the file and the key in every error.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

constexpr const char* kSegmentGraphFormat = "canopy.segment_graph";
constexpr int kSegmentGraphVersion = 1;  // the only version written and read

using Vec3 = std::array<double, 3>;

struct Segment {
  int segment_id = 0;
  int vertex_count = 0;
  double area = 0;            // m^2
  Vec3 radii{};               // sqrt of PCA eigenvalues, largest first (m)
  double thickness = 0;       // sqrt(l3 / l1)
  double elongation = 0;      // sqrt(l2 / l1)
  Vec3 centroid{};            // area-weighted (m, world frame)
  Vec3 normal{};              // unit; smallest PCA axis, oriented like the vertex normals
  int label = 0;              // majority ground-truth label (formats/labels.h)
  double label_purity = 0;    // share of the segment's area carrying that label
  std::vector<int> vertices;  // mesh vertex indices (0-based), ascending
};

struct SegmentEdge {
  int a = 0, b = 0;      // segment ids, a < b
  int shared_edges = 0;  // mesh edges between the two segments
};

struct SegmentGraph {
  formats::Provenance provenance;
  std::string mesh;  // the mesh the segments index into, as given
  std::vector<Segment> segments;
  std::vector<SegmentEdge> adjacency;
};

// kSkip: the segments' "vertices" lists are neither parsed into values nor checked, and every
// Segment::vertices is left empty (vertex_count is read): for readers that use only the
// graph's statistics, e.g. gmatch reading a 1000-entry modelbase (the lists are ~2/3 of a
// graph's bytes and ~40% of its reading time).
enum class GraphVertices { kRead, kSkip };

// Every error is a common::DataError naming `path`.
SegmentGraph read_segment_graph(const std::string& path, GraphVertices vertices = GraphVertices::kRead);
SegmentGraph parse_segment_graph(const std::string& text, const std::string& name,
                                 GraphVertices vertices = GraphVertices::kRead);
void write_segment_graph(const SegmentGraph& graph, const std::string& path);
std::string serialize_segment_graph(const SegmentGraph& graph);

}  // namespace canopy::documents
