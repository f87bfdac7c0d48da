// canopy.height_raster v1 (formats/height_raster.h; topview --raster-out / --raster): round trip,
// and every bad file refused naming the file and what is wrong (issue 31, cost.md §17).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/height_raster.h"
#include "support/cli.h"

using namespace canopy::formats;
using canopy::common::DataError;

namespace {

HeightRaster sample() {
  HeightRaster r;
  r.width = 3;
  r.height = 2;
  r.pixel = 0.07;
  r.x0 = 500000.025;
  r.y1 = 5400009.975;
  r.box_x0 = 500000.025;
  r.box_y0 = 5400000.025;
  r.box_x1 = 500000.2;
  r.box_y1 = 5400009.975;
  r.density = 400.25;
  r.values = {0.0f, 1.5f, std::numeric_limits<float>::quiet_NaN(), -0.25f, 3.0e-7f, 12.125f};
  return r;
}

// parse_height_raster's message for `bytes` (empty when it parses).
std::string error_of(const std::string& bytes) {
  try {
    parse_height_raster(bytes, "top.raster");
  } catch (const DataError& e) { return e.what(); }
  return "";
}

}  // namespace

TEST_CASE("height raster: round trip through a file, every value and NaN kept, same bytes") {
  const auto dir = canopy::test::fresh_dir("formats", "height_raster");
  const HeightRaster r = sample();
  const std::string path = (dir / "top.raster").string();
  write_height_raster(r, path);
  const std::string bytes = canopy::common::read_file(path);
  CHECK(is_height_raster(bytes));
  CHECK(bytes.rfind("canopy.height_raster 1\nwidth 3\nheight 2\npixel 0.070000000000000007\n", 0) == 0);
  CHECK(bytes.size() == bytes.find("data float32_le\n") + 16 + 6 * 4);
  const HeightRaster back = read_height_raster(path);
  CHECK(back.width == 3);
  CHECK(back.height == 2);
  CHECK(back.pixel == r.pixel);
  CHECK(back.x0 == r.x0);
  CHECK(back.y1 == r.y1);
  CHECK(back.box_x0 == r.box_x0);
  CHECK(back.box_y0 == r.box_y0);
  CHECK(back.box_x1 == r.box_x1);
  CHECK(back.box_y1 == r.box_y1);
  CHECK(back.density == r.density);
  REQUIRE(back.values.size() == 6);
  for (std::size_t i = 0; i < 6; ++i) {
    INFO(i);
    if (std::isnan(r.values[i]))
      CHECK(std::isnan(back.values[i]));
    else
      CHECK(back.values[i] == r.values[i]);
  }
  CHECK(back.at(1, 0) == 1.5f);
  CHECK(back.at(2, 1) == 12.125f);
  CHECK(serialize_height_raster(back) == bytes);
}

TEST_CASE("height raster: bad files are refused, naming the file and what is wrong") {
  const std::string good = serialize_height_raster(sample());
  CHECK(error_of(good).empty());
  auto with = [&good](const std::string& from, const std::string& to) {
    std::string b = good;
    const std::size_t at = b.find(from);
    REQUIRE(at != std::string::npos);
    b.replace(at, from.size(), to);
    return b;
  };
  const std::string data_at = "data float32_le\n";
  const std::size_t head = good.find(data_at) + data_at.size();
  struct Case {
    std::string bytes, says;
  };
  float inf = std::numeric_limits<float>::infinity();
  std::string with_inf = good;
  std::memcpy(&with_inf[head + 4], &inf, 4);
  const Case cases[] = {
      {"", "not a height raster"},
      {"P6\n3 2\n255\n", "not a height raster"},
      {with("raster 1\n", "raster 2\n"), "another version"},
      {with("width 3\n", "width 0\n"), "width 0 is not a whole number"},
      {with("width 3\n", "width 2.5\n"), "width 2.5 is not a whole number"},
      {with("height 2\n", "height 9000\n"), "height 9000 is not a whole number"},
      {with("width 3\nheight 2\n", "height 2\nwidth 3\n"), "line 'width ...' missing or out of order"},
      {with("pixel 0.070000000000000007\n", "pixel -1\n"), "pixel must be > 0"},
      {with("pixel 0.070000000000000007\n", "pixel nan\n"), "malformed 'pixel' line"},
      {with("pixel 0.070000000000000007\n", "pixel 0.07 m\n"), "malformed 'pixel' line"},
      {with("corner ", "corner 1 "), "malformed 'corner' line"},
      {with("points 500000.02500000002", "points 600000"), "x0 <= x1"},
      {with("density 400.25\n", "density -1\n"), "density must be >= 0"},
      {with("density 400.25\n", ""), "line 'density ...' missing or out of order"},
      {with("data float32_le\n", "data float64_le\n"), "data must be float32_le"},
      {good.substr(0, good.size() - 1), "need 24 bytes of data, the file holds 23 (truncated file)"},
      {good + std::string(4, '\0'), "need 24 bytes of data, the file holds 28"},
      {with_inf, "pixel 1 holds an infinite value"},
  };
  for (const Case& c : cases) {
    INFO(c.says);
    const std::string e = error_of(c.bytes);
    CHECK(e.find("top.raster") != std::string::npos);
    CHECK(e.find(c.says) != std::string::npos);
  }
  // A missing file: read_file names it.
  CHECK_THROWS_WITH(read_height_raster("/nonexistent/top.raster"),
                    Catch::Contains("/nonexistent/top.raster"));
}
