#include "canopy/formats/cloud_eigen.h"

#include <cmath>
#include <cstdio>

#include "canopy/common/error.h"

namespace canopy::formats {

bool has_fields(const PointCloud& cloud, const Fields3& fields) {
  return cloud.has(fields[0]) && cloud.has(fields[1]) && cloud.has(fields[2]);
}

std::vector<Eigen::Vector3d> to_vectors(const PointCloud& cloud, const Fields3& fields) {
  const auto& x = cloud.col(fields[0]);
  const auto& y = cloud.col(fields[1]);
  const auto& z = cloud.col(fields[2]);
  std::vector<Eigen::Vector3d> v(cloud.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Eigen::Vector3d(x[i], y[i], z[i]);
  return v;
}

std::vector<Eigen::Vector3d> finite_vectors(const PointCloud& cloud, const std::string& file,
                                            const Fields3& fields, const std::string& row,
                                            const std::string& what) {
  std::vector<Eigen::Vector3d> v = to_vectors(cloud, fields);
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].allFinite()) {
      throw common::DataError(file, row + " " + std::to_string(i) + " has a non-finite " + what);
    }
  }
  return v;
}

void set_vectors(PointCloud* cloud, const std::vector<Eigen::Vector3d>& vectors, const Fields3& fields,
                 FieldType type) {
  for (int k = 0; k < 3; ++k) {
    std::vector<double>& c = cloud->has(fields[k]) ? cloud->col(fields[k]) : cloud->add(fields[k], type);
    for (std::size_t i = 0; i < vectors.size(); ++i) c[i] = vectors[i](k);
  }
}

std::vector<std::uint32_t> uint32_column(const PointCloud& cloud, const std::string& field,
                                         const std::string& file, const std::string& row) {
  const auto& c = cloud.col(field);
  std::vector<std::uint32_t> out(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!(c[i] >= 0 && c[i] <= 4294967295.0 && c[i] == std::floor(c[i]))) {
      char value[32];
      std::snprintf(value, sizeof value, "%.17g", c[i]);
      throw common::DataError(file, row + " " + std::to_string(i) + " has " + field + " " + value +
                                        " (want a non-negative integer below 2^32)");
    }
    out[i] = static_cast<std::uint32_t>(c[i]);
  }
  return out;
}

}  // namespace canopy::formats
