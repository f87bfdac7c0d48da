#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/csv_table.h"
#include "canopy/formats/pcd.h"
#include "support/cli.h"
#include "canopy/formats/ply.h"

using namespace canopy::formats;
using canopy::common::DataError;

namespace {

std::string tmp_dir(const std::string& name) { return canopy::test::fresh_dir("formats", name).string(); }

using canopy::test::exists;

PointCloud sample_cloud() {
  PointCloud c;
  c.resize(5);
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  auto& d = c.add("range", kFloat64);
  auto& l = c.add("label", kUint32);
  auto& v = c.add("view_idx", kInt32);
  auto& b = c.add("flag", kUint8);
  auto& s = c.add("small", {'I', 2});
  for (std::size_t i = 0; i < 5; ++i) {
    x[i] = 0.25 * static_cast<double>(i);
    y[i] = -1.5 + static_cast<double>(i);
    z[i] = 3.0;
    d[i] = 1.0 / 3.0 + static_cast<double>(i);
    l[i] = static_cast<double>(i % 3 + 1);
    v[i] = -static_cast<double>(i);
    b[i] = 250;
    s[i] = -300;
  }
  c.comments.push_back("made by test");
  return c;
}

void check_same(const PointCloud& a, const PointCloud& b) {
  REQUIRE(a.size() == b.size());
  REQUIRE(a.names() == b.names());
  for (std::size_t c = 0; c < a.names().size(); ++c) {
    CHECK(a.types()[c] == b.types()[c]);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double expect = a.types()[c] == kFloat32 ? static_cast<float>(a.col(c)[i]) : a.col(c)[i];
      CHECK(b.col(c)[i] == expect);
    }
  }
}

std::string expect_data_error(const std::string& bytes, const std::string& name) {
  try {
    parse_pcd(bytes, name);
  } catch (const DataError& e) {
    CHECK(std::string(e.what()).rfind(name + ": ", 0) == 0);
    return e.cause();
  }
  FAIL("no DataError for " << name);
  return "";
}

const char* kAsciiHeader =
    "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
    "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n";

}  // namespace

TEST_CASE("PCD binary round-trip keeps every field and type") {
  const PointCloud c = sample_cloud();
  const PointCloud back = parse_pcd(serialize_pcd(c), "mem.pcd");
  check_same(c, back);
  CHECK(back.comments == c.comments);
  // Deterministic bytes.
  CHECK(serialize_pcd(c) == serialize_pcd(back));
}

TEST_CASE("PCD ascii with COUNT > 1 and padding fields") {
  const std::string text =
      "VERSION .7\nFIELDS x y z _ hist\nSIZE 4 4 4 1 4\nTYPE F F F U F\nCOUNT 1 1 1 3 2\n"
      "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 0 0 0 0.5 0.25\n4 5 6 0 0 0 1.5 -2\n";
  const PointCloud c = parse_pcd(text, "a.pcd");
  REQUIRE(c.size() == 2);
  CHECK(c.names() == std::vector<std::string>{"x", "y", "z", "hist_0", "hist_1"});
  CHECK(c.col("z")[1] == 6);
  CHECK(c.col("hist_1")[1] == -2);
}

TEST_CASE("malformed PCD input is a DataError naming the file and the problem") {
  CHECK(expect_data_error("", "empty.pcd").find("empty") != std::string::npos);
  CHECK(expect_data_error("hello world\n", "junk.pcd").find("unknown PCD header") != std::string::npos);
  // Truncated binary data.
  std::string bin = serialize_pcd(sample_cloud());
  CHECK(expect_data_error(bin.substr(0, bin.size() - 3), "trunc.pcd").find("truncated") != std::string::npos);
  // Header lying about its size.
  std::string lie = bin;
  lie.replace(lie.find("WIDTH 5"), 7, "WIDTH 9");
  lie.replace(lie.find("POINTS 5"), 8, "POINTS 9");
  CHECK(expect_data_error(lie, "lie.pcd").find("truncated") != std::string::npos);
  std::string mismatch = bin;
  mismatch.replace(mismatch.find("POINTS 5"), 8, "POINTS 4");
  CHECK(expect_data_error(mismatch, "mm.pcd").find("WIDTH") != std::string::npos);
  // Truncated ascii and non-numbers.
  CHECK(expect_data_error(std::string(kAsciiHeader) + "1 2 3\n4 5\n", "short.pcd").find("truncated") !=
        std::string::npos);
  CHECK(expect_data_error(std::string(kAsciiHeader) + "1 2 3\n4 five 6\n", "word.pcd").find("not a number") !=
        std::string::npos);
  // NaN coordinates.
  CHECK(expect_data_error(std::string(kAsciiHeader) + "1 2 3\nnan 5 6\n", "nan.pcd").find("non-finite") !=
        std::string::npos);
  // SIZE/TYPE lists disagreeing with FIELDS.
  CHECK(expect_data_error("FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 0\nPOINTS 0\nDATA ascii\n", "sz.pcd")
            .find("SIZE") != std::string::npos);
  // Corrupt compressed block.
  std::string comp = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA binary_compressed\n";
  comp += std::string("\x05\x00\x00\x00\x0c\x00\x00\x00", 8) + std::string("\xff\xff\xff\xff\xff", 5);
  CHECK(expect_data_error(comp, "lzf.pcd").find("LZF") != std::string::npos);
}

TEST_CASE("a missing required field names the field") {
  const PointCloud c = parse_pcd(std::string(kAsciiHeader) + "1 2 3\n4 5 6\n", "xyz.pcd");
  try {
    c.require({"x", "sensor_x"}, "xyz.pcd", "is this a canopy scan?");
    FAIL("no error");
  } catch (const DataError& e) {
    CHECK(std::string(e.what()) == "xyz.pcd: field 'sensor_x' missing (is this a canopy scan?)");
  }
}

TEST_CASE("writing NaN coordinates is refused and leaves no file") {
  const std::string dir = tmp_dir("nanwrite");
  PointCloud c = sample_cloud();
  c.col("x")[2] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(write_pcd(c, dir + "/bad.pcd"), DataError);
  CHECK_FALSE(exists(dir + "/bad.pcd"));
}

TEST_CASE("PLY round-trip, binary and ascii, with normals mapped to nx ny nz") {
  Mesh m;
  m.vertices.resize(4);
  auto& x = m.vertices.add("x");
  auto& y = m.vertices.add("y");
  m.vertices.add("z");
  auto& nz = m.vertices.add("normal_z");
  auto& lab = m.vertices.add("label", kUint32);
  auto& r = m.vertices.add("red", kUint8);
  x = {0, 1, 0, 1};
  y = {0, 0, 1, 1};
  nz = {1, 1, 1, 1};
  lab = {1, 1, 2, 3};
  r = {255, 0, 10, 20};
  m.faces = {{0, 1, 2}, {1, 3, 2}};
  Mesh expect = m;
  expect.vertices.add("label", kInt32);  // uint32 is written as int (Open3D skips uint)
  for (bool ascii : {false, true}) {
    const std::string bytes = serialize_ply(m, ascii);
    CHECK(bytes.find("property float nz") != std::string::npos);
    CHECK(bytes.find("property int label") != std::string::npos);
    const Mesh back = parse_ply(bytes, "m.ply");
    check_same(expect.vertices, back.vertices);
    CHECK(back.faces == m.faces);
  }
}

TEST_CASE("PLY reader: big endian, quads and vertex_index") {
  std::string b =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_index\nend_header\n";
  auto put_be_float = [&](float f) {
    unsigned char c[4];
    std::memcpy(c, &f, 4);
    for (int i = 3; i >= 0; --i) b.push_back(static_cast<char>(c[i]));
  };
  const float pts[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (auto& p : pts)
    for (float f : p) put_be_float(f);
  b.push_back(4);
  for (int i : {0, 1, 2, 3}) {
    b.push_back(0);
    b.push_back(0);
    b.push_back(0);
    b.push_back(static_cast<char>(i));
  }
  const Mesh m = parse_ply(b, "be.ply");
  CHECK(m.vertices.col("x")[2] == 1.0f);
  REQUIRE(m.faces.size() == 2);
  CHECK(m.faces[1] == std::array<int, 3>{0, 2, 3});
}

TEST_CASE("malformed PLY input is a DataError") {
  CHECK_THROWS_AS(parse_ply("", "e.ply"), DataError);
  CHECK_THROWS_AS(parse_ply("plyx\n", "e.ply"), DataError);
  const std::string hdr =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  CHECK_THROWS_AS(parse_ply(hdr + "0 0 0\n1 0 0\n", "t.ply"), DataError);                  // truncated
  CHECK_THROWS_AS(parse_ply(hdr + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "i.ply"), DataError);  // bad index
  CHECK_THROWS_AS(
      parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", "x.ply"),
      DataError);  // no y, z
}

TEST_CASE("split_csv: non-empty lines with their numbers, cells at every comma, CR dropped") {
  const std::vector<CsvRow> rows = split_csv("a,b\r\n\n,x,\r\n\r\nlast");
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].line == 1);
  CHECK(rows[0].cells == std::vector<std::string>{"a", "b"});
  CHECK(rows[1].line == 3);
  CHECK(rows[1].cells == std::vector<std::string>{"", "x", ""});
  CHECK(rows[2].line == 5);
  CHECK(rows[2].cells == std::vector<std::string>{"last"});
  CHECK(split_csv("").empty());
  CHECK(split_csv("\n\r\n").empty());
}
