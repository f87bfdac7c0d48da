// Issue 25 (reliability round 3): comments that would break a header, PLY data left after the
// last element (a uchar list count that wrapped), PLY written without x y z. The reproducers
// of /work/shared/data/malformed/round3/ that are files are in tests/formats/data/.
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/provenance.h"
#include "support/cli.h"

using namespace canopy::formats;
using canopy::common::DataError;
using Catch::Contains;

namespace {

std::string data(const std::string& name) {
  return std::string(CANOPY_SOURCE_DIR) + "/tests/formats/data/" + name;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

PointCloud one_point() {
  PointCloud c;
  for (const char* f : {"x", "y", "z"}) c.add(f, kFloat32);
  c.resize(1);
  c.col("x")[0] = 1;
  c.col("y")[0] = 2;
  c.col("z")[0] = 3;
  return c;
}

// The input path of the round-3 reproducer: a newline and header lines inside a file name.
const std::string kEvilPath = "in\nPOINTS 1\nDATA ascii\n0 0 0\n.pcd";

}  // namespace

TEST_CASE("provenance text is escaped: a newline in a path cannot end the comment line") {
  const Provenance p{"addnoise", "0.1.0", {{"sigma", "8mm\nFIELDS a"}}, {kEvilPath, "C:\\scans\\a.pcd"}};
  const std::vector<std::string> lines = provenance_comments(p);
  REQUIRE(lines.size() == 4);
  CHECK(lines[1] == "parameter sigma = 8mm\\nFIELDS a");
  CHECK(lines[2] == "input in\\nPOINTS 1\\nDATA ascii\\n0 0 0\\n.pcd");
  CHECK(lines[3] == "input C:\\\\scans\\\\a.pcd");  // backslashes doubled: reversible
  for (const auto& l : lines) CHECK(l.find_first_of(std::string("\n\r\0", 3)) == std::string::npos);
  // Reversible, for every byte.
  std::string all;
  for (int c = 0; c < 256; ++c) all += static_cast<char>(c);
  CHECK(unescape_comment_text(escape_comment_text(all)) == all);
  CHECK(escape_comment_text("a\tb\x01\x7f") == "a\\tb\\x01\\x7f");
  CHECK(unescape_comment_text("keep \\q and \\x4") == "keep \\q and \\x4");  // not escapes written here
  // The writers' safety net escapes control bytes only: an escaped line passes unchanged.
  CHECK(header_safe_comment(lines[2]) == lines[2]);
  CHECK(header_safe_comment(std::string("a\nb\rc\0d", 7)) == "a\\nb\\rc\\x00d");
  CHECK(header_safe_comment(std::string("a\0b", 3)) == "a\\x00b");
}

TEST_CASE("PCD, PLY and LAS writers keep every comment on one line; the files read back") {
  PointCloud c = one_point();
  const Provenance p{"addnoise", "0.1.0", {}, {kEvilPath}};
  c.comments = provenance_comments(p);
  c.comments.push_back("a raw note\nVERSION 0.7\nFIELDS q\r\nwith a NUL " + std::string(1, '\0') + "end");
  const std::string want_input = "input in\\nPOINTS 1\\nDATA ascii\\n0 0 0\\n.pcd";
  const std::string want_note = "a raw note\\nVERSION 0.7\\nFIELDS q\\r\\nwith a NUL \\x00end";
  for (auto enc : {PcdEncoding::ascii, PcdEncoding::binary, PcdEncoding::binary_compressed}) {
    PcdWriteOptions o;
    o.encoding = enc;
    const PointCloud back = parse_pcd(serialize_pcd(c, o), "evil.pcd");
    REQUIRE(back.size() == 1);
    CHECK(back.col("x")[0] == 1);
    CHECK(back.names() == std::vector<std::string>{"x", "y", "z"});
    REQUIRE(back.comments.size() == 3);
    CHECK(back.comments[1] == want_input);
    CHECK(back.comments[2] == want_note);
  }
  Mesh m;
  m.vertices = c;
  for (bool ascii : {true, false}) {
    const Mesh back = parse_ply(serialize_ply(m, ascii), "evil.ply");
    REQUIRE(back.vertices.size() == 1);
    CHECK(back.vertices.col("z")[0] == 3);
    REQUIRE(back.vertices.comments.size() == 3);
    CHECK(back.vertices.comments[1] == want_input);
    CHECK(back.vertices.comments[2] == want_note);
  }
  // LAS: one comment per line of the comments VLR; the note does not become four comments.
  const PointCloud las = parse_las(serialize_las(c), "evil.las");
  REQUIRE(las.comments.size() == 3);
  CHECK(las.comments[1] == want_input);
  CHECK(las.comments[2] == want_note);
}

TEST_CASE("PLY: data after the last element is refused (a wrapped uchar list count)") {
  // The round-3 reproducer: 1000 vertices, one face of 1000 indices whose uchar count wrapped
  // to 232; 768 indices (3072 bytes) were left unread and ignored.
  const std::string bytes = slurp(data("ply-face-uchar-count-wraps.ply"));
  REQUIRE(bytes.size() == 16173);
  CHECK_THROWS_WITH(parse_ply(bytes, "wrap.ply"),
                    Contains("wrap.ply: 3072 bytes of data after the last element") &&
                        Contains("1000 vertex, 1 face") && Contains("uchar count"));
  // Made here: a valid binary and ascii mesh, then one byte / one value more.
  Mesh m;
  m.vertices = one_point();
  m.vertices.resize(3);
  m.vertices.col("x")[1] = 1;
  m.vertices.col("y")[2] = 1;
  m.faces.push_back({0, 1, 2});
  const std::string bin = serialize_ply(m, false), asc = serialize_ply(m, true);
  CHECK(parse_ply(bin, "b.ply").faces.size() == 1);
  CHECK(parse_ply(asc + "\n \r\n", "a.ply").faces.size() == 1);  // trailing white space is fine
  CHECK_THROWS_WITH(parse_ply(bin + "x", "b.ply"), Contains("b.ply: 1 bytes of data after the last element"));
  CHECK_THROWS_WITH(parse_ply(asc + "3 0 1 2\n", "a.ply"),
                    Contains("a.ply: 8 bytes of data after the last element") && !Contains("uchar"));
}

TEST_CASE("a PLY without x y z is never written: canopy could not read it back") {
  const PointCloud noxyz = parse_pcd(slurp(data("pcd-no-xyz.pcd")), "pcd-no-xyz.pcd");  // fields a b
  REQUIRE(noxyz.size() == 2);
  const std::string dir = canopy::test::fresh_dir("formats", "round3_noxyz").string();
  Mesh m;
  m.vertices = noxyz;
  CHECK_THROWS_WITH(write_ply(m, dir + "/n.ply"), Contains(dir + "/n.ply: field 'x' missing"));
  CHECK_THROWS_WITH(write_points(noxyz, dir + "/n.ply"), Contains(dir + "/n.ply: field 'x' missing"));
  CHECK_FALSE(canopy::test::exists(dir + "/n.ply"));
  // PCD has no such requirement: the cloud round-trips.
  write_points(noxyz, dir + "/n.pcd");
  CHECK(read_points(dir + "/n.pcd").names() == std::vector<std::string>{"a", "b"});
}
