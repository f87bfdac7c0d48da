#include "verify/verify.h"

#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/serial_kdtree.h"
#include "canopy/common/units.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/pose_eigen.h"

namespace canopy::verify {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

std::uint64_t cell_key(double a, double b, double cell) {
  const auto i = static_cast<std::int64_t>(std::floor(a / cell));
  const auto j = static_cast<std::int64_t>(std::floor(b / cell));
  return (static_cast<std::uint64_t>(i + (1LL << 31)) << 32) ^ static_cast<std::uint64_t>(j + (1LL << 31));
}

pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const std::vector<Vector3d>& pts) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr c(new pcl::PointCloud<pcl::PointXYZ>);
  c->resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    (*c)[i] = pcl::PointXYZ(static_cast<float>(pts[i].x()), static_cast<float>(pts[i].y()),
                            static_cast<float>(pts[i].z()));
  }
  return c;
}

pcl::PointCloud<pcl::PointNormal>::Ptr to_pcl(const std::vector<Vector3d>& pts,
                                              const std::vector<Vector3d>& nrm) {
  pcl::PointCloud<pcl::PointNormal>::Ptr c(new pcl::PointCloud<pcl::PointNormal>);
  c->resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto& q = (*c)[i];
    q.x = static_cast<float>(pts[i].x());
    q.y = static_cast<float>(pts[i].y());
    q.z = static_cast<float>(pts[i].z());
    q.normal_x = static_cast<float>(nrm[i].x());
    q.normal_y = static_cast<float>(nrm[i].y());
    q.normal_z = static_cast<float>(nrm[i].z());
    q.curvature = 0;
  }
  return c;
}

// PCL's point-to-plane linear least squares, guarded: too few correspondences or a singular
// system (a candidate that is one plane) leave the pose unchanged instead of giving NaN.
class SafePointToPlane
    : public pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal, pcl::PointNormal, double> {
 public:
  using Base =
      pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal, pcl::PointNormal, double>;
  using Base::estimateRigidTransformation;
  void estimateRigidTransformation(const pcl::PointCloud<pcl::PointNormal>& src,
                                   const pcl::PointCloud<pcl::PointNormal>& tgt,
                                   const pcl::Correspondences& corr, Matrix4& T) const override {
    T.setIdentity();
    if (corr.size() < 6) return;
    Base::estimateRigidTransformation(src, tgt, corr, T);
    if (!T.allFinite()) T.setIdentity();
  }
};

Isometry3d heading_pose(double theta, const Vector3d& t) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(theta, Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

Vector3d mean_of(const std::vector<Vector3d>& pts) {
  Vector3d m = Vector3d::Zero();
  for (const auto& p : pts) m += p;
  return pts.empty() ? m : Vector3d(m / static_cast<double>(pts.size()));
}

// Angle of the major horizontal principal axis (in (-pi/2, pi/2]).
double major_axis_angle(const std::vector<Vector3d>& pts, const Vector3d& mean) {
  double sxx = 0, sxy = 0, syy = 0;
  for (const auto& p : pts) {
    const double x = p.x() - mean.x(), y = p.y() - mean.y();
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  return 0.5 * std::atan2(2 * sxy, sxx - syy);
}

// Rotates a pose by pi about the vertical axis through the posed model's centre `c`.
Isometry3d flipped(const Isometry3d& pose, const Vector3d& model_centre) {
  const Vector3d c = pose * model_centre;
  Isometry3d R = Isometry3d::Identity();
  R.linear() = Eigen::AngleAxisd(common::kPi, Vector3d::UnitZ()).toRotationMatrix();
  R.translation() = c - R.linear() * c;
  return R * pose;
}

std::vector<Vector3d> unit_columns(const formats::PointCloud& cloud, const std::string& prefix,
                                   const std::string& name, const std::string& hint) {
  const formats::Fields3 fields{prefix + "_x", prefix + "_y", prefix + "_z"};
  cloud.require({fields[0], fields[1], fields[2]}, name, hint);
  std::vector<Vector3d> v = formats::to_vectors(cloud, fields);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double n = v[i].norm();
    if (!std::isfinite(n) || n < 1e-9) {
      throw common::DataError(name,
                              "point " + std::to_string(i) + ": " + prefix + " vector is zero or not finite");
    }
    v[i] /= n;
  }
  return v;
}

std::vector<Vector3d> xyz(const formats::PointCloud& cloud, const std::string& name) {
  cloud.require({"x", "y", "z"}, name, "is this a point cloud?");
  return formats::finite_vectors(cloud, name);
}

}  // namespace

void validate(const Params& p) {
  if (p.top_k < 1) throw common::UsageError("--top-k must be >= 1");
  if (!(p.inlier_distance > 0) || !(p.inlier_radius > 0) || !(p.ray_cell > 0) || !(p.occlusion_margin >= 0) ||
      !(p.icp_coarse > 0) || !(p.icp_fine > 0)) {
    throw common::UsageError(
        "need --inlier-distance, --inlier-radius, --ray-cell, --icp-coarse, --icp-fine > 0 and "
        "--occlusion-margin >= 0");
  }
  if (!(p.facing > 0 && p.facing <= 1)) throw common::UsageError("--facing must be in (0, 1]");
  if (!(p.seen_spacing >= 0 && p.seen_spacing <= 10))
    throw common::UsageError("--seen-spacing must be in [0, 10]");
  if (p.icp_iterations < 0 || p.icp_iterations > kMaxIcpIterations) {
    throw common::UsageError("--icp-iterations must be in [0, " + std::to_string(kMaxIcpIterations) + "]");
  }
  if (p.icp_points < 6) throw common::UsageError("--icp-points must be >= 6");
  if (!(p.accept >= 0 && p.accept <= 1)) throw common::UsageError("--accept must be in [0, 1]");
  if (!(p.max_tilt > 0 && p.max_tilt <= common::kPi + 1e-12))
    throw common::UsageError("--max-tilt must be in (0, 180] degrees");
  if (!(p.box_margin >= -1 && p.box_margin <= 1)) throw common::UsageError("--box-margin must be in [-1, 1]");
  if (!std::isfinite(p.min_height) || !std::isfinite(p.conf_bias) || !std::isfinite(p.conf_score) ||
      !std::isfinite(p.conf_margin) || !std::isfinite(p.conf_box) || !std::isfinite(p.none_bias) ||
      !std::isfinite(p.none_score) || !std::isfinite(p.none_margin) || !std::isfinite(p.none_box)) {
    throw common::UsageError("--min-height and the confidence coefficients must be finite");
  }
}

Candidate candidate_from_cloud(const formats::PointCloud& cloud, const std::string& name,
                               const std::vector<Vector3d>* sensor) {
  if (cloud.empty()) throw common::DataError(name, "empty candidate: no points");
  Candidate c;
  c.points = xyz(cloud, name);
  c.normals = unit_columns(cloud, "normal", name, "verify needs points with normals, e.g. fitvox's samples");
  if (sensor != nullptr) {
    if (sensor->size() != c.points.size()) {
      throw common::DataError(name, std::to_string(sensor->size()) + " sensor directions for " +
                                        std::to_string(c.points.size()) + " points");
    }
    c.sensor = *sensor;
  } else {
    c.sensor = unit_columns(cloud, "sensor", name,
                            "verify needs the direction toward the sensor of every point (or "
                            "--sensor-direction trajectory|scan-angle|vertical)");
  }
  return c;
}

Surface surface_from_cloud(const formats::PointCloud& cloud, const std::string& name, double min_z,
                           bool* zero_labels) {
  const auto pts = xyz(cloud, name);
  const auto nrm =
      unit_columns(cloud, "normal", name, "a modelbase surface needs normals, e.g. fitvox's samples");
  // A label field carries labels when some row is not 0 (unknown): a render's samples
  // (rangetrace: 1 target, 2 foliage, 3 ground). fitvox writes 0 on every row of an input without
  // labels (a tile candidate's points): such a surface is treated as one without the field.
  const std::vector<double>* label = cloud.has("label") ? &cloud.col("label") : nullptr;
  const bool labelled = formats::carries_labels(cloud);
  if (zero_labels != nullptr) *zero_labels = label != nullptr && !labelled;
  Surface s;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const bool keep = labelled ? (*label)[i] == 1 : pts[i].z() > min_z;
    if (!keep) continue;
    s.points.push_back(pts[i]);
    s.normals.push_back(nrm[i]);
  }
  if (s.points.empty() && labelled) {
    std::vector<double> held(label->begin(), label->end());
    std::sort(held.begin(), held.end());
    held.erase(std::unique(held.begin(), held.end()), held.end());
    std::string list;
    for (std::size_t i = 0; i < held.size() && i < 8; ++i) {
      char v[32];
      std::snprintf(v, sizeof v, "%s%.9g", i ? ", " : "", held[i]);
      list += v;
    }
    if (held.size() > 8) list += ", ...";
    throw common::DataError(name,
                            "no model surface points: its label field marks no point as the vehicle "
                            "(label 1; it holds " +
                                list + ")");
  }
  if (s.points.empty()) {
    throw common::DataError(
        name, std::string("no model surface points: ") +
                  (label ? "its label field is 0 (unknown) everywhere" : "it has no label field") +
                  ", and no point lies above the ground (z > " + common::format_length(min_z) +
                  "; ground z = 0 in the model's frame)");
  }
  return s;
}

// ---- scoring ----------------------------------------------------------------------------

double sample_spacing(const std::vector<Vector3d>& points) {
  if (points.size() < 2) return 0;
  common::SerialFlann<pcl::PointXYZ> tree;
  tree.setInputCloud(to_pcl(points));
  std::vector<int> idx(2);
  std::vector<float> d2(2);
  std::vector<double> nn;
  nn.reserve(points.size());
  for (const auto& q : points) {
    const pcl::PointXYZ s(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
    if (tree.nearestKSearch(s, 2, idx, d2) < 2) continue;
    nn.push_back(std::sqrt(static_cast<double>(d2[1])));
  }
  if (nn.empty()) return 0;
  const auto mid = nn.begin() + static_cast<std::ptrdiff_t>(nn.size() / 2);
  std::nth_element(nn.begin(), mid, nn.end());
  return *mid;
}

struct Scorer::Impl {
  common::SerialFlann<pcl::PointXYZ> all;  // every candidate point (the "seen" test)
  struct View {
    Vector3d s, e1, e2;
    std::unordered_map<std::uint64_t, double> depth;  // max p.s per cell
  };
  std::vector<View> views;
  // Model trees, built on first use and cached by surface address.
  mutable std::map<const Surface*, std::shared_ptr<common::SerialFlann<pcl::PointXYZ>>> models;
  const common::SerialFlann<pcl::PointXYZ>& tree(const Surface& s) const {
    auto& t = models[&s];
    if (!t) {
      t = std::make_shared<common::SerialFlann<pcl::PointXYZ>>();
      t->setInputCloud(to_pcl(s.points));
    }
    return *t;
  }
};

Scorer::Scorer(const Candidate& c, const Params& p) : c_(c), p_(p), impl_(std::make_shared<Impl>()) {
  for (const auto& q : c.points) {
    if (q.z() >= p.min_height) above_.push_back(q);
  }
  // Distinct sensor directions (greedy clustering within 2 degrees).
  const double cos_tol = std::cos(2.0 * common::kPi / 180.0);
  for (const auto& s : c.sensor) {
    bool known = false;
    for (const auto& v : views_) {
      if (v.dot(s) >= cos_tol) {
        known = true;
        break;
      }
    }
    if (!known && views_.size() < 512) views_.push_back(s);
  }
  impl_->all.setInputCloud(to_pcl(c.points));
  // The candidate's spacing only when --seen-spacing reads it (a k-d tree and a search per point).
  seen_radius_ = p.seen_spacing > 0 ? std::max(p.inlier_radius, p.seen_spacing * sample_spacing(above_))
                                    : p.inlier_radius;
  for (const auto& s : views_) {
    Impl::View v;
    v.s = s;
    v.e1 = s.unitOrthogonal();
    v.e2 = s.cross(v.e1);
    for (const auto& q : c.points) {
      const auto key = cell_key(q.dot(v.e1), q.dot(v.e2), p.ray_cell);
      const double d = q.dot(s);
      auto it = v.depth.find(key);
      if (it == v.depth.end()) {
        v.depth.emplace(key, d);
      } else if (d > it->second) {
        it->second = d;
      }
    }
    impl_->views.push_back(std::move(v));
  }
}

Check Scorer::score(const Surface& model, const Isometry3d& pose) const {
  Check r;
  r.pose = pose;
  const auto& tree = impl_->tree(model);
  const Isometry3d inv = pose.inverse();
  std::vector<int> idx(1);
  std::vector<float> d2(1);
  double sum2 = 0;
  for (const auto& q : above_) {
    const Vector3d qm = inv * q;
    pcl::PointXYZ s(static_cast<float>(qm.x()), static_cast<float>(qm.y()), static_cast<float>(qm.z()));
    if (tree.nearestKSearch(s, 1, idx, d2) < 1) continue;
    if (d2[0] > p_.inlier_radius * p_.inlier_radius) continue;
    const double d = model.normals[idx[0]].dot(qm - model.points[idx[0]]);
    if (std::abs(d) > p_.inlier_distance) continue;
    ++r.inliers;
    sum2 += d * d;
  }
  r.explained = above_.empty() ? 0 : static_cast<double>(r.inliers) / above_.size();
  r.fit_rms = r.inliers ? std::sqrt(sum2 / r.inliers) : 0;

  int violations = 0;
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    const Vector3d m = pose * model.points[i];
    const Vector3d n = pose.linear() * model.normals[i];
    bool expected = false;
    for (const auto& v : impl_->views) {
      const double facing = n.dot(v.s);
      if (facing < p_.facing) continue;
      const auto it = v.depth.find(cell_key(m.dot(v.e1), m.dot(v.e2), p_.ray_cell));
      if (p_.free_space_through && it == v.depth.end()) continue;  // no ray evidence in this view
      const bool hidden = it != v.depth.end() && it->second > m.dot(v.s) + p_.occlusion_margin;
      if (!hidden) {
        expected = true;
        break;
      }
    }
    if (!expected) continue;
    ++r.expected;
    pcl::PointXYZ s(static_cast<float>(m.x()), static_cast<float>(m.y()), static_cast<float>(m.z()));
    bool seen = false;
    if (impl_->all.nearestKSearch(s, 1, idx, d2) >= 1 && d2[0] <= seen_radius_ * seen_radius_) {
      seen = std::abs(n.dot(c_.points[idx[0]] - m)) <= p_.inlier_distance;
    }
    if (!seen) ++violations;
  }
  r.violation = r.expected ? static_cast<double>(violations) / r.expected : 1.0;
  r.score = r.explained * (1 - r.violation);
  return r;
}

// ---- poses ------------------------------------------------------------------------------

Isometry3d refine(const Surface& model, const std::vector<Vector3d>& candidate, const Isometry3d& start,
                  const Params& p) {
  if (p.icp_iterations == 0 || candidate.size() < 6) return start;
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // ICP's warnings are expected here
  // At most icp_points source points, an even stride through the candidate (deterministic).
  std::vector<Vector3d> sub;
  const std::size_t stride =
      (candidate.size() + static_cast<std::size_t>(p.icp_points) - 1) / static_cast<std::size_t>(p.icp_points);
  for (std::size_t i = 0; i < candidate.size(); i += stride) sub.push_back(candidate[i]);
  std::vector<Vector3d> zeros(sub.size(), Vector3d::UnitZ());
  auto src = to_pcl(sub, zeros);
  auto tgt = to_pcl(model.points, model.normals);
  pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal, double> icp;
  icp.setTransformationEstimation(std::make_shared<SafePointToPlane>());
  // The target's correspondences through a k-d tree without an OpenMP region per search
  // (common/serial_kdtree.h; docs/decisions/cost.md §10): the same neighbours, a third of the CPU.
  icp.setSearchMethodTarget(std::make_shared<common::SerialKdTree<pcl::PointNormal>>());
  icp.setInputSource(src);
  icp.setInputTarget(tgt);
  icp.setMaximumIterations(p.icp_iterations);
  icp.setTransformationEpsilon(1e-10);
  icp.setEuclideanFitnessEpsilon(1e-10);
  Eigen::Matrix4d guess = start.inverse().matrix();  // candidate -> model
  pcl::PointCloud<pcl::PointNormal> out;
  for (double dist : {p.icp_coarse, p.icp_fine}) {
    icp.setMaxCorrespondenceDistance(dist);
    icp.align(out, guess);
    if (!icp.getFinalTransformation().allFinite()) break;
    guess = icp.getFinalTransformation();
  }
  Isometry3d cm(guess);
  // Re-orthonormalise (float round-off in PCL's estimation).
  Eigen::JacobiSVD<Matrix3d> svd(cm.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0) return start;
  cm.linear() = R;
  return cm.inverse();
}

namespace {

// The q-quantile (0..1) of v (copied; nearest rank).
double quantile(std::vector<double> v, double q) {
  const auto k = static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Samples of a rectangle: origin o, edges a and b, `spacing` apart (cell centres), normal n.
void sample_face(const Vector3d& o, const Vector3d& a, const Vector3d& b, const Vector3d& n, double spacing,
                 Surface* s) {
  const int na = std::max(1, static_cast<int>(std::ceil(a.norm() / spacing)));
  const int nb = std::max(1, static_cast<int>(std::ceil(b.norm() / spacing)));
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nb; ++j) {
      s->points.push_back(o + a * ((i + 0.5) / na) + b * ((j + 0.5) / nb));
      s->normals.push_back(n);
    }
  }
}

}  // namespace

bool null_box(const std::vector<Vector3d>& above, double spacing, Surface* box, Isometry3d* pose) {
  if (above.size() < 10) return false;
  const Vector3d c = mean_of(above);
  const double theta = major_axis_angle(above, c);
  const double ct = std::cos(theta), st = std::sin(theta);
  std::vector<double> u, w, z;
  for (const auto& p : above) {
    const double dx = p.x() - c.x(), dy = p.y() - c.y();
    u.push_back(ct * dx + st * dy);
    w.push_back(-st * dx + ct * dy);
    z.push_back(p.z());
  }
  const double u0 = quantile(u, 0.01), u1 = quantile(u, 0.99);
  const double w0 = quantile(w, 0.01), w1 = quantile(w, 0.99);
  const double top = quantile(z, 0.99);
  if (!(u1 - u0 > spacing && w1 - w0 > spacing && top > spacing)) return false;
  const double hl = (u1 - u0) / 2, hw = (w1 - w0) / 2;
  Surface s;
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  sample_face(Vector3d(-hl, -hw, top), 2 * hl * X, 2 * hw * Y, Z, spacing, &s);
  sample_face(Vector3d(-hl, -hw, 0), 2 * hl * X, top * Z, -Y, spacing, &s);
  sample_face(Vector3d(-hl, hw, 0), 2 * hl * X, top * Z, Y, spacing, &s);
  sample_face(Vector3d(-hl, -hw, 0), 2 * hw * Y, top * Z, -X, spacing, &s);
  sample_face(Vector3d(hl, -hw, 0), 2 * hw * Y, top * Z, X, spacing, &s);
  *box = std::move(s);
  // The box's centre in the candidate frame: the percentile midpoints along the axes.
  const double mu = (u0 + u1) / 2, mw = (w0 + w1) / 2;
  *pose = heading_pose(theta, Vector3d(c.x() + ct * mu - st * mw, c.y() + st * mu + ct * mw, 0));
  return true;
}

bool pose_from_pairs(const documents::SegmentGraph& object, const documents::SegmentGraph& model,
                     const std::vector<documents::SegmentPair>& pairs, Isometry3d* pose) {
  std::map<int, const documents::Segment*> os, ms;
  for (const auto& s : object.segments) os[s.segment_id] = &s;
  for (const auto& s : model.segments) ms[s.segment_id] = &s;
  std::vector<Vector3d> a, b;  // model, object centroids
  std::vector<double> w;
  for (const auto& pr : pairs) {
    if (pr.model_segment < 0) continue;
    auto io = os.find(pr.object_segment);
    auto im = ms.find(pr.model_segment);
    if (io == os.end() || im == ms.end()) continue;
    const auto& co = io->second->centroid;
    const auto& cm = im->second->centroid;
    a.emplace_back(cm[0], cm[1], cm[2]);
    b.emplace_back(co[0], co[1], co[2]);
    w.push_back(std::min(io->second->area, im->second->area));
  }
  if (a.size() < 2) return false;
  double W = 0;
  Vector3d ma = Vector3d::Zero(), mb = Vector3d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += w[i] * a[i];
    mb += w[i] * b[i];
    W += w[i];
  }
  if (!(W > 0)) return false;
  ma /= W;
  mb /= W;
  double sxx = 0, sxy = 0, syx = 0, syy = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vector3d pa = a[i] - ma, pb = b[i] - mb;
    sxx += w[i] * pa.x() * pb.x();
    sxy += w[i] * pa.x() * pb.y();
    syx += w[i] * pa.y() * pb.x();
    syy += w[i] * pa.y() * pb.y();
  }
  if (std::abs(sxx + syy) + std::abs(sxy - syx) < 1e-12) return false;
  const double theta = std::atan2(sxy - syx, sxx + syy);
  const Matrix3d R = Eigen::AngleAxisd(theta, Vector3d::UnitZ()).toRotationMatrix();
  Vector3d t = mb - R * ma;
  t.z() = 0;  // both frames stand on the ground
  *pose = heading_pose(theta, t);
  return true;
}

Isometry3d pose_from_axes(const std::vector<Vector3d>& candidate, const std::vector<Vector3d>& model) {
  const Vector3d mc = mean_of(candidate), mm = mean_of(model);
  const double theta = major_axis_angle(candidate, mc) - major_axis_angle(model, mm);
  const Matrix3d R = Eigen::AngleAxisd(theta, Vector3d::UnitZ()).toRotationMatrix();
  Vector3d t = mc - R * mm;
  t.z() = 0;
  return heading_pose(theta, t);
}

namespace {

double logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }

// Sample spacing of the null hypothesis's box (m): finer than the modelbase's ~128 mm samples,
// so that the box's free-space test is no coarser than a model's.
constexpr double kBoxSpacing = 0.1;

const Model& loaded_model(const Inputs& in, const std::string& name) {
  const Model* model = nullptr;
  for (const auto& m : *in.models) {
    if (m.name == name) model = &m;
  }
  if (model == nullptr) throw common::Error("verify: model " + name + " was not loaded");
  return *model;
}

// How far (radians) a pose's model vertical leans from the tile's vertical (to_tile: candidate ->
// tile; null: the candidate's frame is the reference).
double tilt(const Isometry3d& pose, const Isometry3d* to_tile) {
  const Matrix3d r = to_tile != nullptr ? Matrix3d(to_tile->linear() * pose.linear()) : Matrix3d(pose.linear());
  return std::acos(std::clamp(r(2, 2), -1.0, 1.0));
}

// One hypothesis: every start (the match result's pose when it gives one, else the matched
// pairs' pose when there is one; the principal axes') and, with Params::flip, its 180-degree
// flip, refined by ICP and scored; the best of the upright ones (Params::max_tilt). With no
// upright one, the best of all, marked tilted, with score 0.
documents::Hypothesis check_hypothesis(const Inputs& in, const documents::ModelScore& ms, const Model& model,
                                       const Scorer& scorer, const Params& p) {
  const auto& above = scorer.above_points();
  const Vector3d centre = mean_of(model.surface.points);
  struct Start {
    std::string name;
    Isometry3d pose;
  };
  std::vector<Start> starts;
  Isometry3d pp;
  if (ms.pose) {
    // The match result's own pose (baseline --hypotheses: the FPFH registration's) instead of
    // the pairs' (issue 29, "FPFH poses scored by verify").
    starts.push_back({"pose", formats::to_isometry(*ms.pose)});  // the reader checked it is rigid
  } else if (pose_from_pairs(*in.segments, model.graph, ms.pairs, &pp)) {
    starts.push_back({"pairs", pp});
  }
  starts.push_back({"axes", pose_from_axes(above.empty() ? in.candidate->points : above, model.surface.points)});
  documents::Hypothesis best;
  best.model = ms.model;
  best.gmatch_rank = ms.rank;
  best.gmatch_score = ms.score;
  bool have = false, upright = false;
  for (const auto& s : starts) {
    const int variants = p.flip ? 2 : 1;
    Check checks[2];
    for (int f = 0; f < variants; ++f) {
      const Isometry3d start = f ? flipped(s.pose, centre) : s.pose;
      checks[f] = scorer.score(model.surface, refine(model.surface, above, start, p));
    }
    for (int f = 0; f < variants; ++f) {
      const Check& c = checks[f];
      const bool up = tilt(c.pose, in.to_tile) <= p.max_tilt;
      // an upright pose before any tilted one, then the better score
      if (have && (upright && !up)) continue;
      if (have && up == upright && !(c.score > best.score)) continue;
      have = true;
      upright = up;
      best.start = s.name + (f ? "-flipped" : "");
      best.flipped = f == 1;
      best.pose = formats::to_pose(c.pose);
      best.fit_rms = c.fit_rms;
      best.explained = c.explained;
      best.free_space_violation = c.violation;
      best.score = c.score;
      best.flip_score = variants == 2 ? checks[1 - f].score : 0;
    }
  }
  if (have && !upright) {
    best.tilted = true;
    best.score = 0;
  }
  best.vehicle_class = model.vehicle_class;
  return best;
}

// Decides: the best score, its margin over the best other model, the class; the answer when
// the score passes Params::accept, else none.
void decide(documents::Verdict* verdict, const Params& p) {
  documents::Verdict& v = *verdict;
  // The best upright hypothesis: a tilted one (no upright start, Params::max_tilt) is neither the
  // answer, even where its score 0 passes an --accept of 0, nor the class and nearest instance.
  int chosen = -1;
  for (int i = 0; i < static_cast<int>(v.hypotheses.size()); ++i) {
    if (v.hypotheses[i].tilted) continue;
    if (chosen < 0 || v.hypotheses[i].score > v.hypotheses[chosen].score) chosen = i;
  }
  double second = 0;
  bool runner_up = false;  // another hypothesis was scored (stop 71, review F10)
  for (int i = 0; i < static_cast<int>(v.hypotheses.size()); ++i) {
    if (i == chosen) continue;
    second = std::max(second, v.hypotheses[i].score);
    runner_up = true;
  }
  if (v.has_classes && chosen >= 0) {
    const auto& h = v.hypotheses[chosen];
    v.vehicle_class = h.vehicle_class;
    v.nearest_instance = h.model;
    v.class_score = h.score;
    double other = 0;
    for (const auto& o : v.hypotheses) {
      if (o.vehicle_class != h.vehicle_class) other = std::max(other, o.score);
    }
    v.class_margin = h.score - other;
  }
  if (!v.hypotheses.empty()) {
    // (every hypothesis tilted: none, stated as for a best score of 0, the tilted ones' scores)
    const double s = chosen >= 0 ? v.hypotheses[chosen].score : 0;
    // The margin over the best other model. Without another hypothesis (a one-entry modelbase,
    // --top-k 1) no runner-up was scored, and the margin term, fitted on modelbases where one was
    // (verify.md §15-§19), must not count the whole score as a lead over nothing: a sedan was a
    // one-entry modelbase's pickup at 0.878 (review F10). It is 0 then, as for a tie: nothing
    // tells the answer from another model.
    const double margin = runner_up ? s - second : 0;
    const double over_box = v.box ? s - v.box->score : 0;
    const bool beats_box = !v.box || over_box >= p.box_margin;
    if (chosen >= 0 && s >= p.accept && beats_box) {
      v.chosen = chosen;
      v.model = v.hypotheses[chosen].model;
      v.confidence = logistic(p.conf_bias + p.conf_score * s + p.conf_margin * margin + p.conf_box * over_box);
    } else {
      v.confidence =
          1 - logistic(p.none_bias + p.none_score * s + p.none_margin * margin + p.none_box * over_box);
    }
  } else {
    v.confidence = 1;
  }
}

}  // namespace

Outputs run(const Params& p, const Inputs& in) {
  documents::Verdict v;
  const Scorer scorer(*in.candidate, p);
  const int k = std::min<int>(p.top_k, static_cast<int>(in.match->models.size()));
  for (int h = 0; h < k; ++h) {
    const auto& ms = in.match->models[h];
    const Model& model = loaded_model(in, ms.model);
    v.hypotheses.push_back(check_hypothesis(in, ms, model, scorer, p));
    v.has_classes = v.has_classes || !model.vehicle_class.empty();
  }
  if (p.box) {
    // The null hypothesis: a plain box of the candidate's extent, refined and scored like a
    // model (docs/decisions/verify.md §14).
    Surface box;
    Isometry3d start;
    documents::Verdict::Box b;
    if (null_box(scorer.above_points(), kBoxSpacing, &box, &start)) {
      const Check c = scorer.score(box, refine(box, scorer.above_points(), start, p));
      b.explained = c.explained;
      b.free_space_violation = c.violation;
      b.score = c.score;
    }
    v.box = b;
  }
  decide(&v, p);
  if (in.to_tile != nullptr) {
    v.transform = formats::to_pose(*in.to_tile);
    for (auto& h : v.hypotheses) h.pose_tile = formats::to_pose(*in.to_tile * to_isometry(h.pose));
  }
  return v;
}

}  // namespace canopy::verify
