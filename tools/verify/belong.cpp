// Do verify's inputs belong together? The match result, the segment graph and the candidate's
// points must describe one candidate (docs/decisions/verify.md, "Inputs that belong together").
// Every check here can only refuse what is provably inconsistent: names that cannot be
// resolved and files that are not there prove nothing and are passed over.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <system_error>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/ply.h"
#include "verify/verify.h"

namespace canopy::verify {
namespace {

namespace fs = std::filesystem;
using common::DataError;

std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string point_text(const Eigen::Vector3d& p) {
  return "(" + fmt(p.x()) + ", " + fmt(p.y()) + ", " + fmt(p.z()) + ")";
}

// Where a path recorded in a document (`recorded`) may be now: beside the document that
// records it (the recording tool may have run in that directory), then as seen from here.
// Standard input and empty names resolve to nothing.
std::vector<fs::path> resolutions(const std::string& recorded, const std::string& document) {
  std::vector<fs::path> out;
  if (recorded.empty() || recorded == "-" || recorded == "<stdin>") return out;
  const fs::path p(recorded);
  if (p.is_relative() && !document.empty() && document != "-") {
    const fs::path dir = fs::path(document).parent_path();
    if (!dir.empty()) out.push_back(dir / p);
  }
  out.push_back(p);
  return out;
}

bool regular_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && !ec;
}

}  // namespace

void check_match_names_graph(const documents::MatchResult& match, const std::string& match_name,
                             const documents::SegmentGraph& graph, const std::string& graph_name) {
  std::map<int, double> area;
  for (const auto& s : graph.segments) area[s.segment_id] = s.area;
  for (std::size_t m = 0; m < match.models.size(); ++m) {
    const auto& pairs = match.models[m].pairs;
    const std::string who = "models[" + std::to_string(m) + "] (" + match.models[m].model + ")";
    std::set<int> named;
    double smallest = std::numeric_limits<double>::infinity();
    for (const auto& p : pairs) {
      const auto it = area.find(p.object_segment);
      if (it == area.end()) {
        throw DataError(match_name, who + " pairs object segment " + std::to_string(p.object_segment) +
                                        ", which " + graph_name +
                                        " does not have: the match was made from another segment graph");
      }
      if (!named.insert(p.object_segment).second) {
        throw DataError(match_name,
                        who + " pairs object segment " + std::to_string(p.object_segment) + " twice");
      }
      smallest = std::min(smallest, it->second);
    }
    // gmatch pairs the X largest object segments: none left out may be larger.
    for (const auto& [id, a] : area) {
      if (!named.count(id) && a > smallest) {
        throw DataError(match_name, who + " pairs segments of " + fmt(smallest) + " m² but not segment " +
                                        std::to_string(id) + " of " + graph_name + " (" + fmt(a) +
                                        " m²): the match was made from another segment graph");
      }
    }
  }
}

void check_graph_on_points(const documents::SegmentGraph& graph, const std::string& graph_name,
                           const std::vector<Eigen::Vector3d>& points, const std::string& points_name) {
  if (points.empty()) return;
  Eigen::Vector3d lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Rounding of the centroid's moments: far below a micrometre per metre of extent.
  const double tol =
      1e-6 * (1 + (hi - lo).norm() + std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));
  long long vertices = 0;
  for (const auto& s : graph.segments) {
    vertices += s.vertex_count;
    for (int v : s.vertices) {
      if (v >= static_cast<long long>(points.size())) {
        throw DataError(graph_name, "segment " + std::to_string(s.segment_id) + " has mesh vertex " +
                                        std::to_string(v) + ", but " + points_name + " has only " +
                                        std::to_string(points.size()) +
                                        " points: the segments were not made from these points");
      }
    }
    const Eigen::Vector3d c(s.centroid[0], s.centroid[1], s.centroid[2]);
    if ((c.array() < lo.array() - tol).any() || (c.array() > hi.array() + tol).any()) {
      throw DataError(graph_name, "segment " + std::to_string(s.segment_id) + " has its centroid at " +
                                      point_text(c) + ", outside the box of " + points_name + " " +
                                      point_text(lo) + " - " + point_text(hi) +
                                      ": the segments were not made from these points");
    }
  }
  if (vertices > static_cast<long long>(points.size())) {
    throw DataError(graph_name, "its segments hold " + std::to_string(vertices) + " mesh vertices, but " +
                                    points_name + " has only " + std::to_string(points.size()) +
                                    " points: the segments were not made from these points");
  }
}

void check_mesh_on_points(const std::vector<Eigen::Vector3d>& mesh, const std::string& mesh_name,
                          const std::string& graph_name, const std::vector<Eigen::Vector3d>& points,
                          const std::string& points_name) {
  std::vector<std::array<double, 3>> sorted;
  sorted.reserve(points.size());
  for (const auto& p : points) sorted.push_back({p.x(), p.y(), p.z()});
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < mesh.size(); ++i) {
    const std::array<double, 3> q{mesh[i].x(), mesh[i].y(), mesh[i].z()};
    if (!std::binary_search(sorted.begin(), sorted.end(), q)) {
      throw DataError(graph_name, "its mesh " + mesh_name + " has vertex " + std::to_string(i) + " at " +
                                      point_text(mesh[i]) + ", which is not a point of " + points_name +
                                      ": the segments were not made from these points");
    }
  }
}

void check_inputs_belong(const BelongInputs& in) {
  const std::string match_name = common::display_name(in.match_path);
  const std::string graph_name = common::display_name(in.segments_path);
  const std::string points_name = common::display_name(in.points_path);
  if (in.segments == nullptr) {
    // A match result without pairs (baseline --hypotheses) names the points it was made from.
    if (in.points_path == "-" || in.match->object == in.points_path) return;
    for (const auto& p : resolutions(in.match->object, in.match_path)) {
      if (regular_file(p) && !common::same_file_contents(p.string(), in.points_path)) {
        throw DataError(match_name, "was made from " + in.match->object + ", not from " + points_name +
                                        " (--points): give the points its poses are in");
      }
    }
    return;
  }
  // 1. The match names the segment graph it was made from ("object").
  if (in.segments_path != "-" && in.match->object != in.segments_path) {
    bool found = false, same = false;
    for (const auto& p : resolutions(in.match->object, in.match_path)) {
      if (!regular_file(p)) continue;
      found = true;
      if (common::same_file_contents(p.string(), in.segments_path)) same = true;
    }
    if (found && !same) {
      throw DataError(match_name, "was made from the segment graph " + in.match->object + ", not from " +
                                      graph_name + " (--segments): give the graph gmatch matched");
    }
  }
  // 2. Its pairs name the graph's largest segments.
  check_match_names_graph(*in.match, match_name, *in.segments, graph_name);
  // 3. The graph lies on the points: vertex indices, vertex count, centroids.
  check_graph_on_points(*in.segments, graph_name, in.candidate->points, points_name);
  // 4. The graph's mesh ("mesh"), when it is there and is the graph's (as many vertices as the
  // segments hold): every vertex is one of the points (cocone keeps sample rows as they are).
  long long vertices = 0;
  for (const auto& s : in.segments->segments) vertices += s.vertex_count;
  for (const auto& p : resolutions(in.segments->mesh, in.segments_path)) {
    if (!regular_file(p)) continue;
    formats::Mesh mesh;
    try {
      mesh = formats::read_ply(p.string());
    } catch (const common::Error& e) {
      common::log::debug(std::string("not checked against the mesh: ") + e.what());
      continue;
    }
    if (static_cast<long long>(mesh.vertices.size()) != vertices) {
      common::log::debug("not checked against " + p.string() + ": " + std::to_string(mesh.vertices.size()) +
                         " vertices, the segments hold " + std::to_string(vertices));
      continue;
    }
    check_mesh_on_points(formats::to_vectors(mesh.vertices), p.string(), graph_name, in.candidate->points,
                         points_name);
    return;
  }
}

}  // namespace canopy::verify
