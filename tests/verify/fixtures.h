// Synthetic vehicles, clutter and candidates for the verify tests: unions of axis-aligned
// boxes (model frame: ground z = 0, front +x) sampled on a grid with exact normals, one
// segment per box face, and candidates seen by 12 views at 75 degrees elevation.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/point_cloud.h"
#include "canopy/documents/segment_graph.h"
#include "verify/verify.h"

namespace verify_test {

using Eigen::Isometry3d;
using Eigen::Vector3d;

struct Box {
  Vector3d lo, hi;
  bool inside(const Vector3d& p, double eps = 1e-9) const {
    return (p.array() > lo.array() + eps).all() && (p.array() < hi.array() - eps).all();
  }
};

// Body + cabin at the front: asymmetric front/back, so the 180-degree flip is wrong.
inline std::vector<Box> pickup() {
  return {{{-2.5, -0.9, 0.3}, {2.5, 0.9, 1.0}}, {{0.6, -0.8, 1.0}, {2.2, 0.8, 1.7}}};
}
// A longer, lower flatbed with a tall cab at the front and a crate at the back.
inline std::vector<Box> flatbed() {
  return {{{-3.5, -1.2, 0.5}, {3.5, 1.2, 1.1}},
          {{2.0, -1.1, 1.1}, {3.4, 1.1, 2.6}},
          {{-3.3, -1.0, 1.1}, {-1.5, 1.0, 1.9}}};
}

// Surface samples of the union's outer faces (no bottom faces), grid spacing h shifted by
// `offset`, with exact outward normals.
inline canopy::verify::Surface sample(const std::vector<Box>& boxes, double h, double offset = 0) {
  canopy::verify::Surface s;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const Box& B = boxes[b];
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        if (axis == 2 && side == 0) continue;  // bottom
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        Vector3d n = Vector3d::Zero();
        n[axis] = side ? 1 : -1;
        for (double a = B.lo[u] + offset + h / 2; a < B.hi[u]; a += h) {
          for (double c = B.lo[v] + offset + h / 2; c < B.hi[v]; c += h) {
            Vector3d p;
            p[axis] = side ? B.hi[axis] : B.lo[axis];
            p[u] = a;
            p[v] = c;
            bool covered = false;
            for (std::size_t o = 0; o < boxes.size(); ++o) {
              const Box& O = boxes[o];
              const Vector3d q = p + 1e-6 * n;
              if (o != b && (q.array() >= O.lo.array()).all() && (q.array() <= O.hi.array()).all()) {
                covered = true;
              }
            }
            if (covered) continue;
            s.points.push_back(p);
            s.normals.push_back(n);
          }
        }
      }
    }
  }
  return s;
}

// One segment per box face (ids 6 b + face), centroid/normal/area of the face.
inline canopy::documents::SegmentGraph graph(const std::vector<Box>& boxes) {
  canopy::documents::SegmentGraph g;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const Box& B = boxes[b];
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        canopy::documents::Segment s;
        s.segment_id = static_cast<int>(6 * b + 2 * axis + side);
        s.vertex_count = 10;
        const Vector3d c = (B.lo + B.hi) / 2;
        s.centroid = {c.x(), c.y(), c.z()};
        s.centroid[axis] = side ? B.hi[axis] : B.lo[axis];
        s.normal = {0, 0, 0};
        s.normal[axis] = side ? 1 : -1;
        s.area = (B.hi[u] - B.lo[u]) * (B.hi[v] - B.lo[v]);
        s.thickness = 0.01;
        s.elongation = 0.5;
        g.segments.push_back(s);
      }
    }
  }
  return g;
}

inline std::vector<Vector3d> views75() {
  std::vector<Vector3d> v;
  const double el = 75 * canopy::common::kPi / 180;
  for (int k = 0; k < 12; ++k) {
    const double az = 2 * canopy::common::kPi * k / 12;
    v.emplace_back(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el));
  }
  return v;
}

// The candidate: the surface posed by T, the points some view faces (n.s > 0.25) with the
// sensor direction of the view facing them most, plus ground points (z = 0, spacing h) over
// 10 x 5 m around T's origin outside the objects' footprints.
inline canopy::verify::Candidate candidate(const canopy::verify::Surface& surface,
                                           const std::vector<Box>& boxes, const Isometry3d& T, double h = 0.1) {
  canopy::verify::Candidate c;
  const auto views = views75();
  for (std::size_t i = 0; i < surface.points.size(); ++i) {
    const Vector3d p = T * surface.points[i], n = T.linear() * surface.normals[i];
    double best = 0.25;
    int view = -1;
    for (std::size_t k = 0; k < views.size(); ++k) {
      if (n.dot(views[k]) > best) {
        best = n.dot(views[k]);
        view = static_cast<int>(k);
      }
    }
    if (view < 0) continue;
    c.points.push_back(p);
    c.normals.push_back(n);
    c.sensor.push_back(views[view]);
  }
  const Isometry3d inv = T.inverse();
  for (double x = -5; x < 5; x += h) {
    for (double y = -2.5; y < 2.5; y += h) {
      const Vector3d p = T * Vector3d(x, y, 0);
      const Vector3d g(p.x(), p.y(), 0);
      const Vector3d m = inv * g;
      bool under = false;
      for (const auto& b : boxes) {
        if (m.x() > b.lo.x() && m.x() < b.hi.x() && m.y() > b.lo.y() && m.y() < b.hi.y()) under = true;
      }
      if (under) continue;
      c.points.push_back(g);
      c.normals.push_back(Vector3d::UnitZ());
      c.sensor.push_back(views[0]);
    }
  }
  return c;
}

inline Isometry3d pose(double heading, double x, double y, double z = 0) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(heading, Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Vector3d(x, y, z);
  return T;
}

// A sphere of radius r centred at height zc (upper part above the ground), spacing h.
inline canopy::verify::Surface sphere(double r, double zc, double h) {
  canopy::verify::Surface s;
  const int rings = static_cast<int>(canopy::common::kPi * r / h);
  for (int i = 0; i <= rings; ++i) {
    const double th = canopy::common::kPi * i / rings;
    const int n = std::max(1, static_cast<int>(2 * canopy::common::kPi * r * std::sin(th) / h));
    for (int j = 0; j < n; ++j) {
      const double ph = 2 * canopy::common::kPi * j / n;
      const Vector3d d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const Vector3d p = Vector3d(0, 0, zc) + r * d;
      if (p.z() < 0.02) continue;
      s.points.push_back(p);
      s.normals.push_back(d);
    }
  }
  return s;
}

// Points cloud as written by fitvox (x y z, normals, sensor) from a candidate.
inline canopy::formats::PointCloud to_cloud(const canopy::verify::Candidate& c, bool normals = true) {
  canopy::formats::PointCloud cloud;
  cloud.resize(c.points.size());
  const char* xyz[3] = {"x", "y", "z"};
  const char* nrm[3] = {"normal_x", "normal_y", "normal_z"};
  const char* sen[3] = {"sensor_x", "sensor_y", "sensor_z"};
  for (int a = 0; a < 3; ++a) {
    auto& col = cloud.add(xyz[a]);
    for (std::size_t i = 0; i < c.points.size(); ++i) col[i] = c.points[i][a];
  }
  if (normals) {
    for (int a = 0; a < 3; ++a) {
      auto& col = cloud.add(nrm[a]);
      for (std::size_t i = 0; i < c.points.size(); ++i) col[i] = c.normals[i][a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    auto& col = cloud.add(sen[a]);
    for (std::size_t i = 0; i < c.points.size(); ++i) col[i] = c.sensor[i][a];
  }
  return cloud;
}

// The vehicle's surface `s` on its ground, as fitvox samples a scan of both: `s`'s points first,
// then ground samples (normal up) every h over 8 x 4 m around the origin outside the boxes'
// footprints, alternately at z = 0 and z = 0.04 (under verify's 5 cm cut for unlabelled surfaces).
inline canopy::verify::Surface on_ground(canopy::verify::Surface s, const std::vector<Box>& boxes,
                                         double h = 0.2) {
  int k = 0;
  for (double x = -4 + h / 2; x < 4; x += h) {
    for (double y = -2 + h / 2; y < 2; y += h) {
      bool under = false;
      for (const auto& b : boxes) {
        if (x > b.lo.x() && x < b.hi.x() && y > b.lo.y() && y < b.hi.y()) under = true;
      }
      if (under) continue;
      s.points.emplace_back(x, y, (k++ % 2) ? 0.04 : 0.0);
      s.normals.push_back(Vector3d::UnitZ());
    }
  }
  return s;
}

// A modelbase surface PCD's columns (x y z, normals) from `s`; with `labels`, a U4 label column
// (one value per point), as fitvox writes it.
inline canopy::formats::PointCloud surface_pcd(const canopy::verify::Surface& s,
                                               const std::vector<std::uint32_t>* labels = nullptr) {
  canopy::formats::PointCloud cloud;
  cloud.resize(s.points.size());
  const char* xyz[3] = {"x", "y", "z"};
  const char* nrm[3] = {"normal_x", "normal_y", "normal_z"};
  for (int a = 0; a < 3; ++a) {
    auto& p = cloud.add(xyz[a]);
    for (std::size_t i = 0; i < s.points.size(); ++i) p[i] = s.points[i][a];
  }
  for (int a = 0; a < 3; ++a) {
    auto& n = cloud.add(nrm[a]);
    for (std::size_t i = 0; i < s.points.size(); ++i) n[i] = s.normals[i][a];
  }
  if (labels != nullptr) {
    auto& l = cloud.add("label", canopy::formats::kUint32);
    for (std::size_t i = 0; i < s.points.size(); ++i) l[i] = (*labels)[i];
  }
  return cloud;
}

// A match result ranking `names` in order; the first `paired` get every face paired with the
// same id (the graphs are then built from the same boxes), the others only NULL pairs.
inline canopy::documents::MatchResult match(const std::vector<std::string>& names,
                                            const std::vector<canopy::documents::SegmentGraph>& graphs,
                                            bool with_pairs) {
  canopy::documents::MatchResult r;
  r.provenance = {"test", "0", {}, {}};
  r.object = "segments.json";
  r.error_form = "bounded";
  for (std::size_t i = 0; i < names.size(); ++i) {
    canopy::documents::ModelScore m;
    m.model = names[i];
    m.rank = static_cast<int>(i + 1);
    m.score = 0.5 - 0.1 * i;
    for (const auto& s : graphs[i].segments) {
      if (s.normal[2] < -0.5) continue;  // no bottom faces
      m.pairs.push_back({s.segment_id, with_pairs ? s.segment_id : -1, 0.0});
    }
    r.models.push_back(m);
  }
  return r;
}

}  // namespace verify_test

namespace verify_test {
// The graph with centroids and normals moved by T (the object's graph seen in the scene).
inline canopy::documents::SegmentGraph posed(canopy::documents::SegmentGraph g, const Isometry3d& T) {
  for (auto& s : g.segments) {
    const Vector3d c = T * Vector3d(s.centroid[0], s.centroid[1], s.centroid[2]);
    const Vector3d n = T.linear() * Vector3d(s.normal[0], s.normal[1], s.normal[2]);
    s.centroid = {c.x(), c.y(), c.z()};
    s.normal = {n.x(), n.y(), n.z()};
  }
  return g;
}
}  // namespace verify_test
