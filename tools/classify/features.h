// classify's measurements (classify.h steps 1-4): the candidate's points, its object, the
// object's rectangle, size and shape cues. Exposed for the tests.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "classify/classify.h"

namespace canopy::classify {

// The fields classify reads: x y z, and return numbers when present (else empty vectors).
struct Candidate {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> return_number, number_of_returns;  // 0 = unknown
};

// Errors name the file: x y z missing, a non-finite coordinate.
Candidate read_candidate(const formats::PointCloud& cloud, const std::string& name);

// Indices of the object's points: the above-ground points (z >= ground_cut) clustered at
// distance `link`; the largest cluster whose top-view box (padded by `link`) holds the origin,
// else the largest.
std::vector<std::size_t> object_of(const Candidate& c, double ground_cut, double link);

// Every measurement of Features (classify.h).
Features measure(const Candidate& c, const Params& params);

}  // namespace canopy::classify
