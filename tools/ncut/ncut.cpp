#include "ncut/ncut.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/formats/cloud_eigen.h"

namespace canopy::ncut {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double triangle_area(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

// Running area, first and second moments of one segment, relative to a reference point.
struct Moments {
  Vector3d ref = Vector3d::Zero();
  double area = 0;
  Vector3d m1 = Vector3d::Zero();
  Matrix3d m2 = Matrix3d::Zero();
  void add_triangle(const Vector3d& p, const Vector3d& q, const Vector3d& r) {
    const double t = triangle_area(p, q, r);
    const Vector3d a = p - ref, b = q - ref, c = r - ref, s = a + b + c;
    area += t;
    m1 += t * s / 3.0;
    // Exact second moment of a triangle: (t / 12) (a a^T + b b^T + c c^T + s s^T).
    m2 += (t / 12.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
};

}  // namespace

void validate(const Params& p) {
  const auto& a = p.affinity;
  const auto& s = p.sparsify;
  auto need = [](bool ok, const std::string& rule) {
    if (!ok) throw common::UsageError(rule);
  };
  const double deg = common::kDegree;
  need(a.sigma_n > 0 && a.sigma_n <= 180 * deg, "--sigma-n must be in (0, 180] deg");
  need(a.anisotropy >= 1 && a.anisotropy <= 1e6, "--anisotropy must be in [1, 1e6]");
  need(a.radius >= 1e-3 && a.radius <= 100, "--radius must be in [1mm, 100m]");
  need(s.dense_radius >= 0 && s.dense_radius <= 100, "--dense-radius must be in [0, 100m]");
  need(s.keep_fraction >= 0 && s.keep_fraction <= 1, "--keep-fraction must be in [0, 1]");
  need(s.min_affinity >= 0 && s.min_affinity < 1, "--min-affinity must be in [0, 1)");
  need(s.mesh_edge_floor >= 0 && s.mesh_edge_floor <= 0.1, "--mesh-edge-floor must be in [0, 0.1]");
  need(p.cut.max_ncut > 0, "--max-ncut must be > 0");
  need(p.cut.min_segment >= 1, "--min-segment must be >= 1");
  need(p.cut.tolerance > 0 && p.cut.tolerance <= 1e-3, "--tolerance must be in (0, 1e-3]");
  need(p.cut.max_restarts >= 1, "--max-restarts must be >= 1");
  need(p.cut.ncv >= 3, "--ncv must be >= 3");
}

Inputs input_from_mesh(const formats::Mesh& mesh, const std::string& name) {
  const formats::PointCloud& v = mesh.vertices;
  v.require({"x", "y", "z"}, name, "is this a canopy mesh?");
  const std::size_t n = v.size();
  if (n == 0) throw common::DataError(name, "mesh has no vertices");
  if (mesh.faces.empty()) {
    throw common::DataError(name, "mesh has no faces (ncut segments a triangle mesh)");
  }
  Inputs in;
  in.points = formats::finite_vectors(v, name, formats::kXyzFields, "vertex");
  if (formats::has_fields(v, formats::kNormalFields)) {
    in.normals = formats::finite_vectors(v, name, formats::kNormalFields, "vertex", "normal");
    for (Vector3d& normal : in.normals) {
      const double len = normal.norm();
      if (len > 0) normal /= len;
    }
  }
  if (v.has("label")) in.labels = formats::uint32_column(v, "label", name, "vertex");
  in.faces.reserve(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || static_cast<std::size_t>(t[k]) >= n) {
        throw common::DataError(name, "face " + std::to_string(f) + " has vertex index " + std::to_string(t[k]) +
                                          " (mesh has " + std::to_string(n) + " vertices)");
      }
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      throw common::DataError(name, "face " + std::to_string(f) + " repeats a vertex");
    }
    in.faces.push_back({t[0], t[1], t[2]});
  }
  double area = 0;
  for (const auto& f : in.faces) area += triangle_area(in.points[f[0]], in.points[f[1]], in.points[f[2]]);
  if (!(area > 0)) {
    throw common::DataError(name, "all " + std::to_string(in.faces.size()) +
                                      " faces have zero area (their vertices coincide or are collinear): "
                                      "no surface to segment");
  }
  return in;
}

void check_segments(const Result& r, const std::string& name) {
  for (const documents::Segment& s : r.graph.segments) {
    if (s.area > 0 && std::isfinite(s.area)) continue;
    throw common::DataError(
        name, "segment " + std::to_string(s.segment_id) + " (" + std::to_string(s.vertex_count) +
                  " vertices) has zero area: its vertices lie on no face of nonzero area (unreferenced "
                  "vertices or degenerate faces); a segment graph needs area > 0 in every segment");
  }
}

std::vector<Vector3d> vertex_normals(const std::vector<Vector3d>& points,
                                     const std::vector<std::array<int, 3>>& faces) {
  std::vector<Vector3d> n(points.size(), Vector3d::Zero());
  for (const auto& f : faces) {
    // |cross| = 2 * area: the sum is area-weighted.
    const Vector3d c = (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]);
    for (int k = 0; k < 3; ++k) n[f[k]] += c;
  }
  for (auto& v : n) {
    const double len = v.norm();
    if (len > 0) v /= len;
  }
  return n;
}

std::vector<std::array<int, 2>> mesh_edges(const std::vector<std::array<int, 3>>& faces) {
  std::vector<std::array<int, 2>> e;
  e.reserve(3 * faces.size());
  for (const auto& f : faces) {
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      e.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

namespace {

// Per-segment sums gathered over the mesh before the attributes are derived.
struct SegmentSums {
  std::vector<Moments> mom;
  std::vector<Vector3d> normal_sum;
  std::vector<std::map<std::uint32_t, double>> label_area;
  std::vector<std::map<std::uint32_t, int>> label_count;
  std::vector<double> vertex_area;
};

// Vertex lists of the segments, the area moments of each vertex's barycentric cells, and the
// area-weighted normal and label sums.
SegmentSums gather_segment_sums(const Inputs& in, const std::vector<Vector3d>& normals,
                                const std::vector<int>& segment, int count,
                                std::vector<documents::Segment>& out) {
  const std::size_t n = in.points.size();
  SegmentSums sums;
  sums.mom.resize(count);
  sums.normal_sum.assign(count, Vector3d::Zero());
  sums.label_area.resize(count);
  sums.label_count.resize(count);
  sums.vertex_area.assign(n, 0.0);
  std::vector<Moments>& mom = sums.mom;
  std::vector<double>& vertex_area = sums.vertex_area;

  for (std::size_t v = 0; v < n; ++v) {
    documents::Segment& s = out[segment[v]];
    if (s.vertices.empty()) mom[segment[v]].ref = in.points[v];
    s.vertices.push_back(static_cast<int>(v));
  }
  for (const auto& f : in.faces) {
    const Vector3d g = (in.points[f[0]] + in.points[f[1]] + in.points[f[2]]) / 3.0;
    const double t = triangle_area(in.points[f[0]], in.points[f[1]], in.points[f[2]]);
    for (int k = 0; k < 3; ++k) {
      const int v = f[k];
      vertex_area[v] += t / 3.0;
      // The barycentric cell of v in this triangle: v, the two edge midpoints, the centroid.
      const Vector3d& p = in.points[v];
      const Vector3d mu = 0.5 * (p + in.points[f[(k + 1) % 3]]);
      const Vector3d mw = 0.5 * (p + in.points[f[(k + 2) % 3]]);
      Moments& m = mom[segment[v]];
      m.add_triangle(p, mu, g);
      m.add_triangle(p, g, mw);
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    const int s = segment[v];
    sums.normal_sum[s] += (vertex_area[v] > 0 ? vertex_area[v] : 1.0) * normals[v];
    const std::uint32_t label = in.labels.empty() ? 0u : in.labels[v];
    sums.label_area[s][label] += vertex_area[v];
    sums.label_count[s][label] += 1;
  }
  return sums;
}

// Centroid and covariance of one segment: from the surface moments, or from its vertices.
void segment_moments(const Inputs& in, const documents::Segment& s, const Moments& m, PcaWeighting pca,
                     Vector3d& centroid, Matrix3d& cov) {
  if (pca == PcaWeighting::kSurface && m.area > 0) {
    const Vector3d mean = m.m1 / m.area;
    centroid = m.ref + mean;
    cov = m.m2 / m.area - mean * mean.transpose();
  } else {
    Vector3d sum = Vector3d::Zero();
    for (int v : s.vertices) sum += in.points[v] - m.ref;
    const Vector3d mean = sum / s.vertex_count;
    cov.setZero();
    for (int v : s.vertices) {
      const Vector3d d = in.points[v] - m.ref - mean;
      cov += d * d.transpose();
    }
    cov /= s.vertex_count;
    centroid = m.ref + mean;
  }
}

// Radii, thickness, elongation, centroid and the normal (oriented along the summed vertex normals).
void segment_shape(const Vector3d& centroid, Matrix3d cov, const Vector3d& normal_sum, documents::Segment& s) {
  cov = 0.5 * (cov + cov.transpose());
  Eigen::SelfAdjointEigenSolver<Matrix3d> es(cov);
  const Vector3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending
  const double l1 = ev[2], l2 = ev[1], l3 = ev[0];
  s.radii = {std::sqrt(l1), std::sqrt(l2), std::sqrt(l3)};
  s.thickness = l1 > 0 ? std::sqrt(l3 / l1) : 0.0;
  s.elongation = l1 > 0 ? std::sqrt(l2 / l1) : 0.0;
  s.centroid = {centroid.x(), centroid.y(), centroid.z()};

  Vector3d normal = es.eigenvectors().col(0);
  if (l1 == 0 && normal_sum.norm() > 0) normal = normal_sum.normalized();
  double agree = normal.dot(normal_sum);
  if (agree == 0) {
    Eigen::Index k;
    normal.cwiseAbs().maxCoeff(&k);
    agree = normal[k];
  }
  if (agree < 0) normal = -normal;
  s.normal = {normal.x(), normal.y(), normal.z()};
}

// Majority label by area (by count when the segment has no area); ties -> lower label.
void segment_label(const std::map<std::uint32_t, double>& label_area,
                   std::map<std::uint32_t, int>& label_count, documents::Segment& s) {
  const bool by_area = s.area > 0;
  double best = -1, total = 0;
  for (const auto& [label, a] : label_area) {
    const double w = by_area ? a : label_count[label];
    total += w;
    if (w > best) {
      best = w;
      s.label = static_cast<int>(label);
    }
  }
  s.label_purity = total > 0 ? best / total : 1.0;
}

}  // namespace

std::vector<documents::Segment> segment_attributes(const Inputs& in, const std::vector<Vector3d>& normals,
                                                   const std::vector<int>& segment, int count,
                                                   PcaWeighting pca) {
  std::vector<documents::Segment> out(count);
  SegmentSums sums = gather_segment_sums(in, normals, segment, count, out);
  for (int id = 0; id < count; ++id) {
    documents::Segment& s = out[id];
    s.segment_id = id;
    s.vertex_count = static_cast<int>(s.vertices.size());
    double area = 0;
    for (int v : s.vertices) area += sums.vertex_area[v];
    s.area = area;

    Vector3d centroid;
    Matrix3d cov;
    segment_moments(in, s, sums.mom[id], pca, centroid, cov);
    segment_shape(centroid, cov, sums.normal_sum[id], s);
    segment_label(sums.label_area[id], sums.label_count[id], s);
  }
  return out;
}

std::vector<documents::SegmentEdge> segment_adjacency(const std::vector<std::array<int, 3>>& faces,
                                                      const std::vector<int>& segment) {
  std::map<std::pair<int, int>, int> shared;
  for (const auto& e : mesh_edges(faces)) {
    const int a = segment[e[0]], b = segment[e[1]];
    if (a != b) ++shared[{std::min(a, b), std::max(a, b)}];
  }
  std::vector<documents::SegmentEdge> out;
  for (const auto& [ab, c] : shared) out.push_back({ab.first, ab.second, c});
  return out;
}

Outputs run(const Params& params, const Inputs& in) {
  Result res;
  const std::size_t n = in.points.size();
  std::vector<Vector3d> normals = in.normals;
  const std::vector<Vector3d> from_faces = vertex_normals(in.points, in.faces);
  if (normals.empty()) {
    normals = from_faces;
    res.stats.normals_computed = true;
  } else {
    for (std::size_t v = 0; v < n; ++v) {
      if (normals[v].squaredNorm() == 0) normals[v] = from_faces[v];
    }
  }
  for (const auto& v : normals) res.stats.vertices_without_normal += v.squaredNorm() == 0;

  auto t0 = std::chrono::steady_clock::now();
  SurfacePoints pts{in.points, normals};
  ThesisAffinity affinity(pts, params.affinity);
  const Graph g = build_affinity_graph(pts, mesh_edges(in.faces), affinity, params.sparsify, &res.stats.graph);
  res.stats.seconds_graph = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  res.segment = recursive_ncut(g, params.cut, &res.stats.cut);
  res.stats.seconds_cut = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const int count = res.segment.empty() ? 0 : *std::max_element(res.segment.begin(), res.segment.end()) + 1;
  res.graph.segments = segment_attributes(in, normals, res.segment, count, params.pca);
  res.graph.adjacency = segment_adjacency(in.faces, res.segment);
  res.stats.seconds_attributes = seconds_since(t0);
  return res;
}

std::array<std::uint8_t, 3> segment_colour(int segment_id) {
  const double h = std::fmod(0.13 + 0.6180339887498949 * segment_id, 1.0) * 6.0;
  const double s = (segment_id / 3) % 2 == 0 ? 0.75 : 0.5;
  const double v = (segment_id / 6) % 2 == 0 ? 0.95 : 0.75;
  const int i = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (i) {
    case 1:
      r = q;
      g = v;
      b = p;
      break;
    case 2:
      r = p;
      g = v;
      b = t;
      break;
    case 3:
      r = p;
      g = q;
      b = v;
      break;
    case 4:
      r = t;
      g = p;
      b = v;
      break;
    case 5:
      r = v;
      g = p;
      b = q;
      break;
    default: break;
  }
  auto u8 = [](double c) { return static_cast<std::uint8_t>(std::lround(255.0 * c)); };
  return {u8(r), u8(g), u8(b)};
}

formats::Mesh colored_mesh(const formats::Mesh& mesh, const std::vector<int>& segment) {
  formats::Mesh out = mesh;
  for (const char* name : {"red", "green", "blue"}) out.vertices.add(name, formats::kUint8);
  out.vertices.add("segment", formats::kInt32);
  auto& seg = out.vertices.col("segment");
  auto& red = out.vertices.col("red");
  auto& green = out.vertices.col("green");
  auto& blue = out.vertices.col("blue");
  for (std::size_t v = 0; v < segment.size(); ++v) {
    const auto c = segment_colour(segment[v]);
    seg[v] = segment[v];
    red[v] = c[0];
    green[v] = c[1];
    blue[v] = c[2];
  }
  return out;
}

}  // namespace canopy::ncut
