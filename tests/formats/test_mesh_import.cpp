// formats/mesh_import.h (OBJ, STL, PLY triangle meshes) and formats/ppm.h (POV-Ray's frames).
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/mesh_import.h"
#include "canopy/formats/ppm.h"

using namespace canopy;

TEST_CASE("parse_ppm reads 16-bit P6 with comments, widens 8-bit samples") {
  std::string ppm = "P6\n# Software: test\n2 1\n65535\n";
  const unsigned char data[] = {0x12, 0x34, 0, 1, 0xff, 0xff, 0, 0, 0x80, 0, 0, 2};
  ppm.append(reinterpret_cast<const char*>(data), sizeof data);
  const formats::Image16 img = formats::parse_ppm(ppm, "t.ppm");
  CHECK(img.width == 2);
  CHECK(img.height == 1);
  REQUIRE(img.rgb.size() == 6);
  CHECK(img.rgb[0] == 0x1234);
  CHECK(img.rgb[1] == 0x0001);
  CHECK(img.rgb[2] == 0xffff);
  CHECK(img.rgb[4] == 0x8000);
  CHECK(img.rgb[5] == 0x0002);
  const formats::Image16 eight = formats::parse_ppm(std::string("P6 1 1 255\n") + "\x01\x80\xff", "8.ppm");
  CHECK(eight.rgb == std::vector<std::uint16_t>{257, 0x80 * 257, 0xffff});
  CHECK_THROWS_WITH(formats::parse_ppm(ppm.substr(0, ppm.size() - 1), "t.ppm"),
                    Catch::Contains("t.ppm") && Catch::Contains("truncated"));
  CHECK_THROWS_AS(formats::parse_ppm("P3\n1 1\n255\n0 0 0\n", "t.ppm"), common::DataError);
  CHECK_THROWS_AS(formats::parse_ppm("P6\n1 1\n4095\n", "t.ppm"), common::DataError);
}

TEST_CASE("OBJ: polygons fanned into triangles, v/vt/vn words, relative indices") {
  const formats::TriangleMesh m = formats::parse_obj(
      "# quad\nv 0 0 0\nv 1 0 0\nv 1 2 0\nv 0 2 0\nvn 0 0 1\nf 1/1/1 2//1 3 -1\n", "quad.obj");
  REQUIRE(m.vertices.size() == 4);
  CHECK(m.vertices[2] == Eigen::Vector3d(1, 2, 0));
  REQUIRE(m.faces.size() == 2);
  CHECK(m.faces[0] == std::array<int, 3>{0, 1, 2});
  CHECK(m.faces[1] == std::array<int, 3>{0, 2, 3});
}

TEST_CASE("STL: ASCII and binary give one vertex per facet corner") {
  const formats::TriangleMesh a = formats::parse_stl(
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
      "endfacet\nendsolid t\n",
      "t.stl");
  REQUIRE(a.faces.size() == 1);
  CHECK(a.vertices[1] == Eigen::Vector3d(1, 0, 0));
  std::string bin(84 + 50, '\0');
  const std::uint32_t n = 1;
  std::memcpy(&bin[80], &n, 4);
  const float corners[9] = {0, 0, 0, 2, 0, 0, 0, 3, 0.5f};
  std::memcpy(&bin[84 + 12], corners, sizeof corners);
  const formats::TriangleMesh b = formats::parse_stl(bin, "b.stl");
  REQUIRE(b.vertices.size() == 3);
  CHECK(b.vertices[2] == Eigen::Vector3d(0, 3, 0.5));
  CHECK(b.faces[0] == std::array<int, 3>{0, 1, 2});
}

TEST_CASE("mesh import: malformed OBJ/STL/PLY bytes are DataErrors naming the file") {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  struct Case {
    std::string bytes, ext, want;
  };
  const Case cases[] = {
      {tri + "f 1.5 2 3\n", "obj", "line 4: malformed face index '1.5'"},
      {tri + "f 1 2x 3\n", "obj", "line 4: malformed face index '2x'"},
      {tri + "f 1 2 99999999999\n", "obj", "line 4: malformed face index"},
      {tri + "f 1 2 0\n", "obj", "line 4: face index out of range"},
      {tri + "f 1 2 -4\n", "obj", "line 4: face index out of range"},
      {tri + "f 1 2\n", "obj", "line 4: face with fewer than 3 vertices"},
      {"v 0 0\n", "obj", "line 1: malformed vertex"},
      {"solid x\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n", "stl", "facet with fewer than 3"},
      {"solid x\nvertex 0 0 nan\n", "stl", "malformed 'vertex' line"},
      {std::string(84, '\0') + "abc", "stl", "neither ASCII STL"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n", "ply",
       "field 'x' missing"},
  };
  for (const auto& c : cases) {
    INFO(c.bytes);
    try {
      formats::parse_triangle_mesh(c.bytes, "bad." + c.ext, c.ext);
      FAIL("accepted");
    } catch (const common::DataError& e) {
      CHECK_THAT(std::string(e.what()), Catch::Contains("bad." + c.ext) && Catch::Contains(c.want));
    }
  }
}
