// Issue 31: PointCloud's packed columns (a field stored at its width, turned into doubles by the
// first col()) and the readers' field selection (read_points / read_las with FieldSelection).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/points_io.h"
#include "support/cli.h"

using namespace canopy::formats;
using canopy::common::DataError;

namespace {

std::string las_data(const std::string& name) {
  return std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/" + name;
}

std::uint64_t bits(double d) {
  std::uint64_t b;
  std::memcpy(&b, &d, 8);
  return b;
}

// Every column's values as bits, column by column, through col() of a copy (the copy unpacks,
// the original is left as it is).
std::vector<std::vector<std::uint64_t>> all_bits(const PointCloud& c) {
  PointCloud copy = c;
  std::vector<std::vector<std::uint64_t>> out;
  for (std::size_t i = 0; i < copy.names().size(); ++i) {
    out.emplace_back();
    for (double v : copy.col(i)) out.back().push_back(bits(v));
  }
  return out;
}

// A cloud with a scaled int32 column "x" (0.01 steps about 500000.5), a uint16 "intensity" and
// a plain double column "t"; 5 points.
PointCloud packed_cloud() {
  PointCloud c;
  auto& x = c.add_packed<std::int32_t>("x", kFloat64, true, 0.01, 500000.5);
  auto& in = c.add_packed<std::uint16_t>("intensity", {'U', 2});
  auto& t = c.add("t", kFloat64);
  for (std::int32_t k : {-2147483647 - 1, -1, 0, 7, 2147483647}) x.push_back(k);
  for (std::uint16_t k : {0, 1, 300, 65534, 65535}) in.push_back(k);
  for (double v : {0.5, 1.5, 2.5, 3.5, 4.5}) t.push_back(v);
  c.resize(5);
  return c;
}

}  // namespace

TEST_CASE("a packed column reads as the doubles its reader's expression gives, and is unpacked by col()") {
  PointCloud c = packed_cloud();
  REQUIRE(c.size() == 5);
  CHECK(c.names() == std::vector<std::string>{"x", "intensity", "t"});
  CHECK(c.types()[0] == kFloat64);
  CHECK(c.types()[1] == FieldType{'U', 2});
  CHECK(c.packed(0));
  CHECK(c.packed(1));
  CHECK_FALSE(c.packed(2));
  const std::int32_t raw[5] = {-2147483647 - 1, -1, 0, 7, 2147483647};
  // value() and values() leave the column packed.
  double block[3];
  c.values(0, 1, 3, block);
  for (int k = 0; k < 3; ++k) CHECK(bits(block[k]) == bits(raw[k + 1] * 0.01 + 500000.5));
  CHECK(c.value(1, 4) == 65535.0);
  CHECK(c.value(2, 2) == 2.5);
  CHECK(c.packed(0));
  CHECK_THROWS_AS(c.values(0, 3, 3, block), std::out_of_range);
  // col() unpacks: the same bits as `int32 * scale + offset`, as the LAS reader computed them.
  const PointCloud& cc = c;
  const std::vector<double>& x = cc.col("x");
  CHECK_FALSE(c.packed(0));
  REQUIRE(x.size() == 5);
  for (int k = 0; k < 5; ++k) CHECK(bits(x[k]) == bits(raw[k] * 0.01 + 500000.5));
  CHECK(&cc.col("x") == &x);  // the same column from now on
  CHECK(c.col("intensity") == std::vector<double>{0, 1, 300, 65534, 65535});
  CHECK_FALSE(c.packed(1));
}

TEST_CASE("select, copies, resize and add keep packed columns' values") {
  const PointCloud c = packed_cloud();
  const PointCloud s = c.select({4, 0, 0, 2});
  REQUIRE(s.size() == 4);
  CHECK(s.packed(0));
  CHECK(s.packed(1));
  CHECK(c.packed(0));  // selecting did not unpack the source
  PointCloud plain = c;
  (void)plain.col(0);
  (void)plain.col(1);
  CHECK(c.packed(0));  // unpacking a copy leaves the original packed
  CHECK(all_bits(s) == all_bits(plain.select({4, 0, 0, 2})));
  CHECK(all_bits(c) == all_bits(plain));

  PointCloud grown = c;
  grown.resize(7);  // another length: unpacked, the new rows 0 (not the scale's offset)
  CHECK_FALSE(grown.packed(0));
  CHECK(grown.col("x")[6] == 0.0);
  CHECK(grown.col("x")[4] == plain.col("x")[4]);
  CHECK(grown.col("intensity")[5] == 0.0);

  PointCloud retyped = c;
  retyped.add("intensity", kFloat32);  // an existing packed column: unpacked, then retyped
  CHECK_FALSE(retyped.packed(1));
  CHECK(retyped.type("intensity") == kFloat32);
  CHECK(retyped.col("intensity") == plain.col("intensity"));

  PointCloud moved = PointCloud(c);
  PointCloud target;
  target = std::move(moved);
  CHECK(target.packed(0));
  CHECK(all_bits(target) == all_bits(plain));
  target.remove("x");
  CHECK(target.names() == std::vector<std::string>{"intensity", "t"});
  CHECK(target.col("intensity") == plain.col("intensity"));
}

TEST_CASE("threads unpacking the same columns of a const cloud all see the whole column") {
  PointCloud c;
  auto& a = c.add_packed<std::uint16_t>("a", {'U', 2});
  auto& b = c.add_packed<std::int32_t>("b", kFloat64, true, 0.001, -20.0);
  constexpr std::size_t n = 200000;
  for (std::size_t i = 0; i < n; ++i) {
    a.push_back(static_cast<std::uint16_t>(i * 7));
    b.push_back(static_cast<std::int32_t>(i) - 100000);
  }
  c.resize(n);
  const PointCloud& cc = c;
  std::vector<double> sums(8, 0.0);
  std::vector<const std::vector<double>*> seen(8);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < sums.size(); ++t) {
    threads.emplace_back([&, t] {
      const auto& col = cc.col(t % 2 ? "a" : "b");
      seen[t] = &col;
      for (double v : col) sums[t] += v;
    });
  }
  for (auto& t : threads) t.join();
  double sa = 0, sb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sa += static_cast<std::uint16_t>(i * 7);
    sb += (static_cast<std::int32_t>(i) - 100000) * 0.001 + -20.0;
  }
  for (std::size_t t = 0; t < sums.size(); ++t) {
    CHECK(sums[t] == (t % 2 ? sa : sb));
    CHECK(seen[t] == seen[t % 2]);
  }
}

TEST_CASE("the LAS reader's columns are packed and read as before; gps_time is doubles") {
  const PointCloud c = read_las(las_data("simple.las"));  // format 3: x y z, flags, gps, rgb
  REQUIRE(c.size() == 1065);
  for (std::size_t i = 0; i < c.names().size(); ++i) {
    INFO(c.names()[i]);
    CHECK(c.packed(i) == (c.names()[i] != "gps_time"));
  }
  // The same as the in-memory parser and the chunked reader at a record's edge, bit for bit.
  CHECK(all_bits(c) == all_bits(parse_las(canopy::common::read_file(las_data("simple.las")), "simple.las")));
  CHECK(all_bits(c) == all_bits(read_las(las_data("simple.las"), 34)));
  // Known first record (laspy's simple.las): x 637012.24, intensity 143, classification 1.
  CHECK(c.value(0, 0) == Approx(637012.24).margin(1e-9));
  CHECK(c.col("intensity")[0] == 143);
  CHECK(c.col("classification")[0] == 1);
}

TEST_CASE("read_points with a field selection makes only the selected fields, with the same values") {
  for (const char* file : {"simple.las", "simple.laz", "extrabytes.las", "1_4_w_evlr.laz", "test1_4.las"}) {
    INFO(file);
    const std::string path = las_data(file);
    const PointCloud all = read_points(path);
    const PointCloud xyz = read_points(path, "t", FieldSelection::only({"x", "y", "z"}));
    CHECK(xyz.names() == std::vector<std::string>{"x", "y", "z"});
    CHECK(xyz.size() == all.size());
    CHECK(xyz.comments == all.comments);
    // A field the file lacks is left out, not an error; the order is the file's, not the list's.
    const std::string last = all.names().back();
    const PointCloud two = read_points(path, "t", FieldSelection::only({last, "no_such_field", "intensity"}));
    CHECK(two.names() == std::vector<std::string>{"intensity", last});
    const auto a = all_bits(all);
    auto column = [&](const std::string& f) {
      for (std::size_t i = 0; i < all.names().size(); ++i) {
        if (all.names()[i] == f) return a[i];
      }
      return std::vector<std::uint64_t>{};
    };
    CHECK(all_bits(xyz) == std::vector<std::vector<std::uint64_t>>{column("x"), column("y"), column("z")});
    CHECK(all_bits(two) == std::vector<std::vector<std::uint64_t>>{column("intensity"), column(last)});
  }
  // An Extra Bytes field alone (extrabytes.las describes 'Colors' as 3 uint16 among others).
  const PointCloud all = read_points(las_data("extrabytes.las"));
  std::string extra;
  for (const auto& n : all.names()) {
    if (n.rfind("Colors", 0) == 0) extra = n;
  }
  REQUIRE_FALSE(extra.empty());
  const PointCloud one = read_points(las_data("extrabytes.las"), "t", FieldSelection::only({extra}));
  REQUIRE(one.names() == std::vector<std::string>{extra});
  PointCloud copy = all;
  CHECK(one.col(extra) == copy.col(extra));
  // Errors are the same with a selection.
  CHECK_THROWS_WITH(read_points(las_data("bad_vlr_count.las"), "t", FieldSelection::only({"x"})),
                    Catch::Contains("VLR") && Catch::Contains("bad_vlr_count.las"));
}

TEST_CASE("read_points with a field selection on PCD keeps the selected fields") {
  const auto dir = canopy::test::fresh_dir("formats", "packed_selection");
  PointCloud c;
  for (const char* f : {"x", "y", "z", "label"}) c.add(f, kFloat32);
  c.resize(3);
  for (std::size_t i = 0; i < 3; ++i) {
    c.col("x")[i] = double(i);
    c.col("label")[i] = 10.0 + double(i);
  }
  const std::string path = (dir / "c.pcd").string();
  write_pcd(c, path);
  const PointCloud r = read_points(path, "t", FieldSelection::only({"label", "x"}));
  CHECK(r.names() == std::vector<std::string>{"x", "label"});
  CHECK(r.col("label") == std::vector<double>{10, 11, 12});
  CHECK(read_points(path).names().size() == 4);
}

TEST_CASE("a DATA binary PCD is read in chunks with only the selected columns, the same values as whole") {
  // cost.md §17: read_points hands a regular PCD file to read_pcd (no copy of the whole file);
  // DATA binary makes only the selected columns when x, y and z are among them.
  const auto dir = canopy::test::fresh_dir("formats", "pcd_stream_selection");
  PointCloud c;
  c.add("x", kFloat64);
  c.add("y", kFloat64);
  c.add("z", kFloat64);
  c.add("intensity", kFloat32);
  c.add("label", kUint32);
  const std::size_t n = 70000;  // more than one 1 MiB chunk of 32-byte rows
  c.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    c.col("x")[i] = 500000.125 + 0.001 * double(i);
    c.col("y")[i] = -3.5 * double(i);
    c.col("z")[i] = 1e-3 * double(i % 977);
    c.col("intensity")[i] = 0.5f * float(i % 31);
    c.col("label")[i] = double(i % 7);
  }
  for (const auto& [name, options] : {std::pair{"b.pcd", PcdWriteOptions{PcdEncoding::binary}},
                                      {"c.pcd", PcdWriteOptions{PcdEncoding::binary_compressed}},
                                      {"a.pcd", PcdWriteOptions{PcdEncoding::ascii}}}) {
    INFO(name);
    const std::string path = (dir / name).string();
    write_pcd(c, path, options);
    const PointCloud whole = parse_pcd(canopy::common::read_file(path), path);
    const PointCloud xyz = read_points(path, "t", FieldSelection::only({"z", "x", "y"}));
    CHECK(xyz.names() == std::vector<std::string>{"x", "y", "z"});
    CHECK(xyz.size() == n);
    for (const char* f : {"x", "y", "z"}) {
      INFO(f);
      CHECK(xyz.col(f) == whole.col(f));
    }
    const PointCloud all = read_points(path);
    CHECK(all.names() == whole.names());
    CHECK(all.col("label") == whole.col("label"));
    CHECK(all.col("intensity") == whole.col("intensity"));
    // Without a coordinate in the selection the file is read whole (every coordinate checked).
    CHECK(read_points(path, "t", FieldSelection::only({"label"})).names() ==
          std::vector<std::string>{"label"});
  }
  // A non-finite coordinate in a column not selected is still refused, naming the file.
  c.col("y")[5] = std::nan("");
  const std::string path = (dir / "bad.pcd").string();
  std::string bytes = serialize_pcd(c);  // write_pcd refuses it; the bytes are what a reader gets
  canopy::common::write_file_atomic(path, bytes);
  CHECK_THROWS_WITH(read_points(path, "t", FieldSelection::only({"x", "z"})), Catch::Contains("bad.pcd"));
}
