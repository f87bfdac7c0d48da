#include "areas/areas.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/labels.h"

namespace canopy::areas {
namespace {

using Eigen::Vector3d;
using Key = std::array<std::int64_t, 3>;

struct KeyHash {
  std::size_t operator()(const Key& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::int64_t v : k) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

double inv_l1(const Vector3d& n) {
  const double l1 = std::abs(n(0)) + std::abs(n(1)) + std::abs(n(2));
  return l1 > 0 ? 1.0 / std::max(l1, 1.0) : 1.0 / 1.5;
}

std::string num(double v) { return documents::number_text(v); }

}  // namespace

double visible_area(const std::vector<ScanPoint>& points, double spacing, double cell, double min_cos) {
  if (!(cell > 0) || !std::isfinite(cell)) throw common::Error("cell must be a positive length");
  if (!(spacing > 0) || !std::isfinite(spacing)) throw common::Error("spacing must be a positive length");
  if (!(min_cos > 0 && min_cos <= 1)) throw common::Error("min_cos must be in (0, 1]");
  std::unordered_map<Key, std::vector<std::size_t>, KeyHash> cells;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vector3d& p = points[i].p;
    if (!p.allFinite() || !points[i].toward.allFinite()) {
      throw common::Error("point " + std::to_string(i) + ": non-finite coordinate or direction");
    }
    const Key k{static_cast<std::int64_t>(std::floor(p(0) / cell + 0.5)),
                static_cast<std::int64_t>(std::floor(p(1) / cell + 0.5)),
                static_cast<std::int64_t>(std::floor(p(2) / cell + 0.5))};
    cells[k].push_back(i);
  }
  // Sum in key order so the result does not depend on the hash table's iteration order.
  std::vector<Key> keys;
  keys.reserve(cells.size());
  for (const auto& kv : cells) keys.push_back(kv.first);
  std::sort(keys.begin(), keys.end());
  const double pixel = spacing * spacing;
  double area = 0;
  std::vector<Vector3d> nb;
  std::vector<int> nb_views;
  for (const Key& k : keys) {
    const std::vector<std::size_t>& own = cells[k];
    const Vector3d origin = points[own.front()].p;
    nb.clear();
    nb_views.clear();
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == cells.end()) continue;
          for (std::size_t i : it->second) {
            nb.push_back(points[i].p - origin);
            nb_views.push_back(points[i].view);
          }
        }
      }
    }
    // Normal of the neighbourhood; none (fewer than 3 points, collinear) -> footprint = pixel.
    bool has_normal = false;
    Vector3d n = Vector3d::UnitZ();
    if (nb.size() >= 3) {
      Vector3d mean = Vector3d::Zero();
      for (const Vector3d& q : nb) mean += q;
      mean /= static_cast<double>(nb.size());
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const Vector3d& q : nb) cov.noalias() += (q - mean) * (q - mean).transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
      const Vector3d ev = es.eigenvalues();
      if (es.info() == Eigen::Success && ev(2) > 0 && ev(1) > 1e-9 * ev(2)) {
        n = es.eigenvectors().col(0);
        has_normal = true;
      }
    }
    // Views that see this part of the surface: those with a point in the neighbourhood.
    std::sort(nb_views.begin(), nb_views.end());
    const auto views = static_cast<double>(std::unique(nb_views.begin(), nb_views.end()) - nb_views.begin());
    double best = 0;
    for (std::size_t i : own) {
      const double c = has_normal ? std::max(min_cos, std::abs(n.dot(points[i].toward.normalized()))) : 1.0;
      best += pixel / c;
    }
    best /= views;
    area += best;
  }
  return area;
}

double samples_area(const std::vector<Vector3d>& normals, double voxel) {
  double area = 0;
  for (const Vector3d& n : normals) area += voxel * voxel * inv_l1(n.normalized());
  return area;
}

double mesh_area(const formats::Mesh& mesh, std::uint32_t label) {
  const auto& v = mesh.vertices;
  const bool labelled = v.has("label");
  const auto& x = v.col("x");
  const auto& y = v.col("y");
  const auto& z = v.col("z");
  double area = 0;
  for (const auto& f : mesh.faces) {
    int hits = 0;
    for (int j = 0; j < 3; ++j) {
      hits += labelled && v.col("label")[static_cast<std::size_t>(f[j])] == label;
    }
    if (hits == 0) continue;
    auto P = [&](int j) {
      const auto i = static_cast<std::size_t>(f[j]);
      return Vector3d(x[i], y[i], z[i]);
    };
    area += 0.5 * (P(1) - P(0)).cross(P(2) - P(0)).norm() * hits / 3.0;
  }
  return area;
}

double segments_area(const documents::SegmentGraph& graph, std::uint32_t label, int largest) {
  std::vector<const documents::Segment*> segs;
  for (const auto& s : graph.segments) segs.push_back(&s);
  std::stable_sort(segs.begin(), segs.end(), [](const documents::Segment* a, const documents::Segment* b) {
    return a->area != b->area ? a->area > b->area : a->segment_id < b->segment_id;
  });
  if (largest > 0 && static_cast<int>(segs.size()) > largest) segs.resize(static_cast<std::size_t>(largest));
  double area = 0;
  for (const auto* s : segs) {
    if (s->label == static_cast<int>(label)) area += s->area * s->label_purity;
  }
  return area;
}

namespace {

std::vector<areas::ScanPoint> scan_targets(const formats::PointCloud& c, const std::string& name) {
  c.require({"x", "y", "z", "sensor_x", "sensor_y", "sensor_z", "view_idx", "label"}, name,
            "a labelled rangetrace scan is needed");
  std::vector<areas::ScanPoint> out;
  const auto& l = c.col("label");
  const std::vector<Eigen::Vector3d> xyz = formats::to_vectors(c);
  const std::vector<Eigen::Vector3d> toward = formats::to_vectors(c, formats::kSensorFields);
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (l[i] != formats::kLabelTarget) continue;
    areas::ScanPoint p;
    p.p = xyz[i];
    p.toward = toward[i];
    p.view = static_cast<int>(c.col("view_idx")[i]);
    out.push_back(p);
  }
  return out;
}

std::vector<Eigen::Vector3d> target_points(const formats::PointCloud& c, const std::string& name,
                                           const char* fx, const char* fy, const char* fz) {
  c.require({fx, fy, fz, "label"}, name, "a labelled cloud is needed");
  std::vector<Eigen::Vector3d> out;
  const auto& l = c.col("label");
  const std::vector<Eigen::Vector3d> v = formats::to_vectors(c, {fx, fy, fz});
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (l[i] == formats::kLabelTarget) out.push_back(v[i]);
  }
  return out;
}

}  // namespace

void validate(const Params& p) {
  using common::UsageError;
  if (!(p.spacing >= 1e-3 && p.spacing <= 10)) throw UsageError("--spacing must be in [1mm, 10m]");
  // The 3x3x3 neighbourhood of a cell must hold points of every view that sees the surface
  // there (cell >= spacing) and stay local (measured from 1 to 3 spacings; docs/decisions/formats.md).
  if (!(p.cell >= p.spacing && p.cell <= 4 * p.spacing)) {
    throw UsageError("--cell must be in [--spacing, 4 x --spacing] (" + num(p.spacing) + " to " +
                     num(4 * p.spacing) + " m here)");
  }
  if (!(p.voxel >= 1e-3 && p.voxel <= 100))
    throw UsageError("--voxel must be in [1mm, 100m] (fitvox's range)");
  if (p.max_segments < 1 || p.max_segments > kMaxSegments) {
    throw UsageError("--max-segments must be in [1, " + std::to_string(kMaxSegments) + "]");
  }
}

Outputs run(const Params& params, const Inputs& in) {
  Areas a;
  a.spacing = params.spacing;
  a.cell = params.cell;
  a.voxel = params.voxel;
  a.max_segments = params.max_segments;
  const auto pts = scan_targets(in.scan, in.scan_name);
  a.target_points = pts.size();
  a.visible = visible_area(pts, a.spacing, a.cell);
  const auto normals = target_points(in.samples, in.samples_name, "normal_x", "normal_y", "normal_z");
  a.target_samples = normals.size();
  a.samples = samples_area(normals, a.voxel);
  in.mesh.vertices.require({"x", "y", "z", "label"}, in.mesh_name, "a labelled cocone mesh is needed");
  a.mesh = mesh_area(in.mesh, formats::kLabelTarget);
  for (const auto& s : in.segments.segments) {
    if (!(s.area >= 0) || !std::isfinite(s.area)) {
      throw common::DataError(in.segments_name, "segment " + std::to_string(s.segment_id) + " has area " +
                                                    num(s.area) + ": an area is a finite number >= 0");
    }
    if (!(s.label_purity >= 0 && s.label_purity <= 1)) {
      throw common::DataError(in.segments_name, "segment " + std::to_string(s.segment_id) +
                                                    " has label_purity " + num(s.label_purity) +
                                                    ", outside [0, 1]");
    }
  }
  a.segments = segments_area(in.segments, formats::kLabelTarget, 0);
  a.matched = segments_area(in.segments, formats::kLabelTarget, a.max_segments);
  if (!std::isfinite(a.segments))
    throw common::DataError(in.segments_name, "the segments' areas sum beyond 1e308");
  if (!std::isfinite(a.visible) || !std::isfinite(a.samples) || !std::isfinite(a.mesh)) {
    throw common::Error("areas: an area is beyond 1e308 (scan " + in.scan_name + ", samples " +
                        in.samples_name + ", mesh " + in.mesh_name + ")");
  }
  return a;
}

}  // namespace canopy::areas
