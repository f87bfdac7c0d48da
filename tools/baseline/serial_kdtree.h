// k-d trees for the baseline's PCL classes without an OpenMP region per search (issue 31;
// docs/decisions/baseline.md §6). Include only from files compiled without -fopenmp (the
// point of it: FLANN's per-search `#pragma omp parallel` is inert there).
#pragma once

#include <pcl/kdtree/impl/kdtree_flann.hpp>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/registration/sample_consensus_prerejective.h>
#include <pcl/search/kdtree.h>
#include <memory>
#include <vector>

namespace canopy::baseline {

using PointN = pcl::PointNormal;

// k-d trees without an OpenMP region per query (docs/decisions/baseline.md §6). FLANN opens
// `#pragma omp parallel num_threads(cores)` around every search, even for one query and one
// core, and PCL's precompiled k-d tree (libpcl_kdtree) is built with OpenMP: each of the
// millions of single-point searches of RANSAC's fitness, ICP's correspondences, the normals and
// FPFH paid a thread team's set-up and a futex syscall (a quarter of the baseline's CPU). The
// same PCL and FLANN code, instantiated where this is included (without -fopenmp, so the
// pragma is inert) through a distance type of its own (so that it is not the library's
// instantiation): the same index, the same searches, the same neighbours in the same order.
struct L2Serial : ::flann::L2_Simple<float> {};
template <typename PointT>
using SerialFlann = pcl::KdTreeFLANN<PointT, L2Serial>;

// pcl::search::KdTree (what PCL's features and registration take) answering its searches with
// SerialFlann. The base class's tree is still built (callers may read the cloud through it);
// every search the baseline's PCL classes make goes through the two overrides.
class SerialKdTree : public pcl::search::KdTree<PointN> {
 public:
  using Ptr = std::shared_ptr<SerialKdTree>;
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    pcl::search::KdTree<PointN>::setInputCloud(cloud, indices);
    serial_.setSortedResults(sorted_results_);
    serial_.setInputCloud(cloud, indices);
  }
  void setSortedResults(bool sorted) override {
    pcl::search::KdTree<PointN>::setSortedResults(sorted);
    serial_.setSortedResults(sorted);
  }
  int nearestKSearch(const PointN& point, int k, pcl::Indices& indices,
                     std::vector<float>& sqr_distances) const override {
    return serial_.nearestKSearch(point, k, indices, sqr_distances);
  }
  int radiusSearch(const PointN& point, double radius, pcl::Indices& indices,
                   std::vector<float>& sqr_distances, unsigned int max_nn = 0) const override {
    return serial_.radiusSearch(point, radius, indices, sqr_distances, max_nn);
  }
  using pcl::search::KdTree<PointN>::nearestKSearch;
  using pcl::search::KdTree<PointN>::radiusSearch;

 private:
  SerialFlann<PointN> serial_;
};

// The feature tree of RANSAC's correspondence search, likewise.
class SerialFeatureTree : public pcl::KdTreeFLANN<pcl::FPFHSignature33> {
 public:
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    pcl::KdTreeFLANN<pcl::FPFHSignature33>::setInputCloud(cloud, indices);
    serial_.setInputCloud(cloud, indices);
  }
  int nearestKSearch(const pcl::FPFHSignature33& point, unsigned int k, pcl::Indices& indices,
                     std::vector<float>& sqr_distances) const override {
    return serial_.nearestKSearch(point, k, indices, sqr_distances);
  }
  using pcl::KdTreeFLANN<pcl::FPFHSignature33>::nearestKSearch;

 private:
  SerialFlann<pcl::FPFHSignature33> serial_;
};

// SampleConsensusPrerejective with the serial feature tree (its tree is a protected member).
class Prerejective : public pcl::SampleConsensusPrerejective<PointN, PointN, pcl::FPFHSignature33> {
 public:
  Prerejective() { feature_tree_.reset(new SerialFeatureTree); }
};

}  // namespace canopy::baseline
