// detect's split of rows of parked vehicles (docs/decisions/detect.md §9) on hand-placed
// airborne-like tiles: the highest surface sampled from above at ~20 points/m².
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "detect/detect.h"
#include "detect/output.h"
#include "detect/rows.h"

using namespace canopy;

namespace {

// A car seen from above: 4.2 x 1.8 m; a 0.9 m bonnet at 0.85 m, a 0.5 m boot at 1.0 m, between
// them the cabin (1.4 m wide, 1.5 m high) with the body's shoulders (0.95 m) beside it.
struct Car {
  double x = 0, y = 0, heading = 0;  // centre; heading of the long axis (rad)
};

double car_height(const Car& c, double px, double py) {
  const double dx = px - c.x, dy = py - c.y;
  const double u = dx * std::cos(c.heading) + dy * std::sin(c.heading);
  const double v = -dx * std::sin(c.heading) + dy * std::cos(c.heading);
  if (std::abs(u) > 2.1 || std::abs(v) > 0.9) return 0;
  if (u > 1.2) return 0.85;            // bonnet
  if (u < -1.6) return 1.0;            // boot
  if (std::abs(v) > 0.7) return 0.95;  // shoulders beside the cabin
  return 1.5;
}

struct Box {
  double x0, x1, y0, y1, height;  // axis-aligned
};

// Points at `density` per m² uniformly over [x0, x1] x [y0, y1], each on the highest surface
// under it (ground at z = 100), Gaussian noise of 2 cm.
formats::PointCloud airborne(const std::vector<Car>& cars, const std::vector<Box>& boxes, double x0,
                             double x1, double y0, double y1, double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto n = std::size_t(density * (x1 - x0) * (y1 - y0));
  formats::PointCloud c;
  auto& x = c.add("x", formats::kFloat64);
  auto& y = c.add("y", formats::kFloat64);
  auto& z = c.add("z", formats::kFloat64);
  c.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double px = ux(rng), py = uy(rng);
    double h = 0;
    for (const Car& car : cars) h = std::max(h, car_height(car, px, py));
    for (const Box& b : boxes) {
      if (px >= b.x0 && px <= b.x1 && py >= b.y0 && py <= b.y1) h = std::max(h, b.height);
    }
    x[i] = px;
    y[i] = py;
    z[i] = 100 + h + noise(rng);
  }
  return c;
}

// The candidates whose centre lies within `r` of (x, y) in the top view.
int candidates_near(const detect::Result& r, double x, double y, double within) {
  int k = 0;
  for (const auto& c : r.candidates) k += std::hypot(c.to_tile(0, 3) - x, c.to_tile(1, 3) - y) <= within;
  return k;
}

detect::Params split(const char* how) {
  detect::Params p;
  p.split_rows_from_density = std::string(how) == "auto";
  p.split_rows = std::string(how) == "on";
  return p;
}

}  // namespace

TEST_CASE("a row of three cars bumper to bumper along a wall: one candidate per car") {
  // Cars 0.5 m apart along x, a 1 m wall 0.5 m beside them; 20 points/m² (the rule's voxel,
  // ~0.42 m, joins them all into one 15 m object).
  const std::vector<Car> cars = {{0, 0, 0}, {4.7, 0, 0}, {9.4, 0, 0}};
  const std::vector<Box> wall = {{-3, 12.5, 1.4, 1.65, 1.0}};
  const formats::PointCloud tile = airborne(cars, wall, -8, 18, -8, 8, 20, 26);
  const detect::Result r = detect::run(split("auto"), {&tile, "row"});
  REQUIRE(r.density.split_rows);
  CHECK(r.density.split_rows_by_rule);
  CHECK(r.density.rule < detect::kRowSplitDensity);
  CHECK(r.density.row_tolerance == Approx(detect::row_tolerance_for_density(r.density.rule)));
  CHECK(r.stats.row_splits >= 1);
  for (const Car& c : cars) {
    INFO("car at x = " << c.x);
    CHECK(candidates_near(r, c.x, c.y, 0.5) == 1);
  }
  for (const auto& c : r.candidates) {
    INFO("candidate " << c.to_tile(0, 3) << " " << c.to_tile(1, 3) << " " << c.length << " x " << c.width);
    CHECK(c.length < 5.0);
    CHECK(c.width < 2.3);
  }
  // The index records the rule's choice.
  const auto index = nlohmann::json::parse(detect::serialize_index(r, split("auto"), {}, "row.pcd", ""));
  CHECK(index["density"]["rule"]["split_rows"] == true);
  CHECK(index["density"]["rule"]["split_rows_from"] == "density");
  // Without the split (the ablation) the row stays one object: no car has its own candidate.
  const detect::Result off = detect::run(split("off"), {&tile, "row"});
  CHECK_FALSE(off.density.split_rows);
  CHECK(off.stats.row_splits == 0);
  int found = 0;
  for (const Car& c : cars) found += candidates_near(off, c.x, c.y, 0.5);
  CHECK(found < 3);
  const auto index_off = nlohmann::json::parse(detect::serialize_index(off, split("off"), {}, "row.pcd", ""));
  CHECK(index_off["density"]["rule"]["split_rows"] == false);
  CHECK(index_off["density"]["rule"]["split_rows_from"] == "option");
}

TEST_CASE("a nose-in row of five cars: one candidate per car") {
  std::vector<Car> cars;
  for (int k = 0; k < 5; ++k) cars.push_back({2.4 * k, 0, M_PI / 2});  // 0.6 m between the bodies
  const formats::PointCloud tile = airborne(cars, {}, -7, 17, -8, 8, 20, 27);
  const detect::Result r = detect::run(split("auto"), {&tile, "nose-in"});
  REQUIRE(r.density.split_rows);
  for (const Car& c : cars) {
    INFO("car at x = " << c.x);
    CHECK(candidates_near(r, c.x, c.y, 0.5) == 1);
  }
}

TEST_CASE("a 12 m flat-topped hedge or wall is not cut into car pieces") {
  // 12 x 1.6 m, 1.8 m high, no humps: one roof longer than any parked vehicle's.
  const std::vector<Box> hedge = {{0, 12, 0, 1.6, 1.8}};
  const formats::PointCloud tile = airborne({}, hedge, -8, 20, -8, 10, 20, 28);
  const detect::Result r = detect::run(split("on"), {&tile, "hedge"});
  CHECK(r.stats.row_splits == 0);
  REQUIRE(r.candidates.size() == 1);
  CHECK(r.candidates[0].length > 11.5);
}

TEST_CASE("dense tiles keep their objects: the split is off above the rule's density") {
  // 0.1 m spacing (100 points/m² on the ground and more on the objects): the rule says no.
  const std::vector<Car> cars = {{0, 0, 0}, {4.7, 0, 0}};
  const formats::PointCloud tile = airborne(cars, {}, -6, 10, -5, 5, 120, 29);
  const detect::Result r = detect::run(split("auto"), {&tile, "dense"});
  CHECK(r.density.rule >= detect::kRowSplitDensity);
  CHECK_FALSE(r.density.split_rows);
  CHECK(r.stats.row_splits == 0);
  CHECK(detect::row_tolerance_for_density(20) == Approx(1.5 / std::sqrt(20.0)));
  CHECK(detect::row_tolerance_for_density(1000) == 0.3);
  CHECK(detect::row_tolerance_for_density(2) == 0.6);
}

TEST_CASE("a 9 m flat-topped truck box sampled in scan lines is not cut at the lines") {
  // 9 x 2.5 m, 2.6 m high, seen from above in scan lines across it 0.36 m apart (0.125 m along
  // them: about 22 points/m²; the rule's voxel, ~0.4 m, joins them): each line is a part of the
  // roof band at the rule's tolerance (~0.32 m), and joined up to one roof's size (5 x 1.8 m)
  // they would make car roofs (this test fails with kRowHole = 0); but nothing lower lies
  // between the lines: sampling holes, one roof longer than a parked car's.
  std::mt19937 rng(30);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<Eigen::Vector3d> p;
  for (double x = -12; x <= 12; x += 0.36) {  // lines across the box
    for (double y = -10; y <= 10; y += 0.125) {
      const bool box = x >= -4.5 && x <= 4.5 && y >= -1.25 && y <= 1.25;
      p.emplace_back(x, y, 50 + (box ? 2.6 : 0.0) + noise(rng));
    }
  }
  formats::PointCloud tile;
  auto& cx = tile.add("x", formats::kFloat64);
  auto& cy = tile.add("y", formats::kFloat64);
  auto& cz = tile.add("z", formats::kFloat64);
  tile.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    cx[i] = p[i].x();
    cy[i] = p[i].y();
    cz[i] = p[i].z();
  }
  const detect::Result r = detect::run(split("auto"), {&tile, "truck"});
  REQUIRE(r.density.split_rows);
  CHECK(r.stats.row_splits == 0);
  REQUIRE(r.candidates.size() == 1);
  CHECK(r.candidates[0].length > 8.5);
}

TEST_CASE("a car with a low planter at its end: the planter is trimmed off (detect.md §12)") {
  // AHN3-like 11 points/m²: the rule's voxel (~0.57 m) joins the car and a 2 x 1.5 m planter
  // 0.8 m high, 0.5 m beyond its bonnet, into one 6.7 m object. Its roof band (1.1-3 m) holds one
  // roof, the cabin's: the planter, apart from the car in the top view and beyond the roof's
  // reach, is trimmed off and the car is a candidate of its own size.
  const std::vector<Car> cars = {{0, 0, 0}};
  const std::vector<Box> planter = {{2.6, 4.6, -0.75, 0.75, 0.8}};
  for (unsigned seed : {31u, 32u, 33u}) {
    INFO("seed " << seed);
    const formats::PointCloud tile = airborne(cars, planter, -8, 10, -7, 7, 11, seed);
    const detect::Result r = detect::run(split("auto"), {&tile, "planter"});
    REQUIRE(r.density.split_rows);
    CHECK(r.stats.trims == 1);
    CHECK(r.stats.row_splits == 0);
    REQUIRE(candidates_near(r, 0, 0, 0.4) == 1);
    for (const auto& c : r.candidates) {
      if (std::hypot(c.to_tile(0, 3), c.to_tile(1, 3)) > 0.4) continue;
      INFO("car's candidate " << c.length << " x " << c.width);
      CHECK(c.length > 3.8);
      CHECK(c.length < 5.0);  // a fragment of the planter within the roof's reach may stay
      CHECK(c.width < 2.1);
    }
    // Without the trim (the rule before) the car and the planter are one 6.7 m candidate.
    detect::Params before = split("auto");
    before.row_trim = 0;
    const detect::Result old = detect::run(before, {&tile, "planter"});
    CHECK(old.stats.trims == 0);
    CHECK(candidates_near(old, 0, 0, 0.4) == 0);
    REQUIRE(candidates_near(old, 1.25, 0, 0.5) == 1);
    for (const auto& c : old.candidates)
      CHECK((c.length > 6.2 || std::hypot(c.to_tile(0, 3) - 1.25, c.to_tile(1, 3)) > 0.5));
  }
}

TEST_CASE("--object-field: the car's crop marks the planter beyond the trim 3, the car's own points 1") {
  // The planter scene above with a 2.5 m margin, so that the car's crop holds the planter: the
  // field `object` is 1 exactly on the car's object (object_points of them), 3 on the planter's
  // points (the trim's leftover, a piece of its own after the trim, too small to be a candidate;
  // before detect.md §18 they were 2) and 0 on the ground. Off: no field, the same crop.
  const std::vector<Car> cars = {{0, 0, 0}};
  const std::vector<Box> planter = {{2.6, 4.6, -0.75, 0.75, 0.8}};
  for (unsigned seed : {31u, 32u, 33u}) {
    INFO("seed " << seed);
    const formats::PointCloud tile = airborne(cars, planter, -8, 10, -7, 7, 11, seed);
    detect::Params p = split("auto");
    p.margin = 2.5;
    const detect::Result off = detect::run(p, {&tile, "planter"});
    p.object_field = true;
    const detect::Result on = detect::run(p, {&tile, "planter"});
    REQUIRE(on.stats.trims == 1);
    REQUIRE(on.candidates.size() == off.candidates.size());
    bool seen_car = false;
    for (std::size_t k = 0; k < on.candidates.size(); ++k) {
      const detect::Candidate& c = on.candidates[k];
      const formats::PointCloud& crop = c.cloud;
      REQUIRE_FALSE(off.candidates[k].cloud.has("object"));
      REQUIRE(crop.has("object"));
      REQUIRE(crop.size() == off.candidates[k].cloud.size());
      CHECK(crop.col("x") == off.candidates[k].cloud.col("x"));
      const auto& o = crop.col("object");
      std::size_t ones = 0;
      for (double v : o) {
        CHECK((v == 0 || v == 1 || v == 2 || v == 3));
        ones += v == 1;
      }
      CHECK(ones == c.object_points);
      if (std::hypot(c.to_tile(0, 3), c.to_tile(1, 3)) > 0.4) continue;
      seen_car = true;
      // The crop's points back in the tile: the planter's top beyond the car's reach, the cabin's roof.
      std::size_t planter_pts = 0, planter_ones = 0, planter_threes = 0, roof = 0, roof_ones = 0;
      for (std::size_t i = 0; i < crop.size(); ++i) {
        const Eigen::Vector4d t =
            c.to_tile * Eigen::Vector4d(crop.col("x")[i], crop.col("y")[i], crop.col("z")[i], 1);
        const double h = t.z() - 100;
        if (t.x() > 3.0 && t.x() < 4.6 && std::abs(t.y()) < 0.75 && h > 0.6) {
          ++planter_pts;
          planter_ones += o[i] == 1;
          planter_threes += o[i] == 3;
        }
        if (std::abs(t.x()) < 1.0 && std::abs(t.y()) < 0.6 && h > 1.3) {
          ++roof;
          roof_ones += o[i] == 1;
        }
        if (h < 0.2) CHECK(o[i] == 0);  // the ground
      }
      INFO("planter " << planter_ones << " of " << planter_pts << ", roof " << roof_ones << " of " << roof);
      CHECK(planter_pts >= 10);
      CHECK(planter_ones == 0);
      CHECK(planter_threes == planter_pts);
      CHECK(roof >= 10);
      CHECK(roof_ones == roof);
    }
    CHECK(seen_car);
  }
}

TEST_CASE("--object-field: 3 marks exactly what the trim cut off the car, another car's points stay 2") {
  // A car-sized box (4.4 x 1.8 x 1.5 m) with a low box (3.0 x 0.6 m, 0.7 m high) 0.5 m beside its
  // long side, and a second car-sized box 1.5 m beyond its other side, at 11 points/m²: the
  // voxel (~0.57 m) joins the first box and the low box into one object 2.9 m wide (detect.md §9
  // looks at it; under 3 m, so the half-voxel split of two vehicles side by side does not), whose
  // roof band holds one roof: §12's trim cuts the low box off (beyond kTrimSide of the roof, below
  // the band). The second box is a cluster and candidate of its own.
  // With a 2.5 m margin the first car's crop holds all three: 1 on its own object, 3 on the low
  // box's points and nowhere else, 2 on the second car's, 0 on the ground; the second car's crop,
  // whose object no trim cut, has no 3. With row_trim 0 (no trim) no crop has a 3.
  const std::vector<Box> boxes = {
      {-2.2, 2.2, -0.9, 0.9, 1.5}, {-1.5, 1.5, 1.4, 2.0, 0.7}, {-2.2, 2.2, -4.2, -2.4, 1.5}};
  for (unsigned seed : {41u, 42u, 43u}) {
    INFO("seed " << seed);
    const formats::PointCloud tile = airborne({}, boxes, -8, 10, -9, 7, 11, seed);
    detect::Params p = split("auto");
    p.margin = 2.5;
    p.object_field = true;
    const detect::Result r = detect::run(p, {&tile, "beside"});
    REQUIRE(r.density.split_rows);
    REQUIRE(r.stats.trims == 1);
    REQUIRE(candidates_near(r, 0, 0, 0.4) == 1);
    REQUIRE(candidates_near(r, 0, -3.3, 0.4) == 1);
    for (const detect::Candidate& c : r.candidates) {
      const formats::PointCloud& crop = c.cloud;
      const auto& o = crop.col("object");
      const bool first = std::hypot(c.to_tile(0, 3), c.to_tile(1, 3)) <= 0.4;
      const bool second = std::hypot(c.to_tile(0, 3), c.to_tile(1, 3) + 3.3) <= 0.4;
      INFO("candidate " << c.id << " at " << c.to_tile(0, 3) << ", " << c.to_tile(1, 3));
      std::size_t low = 0, low_threes = 0, threes = 0, other = 0, other_twos = 0, roof = 0, roof_ones = 0;
      for (std::size_t i = 0; i < crop.size(); ++i) {
        const Eigen::Vector4d t =
            c.to_tile * Eigen::Vector4d(crop.col("x")[i], crop.col("y")[i], crop.col("z")[i], 1);
        const double h = t.z() - 100;
        threes += o[i] == 3;
        if (h < 0.2) CHECK(o[i] == 0);  // the ground
        if (std::abs(t.x()) < 1.5 && t.y() > 1.4 && t.y() < 2.0 && h > 0.5) {
          ++low;
          low_threes += o[i] == 3;
        }
        if (std::abs(t.x()) < 2.2 && std::abs(t.y()) < 0.9 && h > 1.3) {
          ++roof;
          roof_ones += o[i] == 1;
        }
        if (std::abs(t.x()) < 2.2 && t.y() > -4.2 && t.y() < -2.4 && h > 1.3) {
          ++other;
          other_twos += o[i] == 2;
        }
      }
      INFO("low box " << low_threes << " of " << low << ", 3s " << threes << ", second car " << other_twos
                      << " of " << other << ", roof " << roof_ones << " of " << roof);
      if (first) {
        CHECK(low >= 10);
        CHECK(low_threes == low);
        CHECK(threes == low);  // nothing but the low box is 3
        CHECK(other >= 5);
        CHECK(other_twos == other);
        CHECK(roof >= 10);
        CHECK(roof_ones == roof);
      } else {
        CHECK(threes == 0);
      }
      if (second) CHECK(roof >= 5);  // the second car's crop reaches the first car
    }
    // Without the trim the low box is the car's: no 3 anywhere.
    p.row_trim = 0;
    const detect::Result untrimmed = detect::run(p, {&tile, "beside"});
    CHECK(untrimmed.stats.trims == 0);
    for (const detect::Candidate& c : untrimmed.candidates)
      for (double v : c.cloud.col("object")) CHECK(v != 3);
  }
}

namespace {

// Seen from above at `density` (ground at z = 100, Gaussian noise of 2 cm in height): with `gap`,
// an 8 x 2.8 m body 1.6 m high (x in [-4, 4], y in [-1.4, 1.4]) and a 1.5 x 2 m bush as high
// 0.19 m beyond its end (x in [4.19, 5.69]), the ground seen between them; without, one 9.69 m
// body whose top returned nothing over x in [4, 4.19] (a windscreen, a dark panel), so nothing
// under that strip is seen either.
formats::PointCloud end_to_end(bool gap, double density, unsigned seed) {
  std::mt19937 rng(seed);
  const double x0 = -10, x1 = 12, y0 = -8, y1 = 8;
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto n = std::size_t(density * (x1 - x0) * (y1 - y0));
  formats::PointCloud c;
  auto& x = c.add("x", formats::kFloat64);
  auto& y = c.add("y", formats::kFloat64);
  auto& z = c.add("z", formats::kFloat64);
  std::vector<double> px, py, pz;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = ux(rng), b = uy(rng);
    const bool strip = a >= 4 && a < 4.19;
    if (!gap && strip && std::abs(b) <= 1.4) continue;  // the hole: no return
    const bool body = (a >= -4 && a < 4 && std::abs(b) <= 1.4) ||
                      (a >= 4.19 && a <= 5.69 && std::abs(b) <= (gap ? 1.0 : 1.4));
    px.push_back(a);
    py.push_back(b);
    pz.push_back(100 + (body ? 1.6 : 0) + noise(rng));
  }
  c.resize(px.size());
  for (std::size_t i = 0; i < px.size(); ++i) {
    x[i] = px[i];
    y[i] = py[i];
    z[i] = pz[i];
  }
  return c;
}

}  // namespace

TEST_CASE(
    "--end-gap: a vehicle and a bush at its end with the ground seen between them are cut apart; a hole over "
    "one body's top is not (detect.md §19)") {
  // 200 points/m²: the rule's voxel (0.2 m) joins body and bush across the 0.19 m gap into one
  // 9.69 m object; 0.05 m slabs, so the gap holds at least two empty slabs (0.1 m = half a voxel).
  for (unsigned seed : {41u, 42u, 43u}) {
    INFO("seed " << seed);
    const formats::PointCloud gap = end_to_end(true, 200, seed);
    detect::Params rule = split("auto");
    rule.end_gap = 0.5;
    const detect::Result r = detect::run(rule, {&gap, "gap"});
    // The 8 m vehicle alone, centred on it.
    REQUIRE(candidates_near(r, 0, 0, 0.3) == 1);
    for (const auto& c : r.candidates) {
      if (std::hypot(c.to_tile(0, 3), c.to_tile(1, 3)) > 0.3) continue;
      CHECK(c.length > 7.8);
      CHECK(c.length < 8.2);
    }
    // Without the cut (the default, the rule before) one 9.69 m candidate holds both.
    const detect::Result old = detect::run(split("auto"), {&gap, "gap"});
    CHECK(candidates_near(old, 0, 0, 0.3) == 0);
    REQUIRE(candidates_near(old, 0.85, 0, 0.3) == 1);
    for (const auto& c : old.candidates)
      if (std::hypot(c.to_tile(0, 3) - 0.85, c.to_tile(1, 3)) <= 0.3) CHECK(c.length > 9.5);

    // The same empty run with nothing seen under it: one body, not cut.
    const formats::PointCloud hole = end_to_end(false, 200, seed);
    const detect::Result h = detect::run(rule, {&hole, "hole"});
    REQUIRE(candidates_near(h, 0.85, 0, 0.3) == 1);
    for (const auto& c : h.candidates)
      if (std::hypot(c.to_tile(0, 3) - 0.85, c.to_tile(1, 3)) <= 0.3) CHECK(c.length > 9.5);
    CHECK(candidates_near(h, 0, 0, 0.3) == 0);
  }
  detect::Params bad;
  bad.end_gap = -1;
  CHECK_THROWS_WITH(detect::validate(bad), Catch::Contains("--end-gap"));
}
