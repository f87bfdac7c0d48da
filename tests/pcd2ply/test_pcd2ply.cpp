// pcd2ply's stage: the cloud's rows, fields and comments become the PLY point set's vertices,
// the provenance lines follow the cloud's own comments; written and read back, nothing is lost.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "canopy/formats/ply.h"
#include "pcd2ply/pcd2ply.h"

namespace fm = canopy::formats;

TEST_CASE("pcd2ply::run keeps every row, field and comment and appends the provenance") {
  fm::PointCloud c;
  c.add("x", fm::kFloat32);
  c.add("y", fm::kFloat32);
  c.add("z", fm::kFloat32);
  c.add("label", fm::kUint32);
  c.resize(3);
  for (std::size_t i = 0; i < 3; ++i) {
    c.col("x")[i] = 1.5 * i;
    c.col("y")[i] = -2.0 * i;
    c.col("z")[i] = 0.25;
    c.col("label")[i] = static_cast<double>(i % 2);
  }
  c.comments = {"rangetrace (canopy) 0.1.0"};
  const fm::Mesh m = canopy::pcd2ply::run({}, {c, {"pcd2ply", "9.9", {{"ascii", "true"}}, {"in.pcd"}}});
  REQUIRE(m.vertices.size() == 3);
  CHECK(m.faces.empty());
  CHECK(m.vertices.names() == c.names());
  CHECK(m.vertices.col("x")[2] == 3.0);
  CHECK(m.vertices.col("label")[1] == 1.0);
  REQUIRE(m.vertices.comments.size() == 4);
  CHECK(m.vertices.comments[0] == "rangetrace (canopy) 0.1.0");
  CHECK(m.vertices.comments[1] == "pcd2ply (canopy) 9.9");
  CHECK(m.vertices.comments[2] == "parameter ascii = true");
  CHECK(m.vertices.comments[3] == "input in.pcd");

  const std::string dir = std::string(CANOPY_TEST_TMP) + "/pcd2ply";
  std::filesystem::create_directories(dir);
  for (bool ascii : {false, true}) {
    const std::string path = dir + (ascii ? "/a.ply" : "/b.ply");
    fm::write_ply(m, path, ascii);
    const fm::Mesh back = fm::read_ply(path);
    CHECK(back.vertices.size() == 3);
    CHECK(back.vertices.col("y")[2] == -4.0);
    CHECK(back.vertices.col("label")[0] == 0.0);
    CHECK(back.vertices.comments == m.vertices.comments);
  }
}
