// PLY colours: uchar as MeshLab and Open3D read them. 16-bit colours (LAS) are written as
// their high byte (value / 256), 8-bit colours exactly as before (formats/README.md "PLY",
// docs/decisions/formats.md, stop 70).
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "canopy/formats/las.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/points_io.h"
#include "support/cli.h"

namespace fm = canopy::formats;
namespace fs = std::filesystem;

namespace {

// Three points with red green blue of type `t` (LAS columns are uint16) holding `rgb`.
fm::Mesh coloured(fm::FieldType t, const std::vector<std::array<double, 3>>& rgb) {
  fm::Mesh m;
  auto& v = m.vertices;
  for (const char* c : {"x", "y", "z"}) v.add(c, fm::kFloat64);
  for (const char* c : {"red", "green", "blue"}) v.add(c, t);
  v.resize(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    v.col("x")[i] = 1000.5 + i;
    v.col("y")[i] = 2000.25;
    v.col("z")[i] = 3.0;
    v.col("red")[i] = rgb[i][0];
    v.col("green")[i] = rgb[i][1];
    v.col("blue")[i] = rgb[i][2];
  }
  return m;
}

std::vector<double> column(const fm::Mesh& m, const char* c) { return m.vertices.col(c); }

// Whether the PLY header of `bytes` has the line `line`.
bool header_has(const std::string& bytes, const std::string& line) {
  const std::size_t end = bytes.find("end_header\n");
  return bytes.substr(0, end).find(line + "\n") != std::string::npos;
}

}  // namespace

TEST_CASE("PLY: 16-bit colours are written as their high byte, as uchar, with a comment") {
  // LAS R15: an 8-bit writer stores v * 256 (IGN's LiDAR HD: 38144 = 149 * 256); a full-range
  // 16-bit writer v * 257 (51400 = 200 * 257); 65535 is white; 255 and 256 are dark.
  const fm::Mesh m = coloured({'U', 2}, {{38144, 39424, 32512}, {51400, 65535, 0}, {255, 256, 65280}});
  for (const bool ascii : {false, true}) {
    INFO(ascii);
    const std::string bytes = fm::serialize_ply(m, ascii);
    CHECK(header_has(bytes, "property uchar red"));
    CHECK(header_has(bytes, "property uchar green"));
    CHECK(header_has(bytes, "property uchar blue"));
    CHECK(header_has(
        bytes, "comment red green blue: 16-bit values (up to 65535) written as value / 256 (the high byte)"));
    const fm::Mesh back = fm::parse_ply(bytes, "back.ply");
    CHECK(column(back, "red") == std::vector<double>{149, 200, 0});
    CHECK(column(back, "green") == std::vector<double>{154, 255, 1});
    CHECK(column(back, "blue") == std::vector<double>{127, 0, 255});
    CHECK(column(back, "x") == column(m, "x"));  // the other fields as before
  }
  // Before stop 70 every such value was clamped to 255: a white cloud.
}

TEST_CASE("PLY: a LAS file's 16-bit colours, through the LAS reader, come out as the 8-bit colours") {
  fm::Mesh m = coloured({'U', 2}, {{43008, 43776, 39680}, {63488, 0, 256 * 17}, {0, 0, 0}});
  const fm::PointCloud las = fm::parse_las(fm::serialize_las(m.vertices, "c.las"), "c.las");
  CHECK(las.type("red") == fm::FieldType{'U', 2});
  fm::Mesh from_las;
  from_las.vertices = las;
  const fm::Mesh back = fm::parse_ply(fm::serialize_ply(from_las), "back.ply");
  CHECK(column(back, "red") == std::vector<double>{168, 248, 0});
  CHECK(column(back, "green") == std::vector<double>{171, 0, 0});
  CHECK(column(back, "blue") == std::vector<double>{155, 17, 0});
}

TEST_CASE("PLY: 8-bit colours are written as they are, byte for byte") {
  // A hand-written ascii PLY with uchar colours (0 and 255 included): read and written back,
  // the same bytes; its values are those of the file.
  const std::string text =
      "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 0\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0 0 128 255\n1 0.5 0 255 255 255\n"
      "2 1 0.25 17 0 1\n";
  const fm::Mesh m = fm::parse_ply(text, "hand.ply");
  CHECK(column(m, "red") == std::vector<double>{0, 255, 17});
  CHECK(fm::serialize_ply(m, true) == text);
  const std::string binary = fm::serialize_ply(m);
  CHECK(fm::serialize_ply(fm::parse_ply(binary, "b.ply")) == binary);
  CHECK(binary.find("16-bit") == std::string::npos);
  // uint16 colour columns whose values all fit in a byte (a LAS writer that did not scale):
  // written as they are, no comment.
  const fm::Mesh small = coloured({'U', 2}, {{0, 128, 255}, {255, 255, 255}, {1, 2, 3}});
  const std::string s = fm::serialize_ply(small, true);
  CHECK(s.find("16-bit") == std::string::npos);
  const fm::Mesh back = fm::parse_ply(s, "s.ply");
  CHECK(column(back, "blue") == std::vector<double>{255, 255, 3});
  // Float colours in [0, 255] (rounded as before) are not 16-bit: 255.4 is 255.
  const fm::Mesh f = coloured(fm::kFloat32, {{255.4, 0.6, 12}, {0, 0, 0}, {1, 1, 1}});
  const fm::Mesh fb = fm::parse_ply(fm::serialize_ply(f), "f.ply");
  CHECK(column(fb, "red") == std::vector<double>{255, 0, 1});
  CHECK(column(fb, "green") == std::vector<double>{1, 0, 1});
}

TEST_CASE("PLY: red green blue are judged together, alpha alone") {
  // One 16-bit red value makes all three colour columns 16-bit (a dark 16-bit blue of 200
  // is 0 in 8 bits, not 200); an 8-bit alpha beside them stays as it is.
  fm::Mesh m = coloured({'U', 2}, {{300, 200, 200}, {65535, 255, 0}, {0, 0, 0}});
  m.vertices.add("alpha", fm::kUint8);
  m.vertices.col("alpha") = {255, 128, 0};
  fm::Mesh back = fm::parse_ply(fm::serialize_ply(m), "back.ply");
  CHECK(column(back, "red") == std::vector<double>{1, 255, 0});
  CHECK(column(back, "green") == std::vector<double>{0, 0, 0});
  CHECK(column(back, "blue") == std::vector<double>{0, 0, 0});
  CHECK(column(back, "alpha") == std::vector<double>{255, 128, 0});
  // A 16-bit alpha beside 8-bit colours: only alpha is shifted.
  fm::Mesh a = coloured(fm::kUint8, {{10, 20, 30}, {40, 50, 60}, {70, 80, 90}});
  a.vertices.add("alpha", {'U', 2});
  a.vertices.col("alpha") = {65535, 32768, 0};
  const std::string bytes = fm::serialize_ply(a, true);
  CHECK(
      header_has(bytes, "comment alpha: 16-bit values (up to 65535) written as value / 256 (the high byte)"));
  back = fm::parse_ply(bytes, "a.ply");
  CHECK(column(back, "red") == std::vector<double>{10, 40, 70});
  CHECK(column(back, "alpha") == std::vector<double>{255, 128, 0});
}

TEST_CASE("pcd2ply: the IGN LiDAR HD tile's 16-bit colours come out as its 8-bit colours") {
  const fs::path laz = fs::path(CANOPY_SOURCE_DIR) / ".." / "shared" / "data" / "real" / "laz" /
                       "ign_lidarhd_870000_6618000.laz";
  if (!fs::exists(laz)) {
    WARN("no " << laz.string() << ": the real tile's colours not checked");
    return;
  }
  const fs::path dir = canopy::test::fresh_dir("formats", "ply_colour");
  const fs::path out = dir / "ign.ply";
  std::string err;
  REQUIRE(canopy::test::sh(std::string(CANOPY_BIN_DIR) + "/pcd2ply -i " + laz.string() + " -o " + out.string(),
                           dir / "err.txt", &err) == 0);
  const fm::Mesh ply = fm::read_ply(out.string());
  const fm::PointCloud las = fm::read_points(laz.string());
  REQUIRE(ply.vertices.size() == 70840);
  // tests/las: point 0 is (38144, 39424, 32512) = 256 x (149, 154, 127); the last point's blue
  // 49152 = 256 x 192. Before stop 70: 255 255 255 for all 70 840 points.
  CHECK(ply.vertices.col("red")[0] == 149);
  CHECK(ply.vertices.col("green")[0] == 154);
  CHECK(ply.vertices.col("blue")[0] == 127);
  CHECK(ply.vertices.col("blue")[70839] == 192);
  std::size_t differ = 0, white = 0;
  for (const char* c : {"red", "green", "blue"}) {
    const auto& a = las.col(c);
    const auto& b = ply.vertices.col(c);
    for (std::size_t i = 0; i < a.size(); ++i) {
      differ += b[i] != static_cast<double>(static_cast<std::uint16_t>(a[i]) >> 8) ? 1 : 0;
      white += b[i] == 255 ? 1 : 0;
    }
  }
  CHECK(differ == 0);
  CHECK(white == 0);  // the tile's brightest value is 64000 = 250 x 256
  // autzen_trim.las stores 8-bit colours unscaled in its 16-bit fields: written as they are
  // (a rule by type, uint16 -> high byte, would have made it black).
  const fs::path autzen = fs::path(CANOPY_SOURCE_DIR) / ".." / "shared" / "data" / "las" / "autzen_trim.las";
  if (!fs::exists(autzen)) return;
  const fm::Mesh a{fm::read_points(autzen.string()), {}};
  const std::string bytes = fm::serialize_ply(a, true);
  CHECK(bytes.find("16-bit") == std::string::npos);
  const fm::Mesh back = fm::parse_ply(bytes, "autzen.ply");
  CHECK(back.vertices.col("red")[0] == 84);
  CHECK(back.vertices.col("green")[0] == 102);
  CHECK(back.vertices.col("blue")[0] == 93);
  CHECK(back.vertices.col("red") == a.vertices.col("red"));
}
