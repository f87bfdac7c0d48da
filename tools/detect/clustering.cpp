#include "detect/clustering.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>
#include <utility>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

namespace canopy::detect {
namespace {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// The occupied voxels of edge v: their packed keys ascending, and the voxel of each entry of idx.
struct Voxels {
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> voxel_of;
};

Voxels occupied_voxels(const std::vector<std::uint32_t>& idx, const std::vector<double>& px,
                       const std::vector<double>& py, const std::vector<double>& pz, double v) {
  double xmin = 1e300, ymin = 1e300, zmin = 1e300, xmax = -1e300, ymax = -1e300, zmax = -1e300;
  for (std::uint32_t p : idx) {
    xmin = std::min(xmin, px[p]);
    ymin = std::min(ymin, py[p]);
    zmin = std::min(zmin, pz[p]);
    xmax = std::max(xmax, px[p]);
    ymax = std::max(ymax, py[p]);
    zmax = std::max(zmax, pz[p]);
  }
  constexpr std::uint64_t kMask = kVoxelMask;
  // Checked before converting: a huge quotient is no valid integer.
  const double extent = std::max({xmax - xmin, ymax - ymin, zmax - zmin});
  if (!(std::floor(extent / v) + 1 < double(kMask))) throw VoxelOverflow{extent};
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(idx.size());
  for (std::size_t n = 0; n < idx.size(); ++n) {
    const std::uint32_t p = idx[n];
    const auto i = std::uint64_t(std::floor((px[p] - xmin) / v)) + 1;
    const auto j = std::uint64_t(std::floor((py[p] - ymin) / v)) + 1;
    const auto k = std::uint64_t(std::floor((pz[p] - zmin) / v)) + 1;
    keyed[n] = {(i << 42) | (j << 21) | k, std::uint32_t(n)};
  }
  std::sort(keyed.begin(), keyed.end());
  Voxels out;
  out.voxel_of.resize(idx.size());
  for (const auto& [key, n] : keyed) {
    if (out.keys.empty() || out.keys.back() != key) out.keys.push_back(key);
    out.voxel_of[n] = std::uint32_t(out.keys.size() - 1);
  }
  return out;
}

// Unites 26-connected voxels by looking up each voxel's 13 forward neighbours.
void unite_grid_neighbours(const std::vector<std::uint64_t>& keys, UnionFind& uf) {
  constexpr std::uint64_t kMask = kVoxelMask;
  std::unordered_map<std::uint64_t, std::uint32_t> lookup;
  lookup.reserve(keys.size() * 2);
  for (std::size_t u = 0; u < keys.size(); ++u) lookup.emplace(keys[u], std::uint32_t(u));
  for (std::size_t u = 0; u < keys.size(); ++u) {
    const std::uint64_t i = keys[u] >> 42, j = (keys[u] >> 21) & kMask, k = keys[u] & kMask;
    // The 13 forward neighbours (the other 13 see this voxel as theirs).
    for (int di = 0; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          if (di == 0 && (dj < 0 || (dj == 0 && dk <= 0))) continue;
          const std::uint64_t key = ((i + di) << 42) | ((j + dj) << 21) | (k + dk);
          const auto it = lookup.find(key);
          if (it != lookup.end()) uf.unite(std::uint32_t(u), it->second);
        }
  }
}

// Unites the voxels PCL's Euclidean clustering puts together (voxel centres, tolerance 1.8 v).
void unite_euclidean_clusters(const std::vector<std::uint64_t>& keys, double v, UnionFind& uf) {
  constexpr std::uint64_t kMask = kVoxelMask;
  pcl::PointCloud<pcl::PointXYZ>::Ptr centres(new pcl::PointCloud<pcl::PointXYZ>);
  centres->resize(keys.size());
  for (std::size_t u = 0; u < keys.size(); ++u) {
    (*centres)[u] = pcl::PointXYZ(float(double(keys[u] >> 42) * v), float(double((keys[u] >> 21) & kMask) * v),
                                  float(double(keys[u] & kMask) * v));
  }
  // 1.8 v: between sqrt(3) v and 2 v, the 26-neighbourhood
  for (const auto& c : euclidean_clusters(centres, v * 1.8)) {
    for (std::size_t m = 1; m < c.indices.size(); ++m) {
      uf.unite(std::uint32_t(c.indices[0]), std::uint32_t(c.indices[m]));
    }
  }
}
}  // namespace

std::vector<pcl::PointIndices> euclidean_clusters(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                                  double tolerance) {
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(float(tolerance));
  ec.setMinClusterSize(1);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(tree);
  ec.setInputCloud(cloud);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);
  return found;
}

std::vector<std::vector<std::uint32_t>> cluster_points(const std::vector<std::uint32_t>& idx,
                                                       const std::vector<double>& px,
                                                       const std::vector<double>& py,
                                                       const std::vector<double>& pz, double v,
                                                       Clustering method) {
  std::vector<std::vector<std::uint32_t>> out;
  if (idx.empty()) return out;
  const Voxels vox = occupied_voxels(idx, px, py, pz, v);
  const std::vector<std::uint64_t>& keys = vox.keys;
  UnionFind uf(keys.size());
  if (method == Clustering::kGrid) {
    unite_grid_neighbours(keys, uf);
  } else {
    unite_euclidean_clusters(keys, v, uf);
  }
  // Root = smallest voxel index of the component (unite keeps the smaller), so ordering by
  // root orders clusters by their smallest voxel key.
  std::map<std::uint32_t, std::size_t> cluster_of_root;
  for (std::size_t u = 0; u < keys.size(); ++u) {
    const std::uint32_t r = uf.find(std::uint32_t(u));
    if (!cluster_of_root.count(r)) cluster_of_root.emplace(r, cluster_of_root.size());
  }
  out.resize(cluster_of_root.size());
  for (std::size_t n = 0; n < idx.size(); ++n) {
    out[cluster_of_root.at(uf.find(vox.voxel_of[n]))].push_back(idx[n]);
  }
  return out;
}

}  // namespace canopy::detect
