// Times fitvox::run (single thread) against PCL's VoxelGrid + NormalEstimation on the same
// points, in the same process. Input: a scan PCD, or the synthetic vehicle scene (synth_scan.h)
// (sigma 8 mm), either subsampled to --points N (default 250000; 0 = all points).
//
//   fitvox_bench [--points N] [--repeat R] [scan.pcd]
#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "canopy/common/rng.h"
#include "canopy/formats/pcd.h"
#include "fitvox/fitvox.h"
#include "synth_scan.h"

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The scan PCD, or the synthetic vehicle scene (sigma 8 mm) when no file is given.
canopy::fitvox::Scan load_scan(const std::string& file) {
  if (!file.empty()) return canopy::fitvox::scan_from_cloud(canopy::formats::read_pcd(file), file, nullptr);
  fitvox_bench::SceneOptions o;
  o.sigma = 0.008;
  return fitvox_bench::synth_scan(o);
}

// Deterministic subsample (partial Fisher-Yates) to `want` points (0 = all), input order kept.
canopy::fitvox::Scan subsample(const canopy::fitvox::Scan& full, std::size_t want) {
  canopy::common::Rng rng(7);
  std::vector<std::size_t> idx(full.points.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  const std::size_t n = want == 0 ? idx.size() : std::min(want, idx.size());
  for (std::size_t i = 0; i < n; ++i) std::swap(idx[i], idx[i + rng.below(idx.size() - i)]);
  idx.resize(n);
  std::sort(idx.begin(), idx.end());
  canopy::fitvox::Scan scan;
  for (std::size_t i : idx) {
    scan.points.push_back(full.points[i]);
    if (!full.sensor.empty()) scan.sensor.push_back(full.sensor[i]);
    if (!full.labels.empty()) scan.labels.push_back(full.labels[i]);
  }
  return scan;
}

// Median seconds of fitvox::run (one thread) over `repeat` runs; its voxel and kept counts.
double time_fitvox(const canopy::fitvox::Scan& scan, int repeat, std::size_t& voxels, std::size_t& kept) {
  canopy::fitvox::Params p;
  p.threads = 1;
  std::vector<double> tf;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = now();
    const auto res = canopy::fitvox::run(p, scan);
    tf.push_back(now() - t0);
    kept = res.stats.kept;
    voxels = res.stats.voxels;
  }
  return median(tf);
}

// Median seconds of PCL's VoxelGrid (128 mm) and NormalEstimation (radius 64 mm, on the full cloud).
struct PclTimes {
  double voxel_grid = 0, normals = 0;
  std::size_t centroids = 0;
};

PclTimes time_pcl(const canopy::fitvox::Scan& scan, int repeat) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& q : scan.points) {
    cloud->push_back(
        pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())));
  }
  std::vector<double> tv, tn;
  PclTimes out;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = now();
    pcl::PointCloud<pcl::PointXYZ>::Ptr down(new pcl::PointCloud<pcl::PointXYZ>);
    pcl::VoxelGrid<pcl::PointXYZ> vg;
    vg.setInputCloud(cloud);
    vg.setLeafSize(0.128f, 0.128f, 0.128f);
    vg.filter(*down);
    const double t1 = now();
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setInputCloud(down);
    ne.setSearchSurface(cloud);
    ne.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
    ne.setRadiusSearch(0.064);
    pcl::PointCloud<pcl::Normal> normals;
    ne.compute(normals);
    const double t2 = now();
    tv.push_back(t1 - t0);
    tn.push_back(t2 - t1);
    out.centroids = down->size();
  }
  out.voxel_grid = median(tv);
  out.normals = median(tn);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t want = 250000;
  int repeat = 5;
  std::string file;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--points") == 0 && i + 1 < argc) {
      want = std::stoul(argv[++i]);
    } else if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      repeat = std::stoi(argv[++i]);
    } else {
      file = argv[i];
    }
  }
  const canopy::fitvox::Scan full = load_scan(file);
  const canopy::fitvox::Scan scan = subsample(full, want);
  std::size_t kept = 0, voxels = 0;
  const double f = time_fitvox(scan, repeat, voxels, kept);
  const PclTimes pcl_t = time_pcl(scan, repeat);
  const double v = pcl_t.voxel_grid, nrm = pcl_t.normals;
  std::printf("points %zu of %zu (%s)\n", scan.points.size(), full.points.size(),
              file.empty() ? "synthetic tank scene, sigma 8 mm" : file.c_str());
  std::printf("fitvox::run            %.4f s  (%zu voxels, %zu kept; median of %d)\n", f, voxels, kept, repeat);
  std::printf("PCL VoxelGrid          %.4f s  (%zu centroids)\n", v, pcl_t.centroids);
  std::printf("PCL NormalEstimation   %.4f s  (radius 64 mm on the full cloud, incl. k-d tree)\n", nrm);
  std::printf("PCL pair / fitvox      %.2fx\n", (v + nrm) / f);
  return 0;
}
