// PointCloud columns <-> Eigen vectors: the one conversion every stage uses to read points,
// normals and sensor directions, and ground-truth labels, from a cloud or mesh.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

using Fields3 = std::array<std::string, 3>;

inline const Fields3 kXyzFields{"x", "y", "z"};
inline const Fields3 kNormalFields{"normal_x", "normal_y", "normal_z"};
inline const Fields3 kSensorFields{"sensor_x", "sensor_y", "sensor_z"};

// True when the cloud has all three fields.
bool has_fields(const PointCloud& cloud, const Fields3& fields);

// Row i of the three columns as a vector (the columns must exist).
std::vector<Eigen::Vector3d> to_vectors(const PointCloud& cloud, const Fields3& fields = kXyzFields);

// to_vectors() that refuses non-finite rows: DataError(file, "<row> <i> has a non-finite <what>"),
// e.g. "point 7 has a non-finite coordinate", "vertex 3 has a non-finite normal".
std::vector<Eigen::Vector3d> finite_vectors(const PointCloud& cloud, const std::string& file,
                                            const Fields3& fields = kXyzFields,
                                            const std::string& row = "point",
                                            const std::string& what = "coordinate");

// Writes the vectors into three columns (added with `type` when missing; the cloud must have
// vectors.size() rows).
void set_vectors(PointCloud* cloud, const std::vector<Eigen::Vector3d>& vectors, const Fields3& fields,
                 FieldType type = kFloat32);

// A column of non-negative integers below 2^32 (labels, counts): DataError(file,
// "<row> <i> has <field> <value> (want a non-negative integer below 2^32)") otherwise.
std::vector<std::uint32_t> uint32_column(const PointCloud& cloud, const std::string& field,
                                         const std::string& file, const std::string& row = "point");

}  // namespace canopy::formats
