#include "detect/shape.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <unordered_map>
#include <utility>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/kdtree/kdtree_flann.h>

namespace canopy::detect {
namespace {

using Eigen::Vector3d;

// How much of an object's surface lies in locally planar neighbourhoods. Its points are
// averaged into `kPlanarVoxel` cubes (so the neighbour set is about as dense at 40 mm as at
// 80 mm pixel spacing, and bounded); for each centroid, its neighbours within `radius` (PCL's
// k-d tree) and the eigenvalues l1 >= l2 >= l3 of their covariance: the centroid is planar
// when sqrt(l3 / l2) <= `ratio` (a plane with noise sigma gives about sigma / (radius / 2); a
// line, a branch or a rail, has l2 ~ l3 and is not planar). Centroids with fewer than
// kPlanarMinNeighbours neighbours are not counted. share = planar / counted centroids (0 for
// an object too small to tell); area = planar centroids x kPlanarVoxel^2 (m^2, about the
// planar surface seen: a vehicle under a bush keeps its panels' area while the bush's points
// lower its share).
constexpr double kPlanarVoxel = 0.1;
constexpr int kPlanarMinNeighbours = 8;

}  // namespace

Shape planar_shape(const LocalFrame& l, const std::vector<std::uint32_t>& pts, double radius, double ratio) {
  std::unordered_map<std::uint64_t, std::uint32_t> slot;
  std::vector<Vector3d> sum;
  std::vector<std::uint32_t> cnt;
  slot.reserve(pts.size());
  for (std::uint32_t q : pts) {
    const auto i = std::uint64_t(std::int64_t(std::floor(l.x[q] / kPlanarVoxel)) + (1 << 20));
    const auto j = std::uint64_t(std::int64_t(std::floor(l.y[q] / kPlanarVoxel)) + (1 << 20));
    const auto k = std::uint64_t(std::int64_t(std::floor(l.z[q] / kPlanarVoxel)) + (1 << 20));
    const auto [it, fresh] = slot.emplace((i << 42) | (j << 21) | k, std::uint32_t(sum.size()));
    if (fresh) {
      sum.emplace_back(Vector3d::Zero());
      cnt.push_back(0);
    }
    sum[it->second] += Vector3d(l.x[q], l.y[q], l.z[q]);
    ++cnt[it->second];
  }
  if (sum.size() < std::size_t(kPlanarMinNeighbours)) return {};
  // Centroids relative to the first one (float32 for PCL; slots in first-seen order: deterministic).
  const Vector3d ref = sum[0] / double(cnt[0]);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(sum.size());
  for (std::size_t u = 0; u < sum.size(); ++u) {
    const Vector3d m = sum[u] / double(cnt[u]) - ref;
    (*cloud)[u] = pcl::PointXYZ(float(m.x()), float(m.y()), float(m.z()));
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  std::size_t planar = 0, counted = 0;
  pcl::Indices nb;
  std::vector<float> d2;
  for (std::size_t u = 0; u < cloud->size(); ++u) {
    if (tree.radiusSearch((*cloud)[u], radius, nb, d2) < kPlanarMinNeighbours) continue;
    Vector3d mean = Vector3d::Zero();
    for (const auto k : nb) mean += (*cloud)[std::size_t(k)].getVector3fMap().cast<double>();
    mean /= double(nb.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto k : nb) {
      const Vector3d d = (*cloud)[std::size_t(k)].getVector3fMap().cast<double>() - mean;
      cov += d * d.transpose();
    }
    const Vector3d l =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
    ++counted;
    planar += l[0] <= ratio * ratio * l[1];  // ascending: l[0] is the smallest
  }
  Shape out;
  out.share = counted ? double(planar) / double(counted) : 0.0;
  out.area = double(planar) * kPlanarVoxel * kPlanarVoxel;
  return out;
}

ShapeTest shape_test(std::vector<Object> objects, const LocalFrame& l, const Params& params) {
  ShapeTest out;
  for (Object& o : objects) {
    o.shape = planar_shape(l, o.points, params.planar_radius, params.planar_ratio);
    if (params.min_planarity > 0 && o.shape.share < params.min_planarity &&
        o.shape.area < params.min_planar_area) {
      ++out.rejected;
    } else {
      out.kept.push_back(std::move(o));
    }
  }
  return out;
}

}  // namespace canopy::detect
