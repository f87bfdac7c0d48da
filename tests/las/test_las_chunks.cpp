// read_las reads a regular LAS file piece by piece: the header and the VLRs, the EVLRs (LAS 1.4,
// after the points), then the point records a chunk of whole records at a time, straight into
// the columns. The cloud and every error must be those parse_las gives for the same bytes,
// whatever the chunk size: one record, sizes that are no multiple of the record, a point count
// that is no multiple of the records per chunk, the Extra Bytes descriptors in an EVLR after
// the points.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/points_io.h"
#include "las_bytes.h"
#include "support/cli.h"

using namespace canopy::formats;
using canopy::common::DataError;

namespace {

using canopy::las_test::data;
using canopy::las_test::get;
using canopy::las_test::set;
using canopy::las_test::slurp;

// The DataError message of f(), or "" when it returns.
template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const DataError& e) { return e.what(); }
  return "";
}

// Same fields, types, comments and values, bit for bit (NaN included).
void check_same(const PointCloud& a, const PointCloud& b) {
  REQUIRE(a.size() == b.size());
  REQUIRE(a.names() == b.names());
  CHECK(a.types() == b.types());
  CHECK(a.comments == b.comments);
  for (std::size_t c = 0; c < a.names().size(); ++c) {
    INFO(a.names()[c]);
    REQUIRE(a.col(c).size() == a.size());
    REQUIRE(b.col(c).size() == b.size());
    CHECK(std::memcmp(a.col(c).data(), b.col(c).data(), a.size() * sizeof(double)) == 0);
  }
}

std::string write(const std::filesystem::path& p, const std::string& bytes) {
  canopy::test::write_file(p, bytes);
  return p.string();
}

// Chunk sizes around the record length and its multiples.
std::vector<std::size_t> chunk_sizes(std::size_t record) {
  return {1, record - 1, record, record + 1, 3 * record + 5, 7 * record, 64 * 1024, kLasReadChunk};
}

}  // namespace

TEST_CASE("read_las from the file = parse_las of its bytes, at every chunk size", "[las]") {
  for (const char* file : {"100-points.las",
                           "1_4_w_evlr.las",
                           "extrabytes.las",
                           "perm-1.0_0.las",
                           "perm-1.0_1.las",
                           "perm-1.1_0.las",
                           "perm-1.1_1.las",
                           "perm-1.2_0.las",
                           "perm-1.2_1.las",
                           "perm-1.2_2.las",
                           "perm-1.2_3.las",
                           "simple.las",
                           "test1_4.las",
                           "bad_vlr_count.las",
                           "garbage_nVariableLength.las",
                           "las-trunc-at-point-offset.las",
                           "las12-count0-with-data.las",
                           "perm-1.2-no-points.las",
                           "1_4_w_evlr.laz",
                           "extra.laz",
                           "simple.laz"}) {
    INFO(file);
    const std::string path = data(file);
    const std::string bytes = slurp(path);
    const std::string expected_error = error_of([&] { parse_las(bytes, path); });
    const std::size_t record = get<std::uint16_t>(bytes, 105);
    for (std::size_t chunk : chunk_sizes(record)) {
      INFO("chunk " << chunk);
      if (!expected_error.empty()) {
        CHECK(error_of([&] { read_las(path, chunk); }) == expected_error);
        continue;
      }
      check_same(read_las(path, chunk), parse_las(bytes, path));
    }
    // Every tool's reader takes the same path.
    if (expected_error.empty()) {
      check_same(read_points(path), parse_points(bytes, path));
    } else {
      CHECK(error_of([&] { read_points(path); }) == expected_error);
    }
  }
}

TEST_CASE("read_las: Extra Bytes described in an EVLR after the points, records across chunks", "[las]") {
  const auto dir = canopy::test::fresh_dir("las", "chunks_evlr");
  // 1001 points with Extra Bytes (described in a VLR by the writer): 7 points is no divisor.
  const std::size_t n = 1001;
  PointCloud c;
  c.resize(n);
  auto& x = c.add("x", kFloat64);
  auto& y = c.add("y", kFloat64);
  auto& z = c.add("z", kFloat64);
  auto& cls = c.add("classification", kUint8);
  auto& sx = c.add("sensor_x");
  auto& view = c.add("view_idx", kInt32);
  for (std::size_t i = 0; i < n; ++i) {
    const double k = static_cast<double>(i);
    x[i] = 500000.0 + 0.125 * k;
    y[i] = 4400000.0 - 0.25 * k;
    z[i] = 0.001 * k;
    cls[i] = static_cast<double>(i % 7);
    sx[i] = static_cast<float>(k / 3);
    view[i] = -k;
  }
  const std::string vlr_file = serialize_las(c);
  const std::size_t record = get<std::uint16_t>(vlr_file, 105);
  REQUIRE(get<std::uint32_t>(vlr_file, 100) == 1);  // the Extra Bytes VLR only
  const std::size_t data_offset = get<std::uint32_t>(vlr_file, 96);
  const std::size_t vlr_len = get<std::uint16_t>(vlr_file, 375 + 20);
  REQUIRE(data_offset == 375 + 54 + vlr_len);
  // The same file with the descriptors in an EVLR after the point records.
  std::string b = vlr_file.substr(0, 375) + vlr_file.substr(data_offset);
  set<std::uint32_t>(&b, 96, 375);
  set<std::uint32_t>(&b, 100, 0);
  set<std::uint64_t>(&b, 235, b.size());
  set<std::uint32_t>(&b, 243, 1);
  std::string evlr(60, '\0');
  std::memcpy(&evlr[2], "LASF_Spec", 9);
  set<std::uint16_t>(&evlr, 18, 4);
  set<std::uint64_t>(&evlr, 20, vlr_len);
  b += evlr + vlr_file.substr(375 + 54, vlr_len);
  const std::string path = write(dir / "evlr.las", b);

  const PointCloud expected = parse_las(vlr_file, "vlr.las");
  for (std::size_t chunk : chunk_sizes(record)) {
    INFO("chunk " << chunk);
    const PointCloud r = read_las(path, chunk);
    check_same(r, expected);
    check_same(r, parse_las(b, path));
    REQUIRE(r.has("sensor_x"));
    for (std::size_t i : {std::size_t(0), std::size_t(6), std::size_t(7), n - 1}) {
      CHECK(r.col("sensor_x")[i] == sx[i]);
      CHECK(r.col("view_idx")[i] == view[i]);
      CHECK(r.col("classification")[i] == cls[i]);
      CHECK(r.col("x")[i] == x[i]);
    }
  }
  // The EVLR cut short, or its count beyond the file: parse_las's errors, naming the file.
  std::string cut = b.substr(0, b.size() - 10);
  const std::string cut_path = write(dir / "evlr-cut.las", cut);
  CHECK(error_of([&] { read_las(cut_path, 3 * record); }) == error_of([&] { parse_las(cut, cut_path); }));
  CHECK(error_of([&] { read_las(cut_path); }).find("evlr-cut.las: EVLR 1 of ") != std::string::npos);
  std::string two = b;
  set<std::uint32_t>(&two, 243, 2);
  const std::string two_path = write(dir / "evlr-two.las", two);
  CHECK(error_of([&] { read_las(two_path); }) == error_of([&] { parse_las(two, two_path); }));
  CHECK(error_of([&] { read_las(two_path); }).find("EVLR 2 does not fit") != std::string::npos);
}

TEST_CASE("read_las: truncated and broken files fail as parse_las does, naming the file", "[las]") {
  const auto dir = canopy::test::fresh_dir("las", "chunks_broken");
  const std::string good = slurp(data("100-points.las"));  // header 227, 100 x 34 bytes
  // Every prefix up to the first records, then every 17th.
  for (std::size_t n = 0; n <= good.size(); n += n < 300 ? 1 : 17) {
    INFO("prefix " << n);
    const std::string cut = good.substr(0, n);
    const std::string path = write(dir / "prefix.las", cut);
    const std::string e = error_of([&] { parse_las(cut, path); });
    CHECK(error_of([&] { read_las(path, 34 * 3); }) == e);
    if (!e.empty()) CHECK(e.find(path + ": ") == 0);
  }
  // Lying counts and offsets.
  std::vector<std::string> broken;
  std::string b = good;
  set<std::uint32_t>(&b, 107, 4000000000u);
  broken.push_back(b);
  b = good;
  set<std::uint32_t>(&b, 96, 100000);
  broken.push_back(b);
  b = good;
  set<std::uint32_t>(&b, 107, 60);
  broken.push_back(b);
  b = good;
  set<std::uint32_t>(&b, 100, 1);
  broken.push_back(b);
  b = good;
  b[104] = static_cast<char>(0x80 | 3);  // LAZ's compression bit, no LASzip VLR
  broken.push_back(b);
  const std::string v14 = slurp(data("test1_4.las"));
  b = v14;
  set<std::uint32_t>(&b, 243, 2);
  set<std::uint64_t>(&b, 235, v14.size());
  broken.push_back(b);
  b = v14;
  set<std::uint32_t>(&b, 243, 1);
  set<std::uint64_t>(&b, 235, 400);  // inside the point data
  broken.push_back(b);
  for (std::size_t i = 0; i < broken.size(); ++i) {
    INFO("broken " << i);
    const std::string path = write(dir / "broken.las", broken[i]);
    const std::string e = error_of([&] { parse_las(broken[i], path); });
    REQUIRE_FALSE(e.empty());
    CHECK(error_of([&] { read_las(path, 34 * 3); }) == e);
    CHECK(error_of([&] { read_points(path); }) == e);
  }
  // Not a file: read_file's errors, as before.
  CHECK(error_of([&] { read_las((dir / "missing.las").string()); }).find("cannot open") != std::string::npos);
  CHECK(error_of([&] { read_las(dir.string()); }).find("is a directory") != std::string::npos);
}
