// Clustering (step 3 of detect.h): occupied voxels, 26-connected (union-find over the voxel
// keys), or PCL's Euclidean clustering on the voxel centres (the same partition).
#pragma once

#include <cstdint>
#include <vector>

#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "detect/detect.h"

namespace canopy::detect {

// A voxel key packs three 21-bit indices.
constexpr std::uint64_t kVoxelMask = (1u << 21) - 1;

// Thrown when the points span more voxels along an axis than a key holds (kVoxelMask - 1).
struct VoxelOverflow {
  double extent = 0;  // the largest extent along an axis (m)
};

// Clusters the points `idx` (coordinates in px, py, pz) with voxel edge `v`. Returns the
// clusters as lists of entries of idx, ordered by their smallest voxel key, points in idx order.
std::vector<std::vector<std::uint32_t>> cluster_points(const std::vector<std::uint32_t>& idx,
                                                       const std::vector<double>& px,
                                                       const std::vector<double>& py,
                                                       const std::vector<double>& pz, double v,
                                                       Clustering method);

// PCL's Euclidean clustering of `cloud` at `tolerance` (m), every cluster kept (sizes 1 and up),
// by a k-d tree: the clusters' point indices as PCL returns them.
std::vector<pcl::PointIndices> euclidean_clusters(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                                  double tolerance);

}  // namespace canopy::detect
