#include "detect/frame.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/csv_table.h"

namespace canopy::detect {
namespace {

using common::DataError;
using Eigen::Vector3d;
using formats::format_number;

constexpr double kFloat32ExactLimit = 131072.0;  // 2^17: float32 steps reach 15.6 mm beyond

// DataError when a float32 coordinate column reaches magnitudes where float32 is not exact.
void check_float32_exact(const formats::PointCloud& tile, const LocalFrame& l, const std::string& name) {
  for (const char* axis : {"x", "y", "z"}) {
    const int a = axis[0] - 'x';
    const double mag = std::max(std::abs(l.lo[a]), std::abs(l.hi[a]));
    if (tile.type(axis) == formats::kFloat32 && mag >= kFloat32ExactLimit) {
      throw DataError(
          name, std::string("coordinate ") + axis + " is stored as float32 at magnitudes up to " +
                    format_number("%.0f", mag) + " m, where float32 steps are " +
                    format_number("%.3g", std::ldexp(1.0, int(std::floor(std::log2(mag))) - 23)) +
                    " m: the tile is already quantised; store coordinates as float64 (PCD TYPE F SIZE 8)");
    }
  }
}

}  // namespace

LocalFrame local_frame(const formats::PointCloud& tile, const std::string& name) {
  LocalFrame l;
  for (const Vector3d& q : formats::finite_vectors(tile, name)) {
    l.lo = l.lo.cwiseMin(q);
    l.hi = l.hi.cwiseMax(q);
  }
  check_float32_exact(tile, l, name);
  l.origin = Vector3d(std::floor(0.5 * (l.lo.x() + l.hi.x())), std::floor(0.5 * (l.lo.y() + l.hi.y())),
                      std::floor(l.lo.z()));
  const std::size_t n = tile.size();
  const auto& tx = tile.col("x");
  const auto& ty = tile.col("y");
  const auto& tz = tile.col("z");
  l.x.resize(n);
  l.y.resize(n);
  l.z.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    l.x[i] = tx[i] - l.origin.x();
    l.y[i] = ty[i] - l.origin.y();
    l.z[i] = tz[i] - l.origin.z();
  }
  return l;
}

}  // namespace canopy::detect
