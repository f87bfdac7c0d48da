// k-d trees for PCL without an OpenMP region per search (issue 31; docs/decisions/baseline.md
// §6, cost.md §9). Header-only and over PCL: include it only from targets that link PCL (the
// baseline, verify), and only from files compiled without -fopenmp (the point of it: FLANN's
// per-search `#pragma omp parallel` is inert there).
#pragma once

#include <pcl/kdtree/impl/kdtree_flann.hpp>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/search/kdtree.h>
#include <memory>
#include <vector>

namespace canopy::common {

// FLANN opens `#pragma omp parallel num_threads(cores)` around every search, even for one query
// and one core, and PCL's precompiled k-d tree (libpcl_kdtree) is built with OpenMP: each of the
// millions of single-point searches of a registration or a scoring loop paid a thread team's
// set-up and a futex syscall. The same PCL and FLANN code, instantiated where this is included
// (without -fopenmp, so the pragma is inert) through a distance type of its own (so that it is
// not the library's instantiation): the same index, the same searches, the same neighbours in
// the same order (tests/baseline/test_serial_kdtree.cpp).
struct L2Serial : ::flann::L2_Simple<float> {};
template <typename PointT>
using SerialFlann = pcl::KdTreeFLANN<PointT, L2Serial>;

// pcl::search::KdTree (what PCL's features and registration take) answering its searches with
// SerialFlann. The base class's tree is still built (callers may read the cloud through it);
// every k-nearest and radius search goes through the two overrides.
template <typename PointT>
class SerialKdTree : public pcl::search::KdTree<PointT> {
  using Base = pcl::search::KdTree<PointT>;

 public:
  using Ptr = std::shared_ptr<SerialKdTree<PointT>>;
  void setInputCloud(const typename Base::PointCloudConstPtr& cloud,
                     const typename Base::IndicesConstPtr& indices = typename Base::IndicesConstPtr()) override {
    Base::setInputCloud(cloud, indices);
    serial_.setSortedResults(this->sorted_results_);
    serial_.setInputCloud(cloud, indices);
  }
  void setSortedResults(bool sorted) override {
    Base::setSortedResults(sorted);
    serial_.setSortedResults(sorted);
  }
  int nearestKSearch(const PointT& point, int k, pcl::Indices& indices,
                     std::vector<float>& sqr_distances) const override {
    return serial_.nearestKSearch(point, k, indices, sqr_distances);
  }
  int radiusSearch(const PointT& point, double radius, pcl::Indices& indices,
                   std::vector<float>& sqr_distances, unsigned int max_nn = 0) const override {
    return serial_.radiusSearch(point, radius, indices, sqr_distances, max_nn);
  }
  using Base::nearestKSearch;
  using Base::radiusSearch;

 private:
  SerialFlann<PointT> serial_;
};

}  // namespace canopy::common
