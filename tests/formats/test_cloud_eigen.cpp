// formats/cloud_eigen.h: the one PointCloud <-> Eigen conversion of the stages.
#include <catch2/catch.hpp>

#include <limits>

#include "canopy/common/error.h"
#include "canopy/formats/cloud_eigen.h"

using namespace canopy;
using Eigen::Vector3d;

namespace {

formats::PointCloud two_points() {
  formats::PointCloud c;
  c.resize(2);
  c.add("x") = {1, 4};
  c.add("y") = {2, 5};
  c.add("z") = {3, 6};
  c.add("normal_x") = {0, 1};
  c.add("normal_y") = {0, 0};
  c.add("normal_z") = {1, 0};
  c.add("label", formats::kUint32) = {1, 3};
  return c;
}

}  // namespace

TEST_CASE("to_vectors reads rows of three columns; set_vectors writes them back") {
  formats::PointCloud c = two_points();
  const auto p = formats::to_vectors(c);
  REQUIRE(p.size() == 2);
  CHECK(p[1] == Vector3d(4, 5, 6));
  CHECK(formats::to_vectors(c, formats::kNormalFields)[1] == Vector3d(1, 0, 0));
  CHECK(formats::has_fields(c, formats::kNormalFields));
  CHECK_FALSE(formats::has_fields(c, formats::kSensorFields));
  formats::set_vectors(&c, {Vector3d(0, 0, 1), Vector3d(0, 1, 0)}, formats::kSensorFields);
  CHECK(c.type("sensor_y") == formats::kFloat32);
  CHECK(formats::to_vectors(c, formats::kSensorFields)[1] == Vector3d(0, 1, 0));
  formats::set_vectors(&c, {Vector3d(7, 8, 9), Vector3d(1, 1, 1)}, formats::kXyzFields);
  CHECK(c.col("z")[0] == 9);
}

TEST_CASE("finite_vectors and uint32_column name the file, the row and the problem") {
  formats::PointCloud c = two_points();
  c.col("normal_y")[1] = std::numeric_limits<double>::quiet_NaN();
  CHECK(formats::finite_vectors(c, "m.ply").size() == 2);
  CHECK_THROWS_WITH(formats::finite_vectors(c, "m.ply", formats::kNormalFields, "vertex", "normal"),
                    "m.ply: vertex 1 has a non-finite normal");
  CHECK(formats::uint32_column(c, "label", "s.pcd") == std::vector<std::uint32_t>{1, 3});
  c.col("label")[1] = 2.5;
  CHECK_THROWS_WITH(formats::uint32_column(c, "label", "s.pcd"),
                    "s.pcd: point 1 has label 2.5 (want a non-negative integer below 2^32)");
  c.col("label")[1] = -1;
  CHECK_THROWS_AS(formats::uint32_column(c, "label", "s.pcd"), common::DataError);
  c.col("label")[1] = 4294967296.0;
  CHECK_THROWS_AS(formats::uint32_column(c, "label", "s.pcd"), common::DataError);
}
