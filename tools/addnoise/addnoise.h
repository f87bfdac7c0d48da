// addnoise: isotropic Gaussian noise on the point coordinates of a scan (thesis ch. 2:
// sigma in {0, 2, 4, 8, 16, 32} mm). Only x, y, z change; every other field and the row order
// are kept. The noise is drawn from Rng(derive_seed(seed, "addnoise")), three normals per point
// in row order, so the same scan, sigma and seed give the same output on every platform.
#pragma once

#include <cstdint>

#include "canopy/formats/point_cloud.h"

namespace canopy::addnoise {

struct Params {
  double sigma = 0.0;  // standard deviation per axis (m), >= 0; 0 = exact copy
  std::uint64_t seed = 1;
};

// Throws common::UsageError naming --sigma when sigma is outside [0, 100 m].
void validate(const Params& params);

struct Inputs {
  const formats::PointCloud* scan = nullptr;  // the scan (borrowed)
};

using Outputs = formats::PointCloud;  // the noisy copy of the scan

// Requires fields x, y, z (throws std::out_of_range naming the field otherwise).
Outputs run(const Params& params, const Inputs& inputs);
// run() on the scan itself, without the copy (the tool: a tile's scan is millions of points).
void apply(const Params& params, formats::PointCloud* scan);

}  // namespace canopy::addnoise
