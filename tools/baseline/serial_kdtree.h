// k-d trees for the baseline's PCL classes without an OpenMP region per search (issue 31;
// docs/decisions/baseline.md §6). Include only from files compiled without -fopenmp (the
// point of it: FLANN's per-search `#pragma omp parallel` is inert there).
#pragma once

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/registration/sample_consensus_prerejective.h>
#include <pcl/search/kdtree.h>
#include <memory>
#include <vector>

#include "canopy/common/serial_kdtree.h"

namespace canopy::baseline {

using PointN = pcl::PointNormal;

// The serial trees (common/serial_kdtree.h) for the baseline's point type.
using common::L2Serial;
template <typename PointT>
using SerialFlann = common::SerialFlann<PointT>;
using SerialKdTree = common::SerialKdTree<PointN>;

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
