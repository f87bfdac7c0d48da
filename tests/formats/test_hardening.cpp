// Malformed and hostile input (issue 12): every case here broke a reader before (crash, hang,
// gigabytes allocated for a 100-byte file, a value read wrongly, or a message cut at a NUL).
// The bytes are made here, so CI needs nothing but the repository. Also: PCL's zero padding,
// the binary_compressed/ascii PCD writers, PLY int labels and scalar_ names
// (the JSON documents' cases are in tests/documents/).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "support/cli.h"

using namespace canopy::formats;
using canopy::common::DataError;
using Catch::Contains;

namespace {

std::string tmp_dir(const std::string& name) { return canopy::test::fresh_dir("formats", name).string(); }

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
}

// The DataError's full message ("<name>: <cause>"); fails the test when `f` does not throw one.
template <typename F>
std::string data_error(F f, const std::string& name) {
  try {
    f();
  } catch (const DataError& e) {
    CHECK(std::string(e.what()).rfind(name + ": ", 0) == 0);
    return e.what();
  }
  FAIL("no DataError for " << name);
  return "";
}

std::string pcd_error(const std::string& bytes, const std::string& name) {
  return data_error([&] { parse_pcd(bytes, name); }, name);
}
std::string ply_error(const std::string& bytes, const std::string& name) {
  return data_error([&] { parse_ply(bytes, name); }, name);
}

std::string xyz_header(const std::string& width, const std::string& points, const std::string& data,
                       const std::string& count = "1 1 1") {
  return "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT " + count + "\nWIDTH " + width +
         "\nHEIGHT 1\nPOINTS " + points + "\nDATA " + data + "\n";
}

std::string floats(std::initializer_list<float> v) {
  std::string s;
  for (float f : v) s.append(reinterpret_cast<const char*>(&f), 4);
  return s;
}

// A cloud with a float64 column and an odd row size (13 bytes), so rows straddle read chunks.
PointCloud odd_cloud(std::size_t n) {
  PointCloud c;
  c.resize(n);
  auto& x = c.add("x");
  auto& y = c.add("y", kFloat64);
  auto& l = c.add("flag", kUint8);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<float>(0.001 * static_cast<double>(i));
    y[i] = 1.0 / 3.0 + static_cast<double>(i);
    l[i] = static_cast<double>(i % 251);
  }
  return c;
}

void check_equal(const PointCloud& a, const PointCloud& b) {
  REQUIRE(a.size() == b.size());
  REQUIRE(a.names() == b.names());
  for (std::size_t c = 0; c < a.names().size(); ++c) {
    CHECK(a.types()[c] == b.types()[c]);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a.col(c)[i] != b.col(c)[i];
    INFO("column " << a.names()[c]);
    CHECK(differ == 0);
  }
}

}  // namespace

TEST_CASE("PCD: a header line of only spaces is skipped like an empty line (was SIGSEGV)") {
  const std::string bytes =
      "VERSION 0.7\n   \nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n\t \r\nCOUNT 1 1 1\n"
      "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
  const PointCloud c = parse_pcd(bytes, "blank.pcd");
  REQUIRE(c.size() == 1);
  CHECK(c.col("z")[0] == 3.0);
}

TEST_CASE("PCD: huge COUNT is refused by a limit, not a quadratic loop") {
  for (const char* count : {"20000", "200000", "4294967296"}) {
    INFO(count);
    const std::string msg =
        pcd_error(xyz_header("0", "0", "binary", std::string("1 1 ") + count), "count.pcd");
    CHECK_THAT(msg, Contains("COUNT"));
  }
  CHECK_THAT(pcd_error(xyz_header("0", "0", "binary", "1 1 0"), "c0.pcd"), Contains("COUNT 0"));
  // Within the limit: a PCL-style descriptor with COUNT 33 is fine.
  std::string fpfh = "FIELDS fpfh\nSIZE 4\nTYPE F\nCOUNT 33\nWIDTH 1\nPOINTS 1\nDATA binary\n";
  fpfh += std::string(33 * 4, '\0');
  CHECK(parse_pcd(fpfh, "fpfh.pcd").names().size() == 33);
}

TEST_CASE("PCD: POINTS larger than the data is refused before allocating") {
  const std::string body = floats({0, 0.2f, 1, 0.1f, 0.2f, 1, 0.2f, 0.2f, 1});  // 3 points
  for (const char* n : {"100000000", "4294967295", "9223372036854775807"}) {
    INFO(n);
    const std::string msg = pcd_error(xyz_header(n, n, "binary") + body, "big.pcd");
    CHECK_THAT(msg, Contains("truncated") && Contains(std::string("POINTS ") + n) && Contains("36 bytes"));
    // ascii: at least two bytes per value.
    CHECK_THAT(pcd_error(xyz_header(n, n, "ascii") + "1 2 3\n", "big.pcd"), Contains("POINTS"));
  }
  CHECK_THAT(pcd_error(xyz_header("18446744073709551616", "1", "binary"), "u64.pcd"),
             Contains("WIDTH") && Contains("not an integer"));
  CHECK_THAT(pcd_error(xyz_header("-1", "1", "binary"), "neg.pcd"), Contains("WIDTH '-1'"));
  CHECK_THAT(pcd_error(xyz_header("1e8", "1e8", "binary"), "exp.pcd"), Contains("WIDTH '1e8'"));
}

TEST_CASE("PCD: a binary_compressed header cannot ask for more than its block can hold") {
  std::string b =
      "FIELDS x\nSIZE 4\nTYPE F\nCOUNT 1\nWIDTH 1073741823\nHEIGHT 1\nPOINTS 1073741823\n"
      "DATA binary_compressed\n";
  const std::uint32_t csize = 2, usize = 1073741823u * 4u;
  b.append(reinterpret_cast<const char*>(&csize), 4);
  b.append(reinterpret_cast<const char*>(&usize), 4);
  b += std::string("\xfc\xff", 2);
  CHECK_THAT(pcd_error(b, "comp.pcd"), Contains("POINTS 1073741823"));
}

TEST_CASE("PCD: WIDTH x HEIGHT overflow and SIZE beyond int are errors, not wrapped values") {
  std::string wh =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967296\nHEIGHT 4294967296\nPOINTS 0\nDATA binary\n";
  CHECK_THAT(pcd_error(wh, "wh.pcd"), Contains("WIDTH 4294967296 x HEIGHT 4294967296"));
  const std::string size = "FIELDS x\nSIZE 4294967300\nTYPE F\nWIDTH 1\nPOINTS 1\nDATA binary\n" + floats({1});
  CHECK_THAT(pcd_error(size, "size.pcd"), Contains("SIZE '4294967300'"));
  CHECK_THAT(pcd_error("FIELDS x\nSIZE 3\nTYPE F\nWIDTH 0\nDATA binary\n", "s3.pcd"), Contains("SIZE 3"));
  CHECK_THAT(pcd_error("FIELDS x\nSIZE 4\nTYPE f\nWIDTH 0\nDATA binary\n", "t.pcd"), Contains("TYPE 'f'"));
  CHECK_THAT(pcd_error(xyz_header("1", "1", "binary") + "WIDTH 1\n", "dup.pcd"),
             Contains("not a number") || Contains("truncated"));
  CHECK_THAT(pcd_error("FIELDS x\nFIELDS y\nSIZE 4\nTYPE F\nWIDTH 0\nDATA binary\n", "twice.pcd"),
             Contains("FIELDS appears twice"));
  CHECK_THAT(pcd_error("FIELDS x x\nSIZE 4 4\nTYPE F F\nWIDTH 0\nDATA binary\n", "dupf.pcd"),
             Contains("duplicate field 'x'"));
}

TEST_CASE("PCD errors say what the file is and are not cut at a NUL byte") {
  CHECK_THAT(pcd_error("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n", "m.pcd"),
             Contains("this is a PLY file, not a PCD file"));
  CHECK_THAT(pcd_error(std::string("LASF\x01\x02", 6), "s.pcd"), Contains("this is a LAS file"));
  CHECK_THAT(pcd_error("{\"format\": \"canopy.segment_graph\"}\n", "j.pcd"),
             Contains("this is a JSON document"));
  const std::string msg = pcd_error(std::string("VERSION 0.7\nFIE\0LDS x\n", 22), "nul.pcd");
  CHECK_THAT(msg, Contains("FIE\\x00LDS x"));
  CHECK(std::strlen(msg.c_str()) == msg.size());  // no NUL inside: printing shows it all
  const std::string junk = pcd_error(xyz_header("1", "1", "ascii") + "1 2\x01z 3\n", "j2.pcd");
  CHECK_THAT(junk, Contains("'2\\x01z' is not a number"));
}

TEST_CASE("PCD: zero padding after binary data (PCL's writer) is accepted, other trailing data is not") {
  const std::string good = xyz_header("2", "2", "binary") + floats({1, 2, 3, 4, 5, 6});
  const PointCloud c = parse_pcd(good + std::string(4096, '\0'), "pad.pcd");
  REQUIRE(c.size() == 2);
  CHECK(c.col("z")[1] == 6.0);
  CHECK_THAT(pcd_error(good + floats({7, 8, 9}), "more.pcd"), Contains("data longer than the header says"));
  // ascii: trailing whitespace is fine, more numbers are not.
  CHECK(parse_pcd(xyz_header("1", "1", "ascii") + "1 2 3\n\n \n", "a.pcd").size() == 1);
  CHECK_THAT(pcd_error(xyz_header("1", "1", "ascii") + "1 2 3\n4 5 6\n", "a2.pcd"),
             Contains("more ascii data"));

  const std::string dir = tmp_dir("padding");
  write_bytes(dir + "/pad.pcd", good + std::string(4096, '\0'));
  CHECK(read_pcd(dir + "/pad.pcd").col("x")[1] == 4.0);
  write_bytes(dir + "/more.pcd", good + std::string(5000, '\0') + "x");
  CHECK_THAT(data_error([&] { read_pcd(dir + "/more.pcd"); }, dir + "/more.pcd"), Contains("data longer"));
}

TEST_CASE("read_pcd (chunked binary reading) gives what parse_pcd gives, and the same errors") {
  const std::string dir = tmp_dir("chunks");
  const PointCloud c = odd_cloud(200003);  // 2.6 MB: several 1 MiB chunks, rows cut at chunk ends
  const std::string bytes = serialize_pcd(c);
  write_bytes(dir + "/c.pcd", bytes);
  check_equal(c, read_pcd(dir + "/c.pcd"));
  check_equal(c, parse_pcd(bytes, "c.pcd"));
  write_bytes(dir + "/t.pcd", bytes.substr(0, bytes.size() - 5));
  CHECK_THAT(data_error([&] { read_pcd(dir + "/t.pcd"); }, dir + "/t.pcd"), Contains("truncated"));
  // Every encoding through the file reader.
  for (auto enc : {PcdEncoding::ascii, PcdEncoding::binary_compressed}) {
    PcdWriteOptions o;
    o.encoding = enc;
    write_pcd(c, dir + "/e.pcd", o);
    check_equal(c, read_pcd(dir + "/e.pcd"));
  }
}

TEST_CASE("PCD writer: binary_compressed and ascii round-trip every type exactly") {
  PointCloud c = odd_cloud(5000);
  c.add("neg", {'I', 2});
  c.add("u16", {'U', 2});
  for (std::size_t i = 0; i < c.size(); ++i) {
    c.col("neg")[i] = -static_cast<double>(i % 300);
    c.col("u16")[i] = 7;  // constant: long back-references
  }
  c.comments = {"made by test"};
  PcdWriteOptions comp;
  comp.encoding = PcdEncoding::binary_compressed;
  const std::string z = serialize_pcd(c, comp);
  CHECK(z.find("DATA binary_compressed\n") != std::string::npos);
  CHECK(z.size() < serialize_pcd(c).size());
  check_equal(c, parse_pcd(z, "z.pcd"));
  CHECK(serialize_pcd(c, comp) == z);  // deterministic
  PcdWriteOptions ascii;
  ascii.encoding = PcdEncoding::ascii;
  check_equal(c, parse_pcd(serialize_pcd(c, ascii), "a.pcd"));
  // Incompressible bytes and the empty cloud.
  PointCloud r;
  r.resize(3000);
  auto& x = r.add("x", kFloat64);
  std::uint64_t s = 88172645463325252ull;
  for (auto& v : x) {
    s ^= s << 13, s ^= s >> 7, s ^= s << 17;
    v = static_cast<double>(s >> 11) * 0x1.0p-53;
  }
  check_equal(r, parse_pcd(serialize_pcd(r, comp), "r.pcd"));
  PointCloud empty;
  empty.add("x");
  CHECK(parse_pcd(serialize_pcd(empty, comp), "e.pcd").size() == 0);
}

TEST_CASE("PLY: element counts larger than the data are refused before allocating") {
  const std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex COUNT\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  for (const char* n : {"100000000", "4294967295", "9223372036854775807"}) {
    INFO(n);
    std::string b = bin;
    b.replace(b.find("COUNT"), 5, n);
    CHECK_THAT(ply_error(b + std::string(36, '\0'), "v.ply"), Contains("truncated") && Contains(n));
  }
  std::string b = bin;
  b.replace(b.find("COUNT"), 5, "9223372036854775808");
  CHECK_THAT(ply_error(b, "v.ply"), Contains("count '9223372036854775808'"));
  const std::string face =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4294967295\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  CHECK_THAT(ply_error(face, "f.ply"), Contains("element face count 4294967295"));
  // A list longer than the data left.
  std::string list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  list += std::string(36, '\0');
  const std::uint32_t m = 4000000000u;
  list.append(reinterpret_cast<const char*>(&m), 4);
  list += std::string(12, '\0');
  CHECK_THAT(ply_error(list, "l.ply"), Contains("face.vertex_indices") && Contains("does not fit"));
}

TEST_CASE("PLY: an ascii value outside its integer type is an error, not a wrapped value") {
  const std::string hdr =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  CHECK(parse_ply(hdr + "3 0 1 2\n", "ok.ply").faces.size() == 1);
  CHECK_THAT(ply_error(hdr + "259 0 1 2\n", "wrap.ply"), Contains("'259' is not a uchar"));
  CHECK_THAT(ply_error(hdr + "3 0 1 2.5\n", "frac.ply"), Contains("'2.5' is not a int"));
  CHECK_THAT(ply_error(hdr + "3 0 1 1e10\n", "big.ply"), Contains("'1e10' is not a int"));
  CHECK_THAT(ply_error(hdr + "3 0 1 -1\n", "neg.ply"), Contains("refers to vertex -1"));
}

TEST_CASE("PLY errors say what the file is and are not cut at a NUL byte") {
  CHECK_THAT(ply_error("# .PCD v0.7\nVERSION 0.7\nFIELDS x\n", "p.ply"),
             Contains("this is a PCD file, not a PLY file"));
  const std::string msg =
      ply_error(std::string("ply\nformat ascii 1.0\nelem\0ent vertex 1\nend_header\n", 47), "n.ply");
  CHECK_THAT(msg, Contains("elem\\x00ent vertex 1"));
  CHECK(std::strlen(msg.c_str()) == msg.size());
  CHECK_THAT(
      ply_error("ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\nend_header\n0\n0\n", "two.ply"),
      Contains("two vertex elements"));
}

TEST_CASE("PLY writer: uint32 as int, scalar_ prefix for CloudCompare, read back without it") {
  Mesh m;
  m.vertices.resize(2);
  m.vertices.add("x") = {0, 1};
  m.vertices.add("y") = {0, 1};
  m.vertices.add("z") = {0, 1};
  m.vertices.add("normal_x") = {1, 1};
  m.vertices.add("red", kUint8) = {1, 2};
  m.vertices.add("label", kUint32) = {1, 3};
  m.vertices.add("point_count", kUint32) = {7, 9};
  m.vertices.add("big", kUint32) = {1, 4294967295.0};
  m.vertices.add("curvature") = {0.5, 0.25};
  const std::string plain = serialize_ply(m);
  CHECK_THAT(plain, Contains("property int label\nproperty int point_count\nproperty uint big\n"));
  PlyWriteOptions o;
  o.scalar_prefix = true;
  for (bool ascii : {false, true}) {
    o.ascii = ascii;
    const std::string cc = serialize_ply(m, o);
    CHECK_THAT(cc, Contains("property float x\n") && Contains("property float nx\n") &&
                       Contains("property uchar red\n") && Contains("property int scalar_label\n") &&
                       Contains("property int scalar_point_count\n") &&
                       Contains("property float scalar_curvature\n"));
    const Mesh back = parse_ply(cc, "cc.ply");
    CHECK(back.vertices.names() == m.vertices.names());
    CHECK(back.vertices.col("label") == m.vertices.col("label"));
    CHECK(back.vertices.col("big") == m.vertices.col("big"));
  }
  // A file with both "f" and "scalar_f" keeps both names.
  const Mesh both = parse_ply(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty float f\nproperty float scalar_f\nend_header\n0 0 0 1 2\n",
      "both.ply");
  CHECK(both.vertices.col("f")[0] == 1.0);
  CHECK(both.vertices.col("scalar_f")[0] == 2.0);
}

TEST_CASE("PCD: a header of only padding fields is refused (a cloud without columns cannot be written)") {
  CHECK_THAT(pcd_error("FIELDS _\nSIZE 1\nTYPE U\nCOUNT 4\nWIDTH 1\nPOINTS 1\nDATA binary\nabcd", "pad.pcd"),
             Contains("only padding fields"));
}

TEST_CASE("ascii writers store integer columns as the binary writer does (rounded, clamped)") {
  PointCloud c;
  c.resize(3);
  c.add("x") = {0, 1, 2};
  c.add("u8", kUint8) = {300, -5, 2.6};
  c.add("i32", kInt32) = {1e300, -1e300, std::nan("")};
  PcdWriteOptions ascii;
  ascii.encoding = PcdEncoding::ascii;
  const PointCloud a = parse_pcd(serialize_pcd(c, ascii), "a.pcd");
  const PointCloud b = parse_pcd(serialize_pcd(c), "b.pcd");
  CHECK(a.col("u8") == std::vector<double>{255, 0, 3});
  CHECK(a.col("i32") == std::vector<double>{2147483647.0, -2147483648.0, 0});
  CHECK(a.col("u8") == b.col("u8"));
  CHECK(a.col("i32") == b.col("i32"));
}

TEST_CASE("read_pcd: a long header (many comment lines) across read chunks") {
  const std::string dir = tmp_dir("long_header");
  PointCloud c = odd_cloud(10);
  for (int i = 0; i < 20000; ++i) c.comments.push_back("comment line " + std::to_string(i));  // ~400 KB
  write_pcd(c, dir + "/h.pcd");
  const PointCloud back = read_pcd(dir + "/h.pcd");
  check_equal(c, back);
  CHECK(back.comments.size() == 20000);
  CHECK(back.comments.back() == "comment line 19999");
}
