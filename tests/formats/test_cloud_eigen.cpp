// formats/cloud_eigen.h and pose_eigen.h: the one PointCloud <-> Eigen and Pose <-> Eigen
// conversions of the stages.
#include <catch2/catch.hpp>

#include <array>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/pose_eigen.h"

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

TEST_CASE("to_pose writes the rotation row-major and the translation; to_isometry reads them back") {
  // 90 degrees about z, then (1, 2, 3): x -> y, y -> -x.
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  t.translation() = Vector3d(1, 2, 3);
  const formats::Pose p = formats::to_pose(t);
  CHECK(p.rotation == std::array<double, 9>{0, -1, 0, 1, 0, 0, 0, 0, 1});
  CHECK(p.translation == std::array<double, 3>{1, 2, 3});
  CHECK(formats::euler_degrees(p)[0] == Approx(90));
  CHECK(formats::to_isometry(p).matrix() == t.matrix());
  // A 4 x 4 matrix: only its rigid part is read.
  Eigen::Matrix4d m = t.matrix();
  m(3, 0) = 5;
  CHECK(formats::to_pose(m).rotation == p.rotation);
  CHECK(formats::to_pose(m).translation == p.translation);
  CHECK(formats::to_pose(Eigen::Isometry3d::Identity()).rotation == formats::Pose{}.rotation);
}
