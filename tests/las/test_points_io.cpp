// read_points / write_points: input format by magic, output format by extension, float32
// coordinates promoted when they would lose more than 0.1 mm.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/points_io.h"
#include "support/cli.h"

using namespace canopy::formats;
using canopy::common::DataError;
using canopy::common::UsageError;

namespace {

PointCloud small_cloud(double shift = 0) {
  PointCloud c;
  c.resize(4);
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  auto& l = c.add("label", kUint32);
  for (std::size_t i = 0; i < 4; ++i) {
    x[i] = shift + 0.01 * static_cast<double>(i) + 0.0123;
    y[i] = shift - 0.37 * static_cast<double>(i);
    z[i] = 1.25;
    l[i] = static_cast<double>(i);
  }
  return c;
}

std::string error_of(const std::string& bytes, const std::string& name, const std::string& tool = "fitvox") {
  try {
    parse_points(bytes, name, tool);
  } catch (const DataError& e) { return e.what(); }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("read_points chooses the format by magic, not by name", "[points_io]") {
  const PointCloud c = small_cloud();
  const std::string pcd = serialize_pcd(c);
  Mesh m;
  m.vertices = c;
  const std::string ply = serialize_ply(m);
  const std::string ply_ascii = serialize_ply(m, true);
  const std::string las = serialize_las(c);
  for (const auto& [bytes, fmt] :
       {std::pair{pcd, "pcd"}, {ply, "ply"}, {ply_ascii, "ascii ply"}, {las, "las"}}) {
    INFO(fmt);
    for (const std::string name : {"a.pcd", "a.ply", "a.las", "noext"}) {
      const PointCloud r = parse_points(bytes, name);
      REQUIRE(r.size() == 4);
      CHECK(r.col("label")[3] == 3);
      CHECK(std::fabs(r.col("x")[1] - static_cast<float>(0.0223)) < 1e-3);
    }
  }
  // A PCD whose header starts with a key instead of a comment.
  const std::string bare =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
      "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
  CHECK(parse_points(bare, "b").col("z")[0] == 3);
}

TEST_CASE("read_points names what a file is when it is no point cloud", "[points_io]") {
  Mesh m;
  m.vertices = small_cloud();
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  CHECK(contains(error_of(serialize_ply(m), "mesh.ply"),
                 "mesh.ply: this is a PLY mesh with 2 faces; fitvox reads points"));
  CHECK(contains(error_of("{\"format\": \"canopy.segment_graph\", \"version\": 1}", "s.pcd"),
                 "s.pcd: this is a JSON document (canopy.segment_graph)"));
  CHECK(contains(error_of("\x89PNG\r\n\x1a\n....", "i.pcd"), "i.pcd: this is a PNG image"));
  CHECK(contains(error_of("", "e.pcd"),
                 "e.pcd: empty file (no points; fitvox reads PCD, PLY point sets and LAS)"));
  CHECK(contains(error_of("\x1f\x8b\x08\x00", "z.pcd"), "gzip"));
  CHECK(contains(error_of("# A markdown title\n\nSome text\n", "README.md"),
                 "README.md: this is not a point cloud canopy reads"));
  // A NUL early in the file does not cut the message: the bytes are escaped, the sentence ends.
  const std::string nul("ab\0cd\nmore", 10);
  const std::string e = error_of(nul, "nul.pcd");
  CHECK(contains(e, "'ab\\x00cd\\nmore'"));
  CHECK(contains(e, "fitvox reads PCD, PLY point sets and LAS"));
  CHECK(e.find('\0') == std::string::npos);
}

TEST_CASE("describe_content names a file for readers that expect something else", "[points_io]") {
  Mesh m;
  m.vertices = small_cloud();
  CHECK(describe_content(serialize_ply(m)) == "a PLY point set");
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  CHECK(describe_content(serialize_ply(m)) == "a PLY mesh (2 faces)");
  CHECK(describe_content(serialize_ply(m, true)) == "a PLY mesh (2 faces)");
  CHECK(describe_content(serialize_las(small_cloud())) == "a LAS file");
  CHECK(describe_content(slurp(std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/simple.laz")) ==
        "a LAZ file (compressed LAS)");
  CHECK(describe_content(serialize_pcd(small_cloud())) == "a PCD point cloud");
  CHECK(describe_content("{\"format\": \"canopy.match_result\"}") == "a JSON document (canopy.match_result)");
  CHECK(describe_content(std::string("\0\0\0", 3)) == "not a point cloud, mesh or document canopy reads");
  CHECK(describe_content("solid cube\nfacet normal 0 0 1\n") == "an STL mesh?");
  CHECK(describe_content("") == "an empty file");
}

TEST_CASE("write_points chooses the format by extension; others are usage errors", "[points_io]") {
  CHECK(output_format("-") == PointFormat::kPcd);
  CHECK(output_format("a/b.pcd") == PointFormat::kPcd);
  CHECK(output_format("a.b/c.PLY") == PointFormat::kPly);
  CHECK(output_format("x.Las") == PointFormat::kLas);
  CHECK_THROWS_AS(output_format("x.txt"), UsageError);
  CHECK_THROWS_WITH(output_format("x.txt"), Catch::Contains("unknown extension '.txt'"));
  // No extension (FIFOs, devices, /dev/fd/N): the default, PCD, as for "-".
  CHECK(output_format("dir.d/samples") == PointFormat::kPcd);
  CHECK(output_format("/dev/fd/63") == PointFormat::kPcd);
  CHECK_THROWS_WITH(output_format("x.laz"), Catch::Contains("cannot write LAZ"));

  const auto dir = canopy::test::fresh_dir("las", "write_points");
  const PointCloud c = small_cloud();
  for (const std::string ext : {"pcd", "ply", "las"}) {
    const std::string path = (dir / ("out." + ext)).string();
    write_points(c, path);
    const std::string bytes = slurp(path);
    if (ext == "pcd") CHECK(bytes == serialize_pcd(c));
    if (ext == "ply") CHECK(bytes.compare(0, 4, "ply\n") == 0);
    if (ext == "las") CHECK(bytes == serialize_las(c));
    CHECK(read_points(path).col("label")[2] == 2);
  }
  CHECK_THROWS_AS(write_points(c, (dir / "out.xyz").string()), UsageError);
  CHECK_FALSE(canopy::test::exists(dir / "out.xyz"));
}

TEST_CASE("float32 coordinates that would lose more than 0.1 mm are written as float64", "[points_io]") {
  // Near the origin float32 is kept (and the bytes are what write_pcd writes).
  PointCloud near = small_cloud(1000);
  CHECK_FALSE(promote_coordinates(&near));
  CHECK(near.type("x") == kFloat32);

  // UTM: E 500 000, N 4 400 000. float32 spacing there is 3 cm / 25 cm.
  const auto dir = canopy::test::fresh_dir("las", "promote");
  PointCloud utm = small_cloud(0);
  for (double& v : utm.col("x")) v += 500000;
  for (double& v : utm.col("y")) v += 4400000;
  for (const std::string ext : {"pcd", "ply"}) {
    const std::string path = (dir / ("utm." + ext)).string();
    write_points(utm, path);
    const PointCloud r = read_points(path);
    CHECK(r.type("x") == kFloat64);
    CHECK(r.type("y") == kFloat64);
    CHECK(r.type("z") == kFloat32);  // z stays: 1.25 is exact
    // PCD keeps U 4; PLY writes label as int (Open3D drops uint properties).
    CHECK(r.type("label") == (ext == std::string("pcd") ? kUint32 : kInt32));
    for (std::size_t i = 0; i < 4; ++i) {
      CHECK(r.col("x")[i] == utm.col("x")[i]);
      CHECK(r.col("y")[i] == utm.col("y")[i]);
    }
    std::set<double> xs(r.col("x").begin(), r.col("x").end());
    CHECK(xs.size() == 4);
  }
  // What float32 would have done: the four x values collapse to fewer.
  std::set<float> f32;
  for (double v : utm.col("x")) f32.insert(static_cast<float>(v));
  CHECK(f32.size() < 4);
}
