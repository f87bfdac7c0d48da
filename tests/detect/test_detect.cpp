// detect on hand-placed synthetic tiles with known vehicle poses.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/math.h"
#include "canopy/common/error.h"
#include "candtruth/candtruth.h"
#include "detect/detect.h"
#include "detect/output.h"
#include "fixtures/detect_synth_tile.h"

using namespace canopy;
using detect_test::TileSpec;
using detect_test::VehicleSpec;

namespace {

// The candidates' ground truth as candtruth computes it from the labelled tile and the index
// detect would write (issue 30: detect itself holds no truth).
documents::CandidateTruth truth_of(const formats::PointCloud& tile, const detect::Result& r,
                                   const detect::Params& params = {}) {
  candtruth::Inputs in;
  in.tile = &tile;
  in.tile_name = "tile";
  in.index = detect::index_document(r, params, "tile", "");
  return candtruth::run(candtruth::Params{}, in);
}

// A candidate with its ground truth.
struct Found {
  const detect::Candidate* c = nullptr;
  documents::CandidateTruthRow truth;
};

// The candidates whose ground truth is vehicle `instance`.
std::vector<Found> candidates_of(const formats::PointCloud& tile, const detect::Result& r,
                                 std::uint32_t instance, const detect::Params& params = {}) {
  const documents::CandidateTruth t = truth_of(tile, r, params);
  std::vector<Found> out;
  for (std::size_t k = 0; k < r.candidates.size(); ++k) {
    if (t.candidates[k].instance == instance) out.push_back({&r.candidates[k], t.candidates[k]});
  }
  return out;
}

// Angle between the candidate's x axis and the vehicle's, folded to [0, 90] degrees.
double axis_error_deg(const detect::Candidate& c, const Eigen::Matrix3d& R) {
  const double cosang = std::abs(c.to_tile.block<3, 1>(0, 0).dot(R.col(0)));
  return std::acos(std::min(1.0, cosang)) * 180 / canopy::common::kPi;
}

// Every vehicle: exactly one candidate, centre within 0.3 m, axis within 5 degrees.
void check_poses(const TileSpec& s, const formats::PointCloud& tile, const detect::Result& r) {
  for (const auto& v : s.vehicles) {
    INFO("vehicle " << v.instance << " at " << v.x << ", " << v.y << " heading " << v.heading);
    const auto found = candidates_of(tile, r, v.instance);
    REQUIRE(found.size() == 1);
    const detect::Candidate& c = *found[0].c;
    const Eigen::Vector3d centre = c.to_tile.block<3, 1>(0, 3);
    const Eigen::Vector3d truth = detect_test::vehicle_centre(s, v);
    INFO("candidate " << c.id << " centre " << centre.transpose() << " truth " << truth.transpose()
                      << " length " << c.length << " width " << c.width << " height " << c.height);
    CHECK((centre - truth).norm() < 0.3);
    CHECK(axis_error_deg(c, detect_test::vehicle_rotation(s, v)) < 5.0);
    CHECK(c.length == Approx(v.length).margin(0.4));
    CHECK(c.width == Approx(v.width).margin(0.4));
    CHECK(c.height == Approx(v.height).margin(0.3));
    CHECK(found[0].truth.coverage > 0.95);
    CHECK(found[0].truth.crop_points == static_cast<std::int64_t>(c.cloud.size()));
    // The transform is rigid.
    const Eigen::Matrix3d R = c.to_tile.topLeftCorner<3, 3>();
    CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9);
    CHECK(R.determinant() == Approx(1.0));
  }
}

TileSpec three_vehicles(detect_test::Terrain terrain) {
  TileSpec s;
  s.terrain = terrain;
  s.seed = 5;
  s.vehicles = {{-8, -6, 0.5, 4.5, 1.8, 1.5, 7},   // a car
                {6, -9, -1.1, 8.0, 2.5, 3.0, 8},   // a truck
                {-2, 9, 2.9, 16.0, 2.5, 4.0, 9}};  // a tractor with trailer (heading ~166 deg)
  s.trees = {{10, 6, 3.0, 5.0, 11.0, 0.2}, {-14, 2, 2.5, 4.8, 9.0, 0.15}};
  s.bushes = {{13, -2, 1.0, 0.2, 1.6}};
  s.boulders = {{-12, -14, 0.7}};
  return s;
}

// A cloud of x y z (float64) points.
formats::PointCloud xyz_cloud(const std::vector<Eigen::Vector3d>& p) {
  formats::PointCloud c;
  auto& x = c.add("x", formats::kFloat64);
  auto& y = c.add("y", formats::kFloat64);
  auto& z = c.add("z", formats::kFloat64);
  c.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    x[i] = p[i].x();
    y[i] = p[i].y();
    z[i] = p[i].z();
  }
  return c;
}

}  // namespace

TEST_CASE("flat tile: every vehicle gets one candidate at its pose") {
  const TileSpec s = three_vehicles(detect_test::Terrain::kFlat);
  const auto tile = detect_test::make_tile(s);
  const detect::Result r = detect::run(detect::Params{}, {&tile, "flat"});
  check_poses(s, tile, r);
  const documents::CandidateTruth truth = truth_of(tile, r);
  REQUIRE(truth.instances.size() == 3);
  // No candidate in the crowns or on the boulder (too small).
  for (const auto& t : truth.candidates) CHECK(t.instance != 0);
  // The crops carry no truth (issue 30): a later stage cannot read it by accident.
  REQUIRE(tile.has("label"));
  REQUIRE(tile.has("instance"));
  for (const auto& c : r.candidates) {
    CHECK_FALSE(c.cloud.has("label"));
    CHECK_FALSE(c.cloud.has("instance"));
  }
}

TEST_CASE("15 degree slope: poses in the tilted ground frame") {
  TileSpec s = three_vehicles(detect_test::Terrain::kSlope);
  s.slope_deg = 15;
  const auto tile = detect_test::make_tile(s);
  const detect::Result r = detect::run(detect::Params{}, {&tile, "slope"});
  check_poses(s, tile, r);
  // The candidate frame's z is the ground normal (15 degrees from vertical).
  for (const auto& c : r.candidates) {
    const double tilt = std::acos(c.to_tile(2, 2)) * 180 / canopy::common::kPi;
    CHECK(tilt == Approx(15.0).margin(1.0));
  }
}

TEST_CASE("rolling ground at UTM magnitudes in float64") {
  TileSpec s = three_vehicles(detect_test::Terrain::kRolling);
  // A rigid 16 m box does not follow ground that rolls 2 m in 27 m (its ends would float a
  // metre up): a second car instead.
  s.vehicles[2] = {-2, 9, 2.9, 3.8, 1.7, 1.4, 9};
  s.offset = Eigen::Vector3d(500000.25, 4400000.75, 1234.5);
  s.noise = 0.008;
  const auto tile = detect_test::make_tile(s);
  REQUIRE(tile.type("x") == formats::kFloat64);
  const detect::Result r = detect::run(detect::Params{}, {&tile, "utm"});
  check_poses(s, tile, r);
  CHECK(std::abs(r.origin.x() - 500000) < 25);
  CHECK(std::abs(r.origin.y() - 4400000) < 25);
}

TEST_CASE("candidate clouds: local frame, ground at z = 0, every input field but the truth") {
  TileSpec s = three_vehicles(detect_test::Terrain::kSlope);
  auto tile = detect_test::make_tile(s);
  // The labels again under a name that is not a truth field: the crops carry it.
  tile.add("tag", tile.type("label")) = tile.col("label");
  const detect::Result r = detect::run(detect::Params{}, {&tile, "fields"});
  REQUIRE(!r.candidates.empty());
  for (const auto& c : r.candidates) {
    for (const auto& f : tile.names()) CHECK(c.cloud.has(f) == (f != "label" && f != "instance"));
    CHECK(c.cloud.size() > c.object_points);  // the crop includes the ground around it
    const auto& z = c.cloud.col("z");
    const auto& label = c.cloud.col("tag");
    const auto& sz = c.cloud.col("sensor_z");
    const auto& sx = c.cloud.col("sensor_x");
    std::size_t ground = 0;
    for (std::size_t i = 0; i < c.cloud.size(); ++i) {
      if (label[i] == formats::kLabelGround) {
        ++ground;
        CHECK(std::abs(z[i]) < 0.05);
      }
      // Sensor directions (0, 0, 1) in the tile, rotated into the tilted frame.
      CHECK(sz[i] == Approx(c.to_tile(2, 2)).margin(1e-6));
      CHECK(sx[i] == Approx(c.to_tile(2, 0)).margin(1e-6));
    }
    CHECK(ground > 50);
    // Local x is the long axis: the points span more along x than y.
    double xmax = 0, ymax = 0;
    const auto& x = c.cloud.col("x");
    const auto& y = c.cloud.col("y");
    for (std::size_t i = 0; i < c.cloud.size(); ++i) {
      if (label[i] != formats::kLabelTarget) continue;
      xmax = std::max(xmax, std::abs(x[i]));
      ymax = std::max(ymax, std::abs(y[i]));
    }
    CHECK(xmax > ymax);
    CHECK(xmax == Approx(c.length / 2).margin(0.05));
  }
}

TEST_CASE("two vehicles side by side give two candidates") {
  // Separated by a narrow gap (boxes), or touching (cars: body and cabin).
  for (const double gap : {0.3, 0.1, 0.0}) {
    INFO("gap " << gap);
    TileSpec s;
    s.seed = 9;
    const double h = 0.35;
    const Eigen::Vector2d across(-std::sin(h), std::cos(h));
    const double off = (1.8 + gap) / 2;
    const bool cabin = gap == 0.0;
    s.vehicles = {{across.x() * off, across.y() * off, h, 4.5, 1.8, 1.5, 1, cabin},
                  {-across.x() * off, -across.y() * off, h, 4.6, 1.8, 1.6, 2, cabin}};
    const auto tile = detect_test::make_tile(s);
    const detect::Result r = detect::run(detect::Params{}, {&tile, "pair"});
    CHECK(r.candidates.size() == 2);
    check_poses(s, tile, r);
  }
}

TEST_CASE("a vehicle under a bush is still a candidate") {
  TileSpec s;
  s.seed = 10;
  s.vehicles = {{0, 0, 0.2, 4.5, 1.8, 1.5, 3}};
  s.bushes = {{1.5, 0.8, 1.5, 0.3, 2.6}};
  const auto tile = detect_test::make_tile(s);
  const detect::Result r = detect::run(detect::Params{}, {&tile, "bush"});
  const auto found = candidates_of(tile, r, 3);
  REQUIRE(found.size() == 1);
  CHECK(found[0].truth.coverage > 0.9);
  CHECK((found[0].c->to_tile.block<3, 1>(0, 3) - detect_test::vehicle_centre(s, s.vehicles[0])).norm() < 1.5);
}

TEST_CASE("a tile with no vehicle gives no candidate") {
  SECTION("trees, bushes, a boulder") {
    TileSpec s = three_vehicles(detect_test::Terrain::kRolling);
    s.vehicles.clear();
    const formats::PointCloud tile = detect_test::make_tile(s);
    const detect::Result r = detect::run(detect::Params{}, {&tile, "forest"});
    CHECK(r.candidates.empty());
  }
  SECTION("only ground, sloped") {
    TileSpec s;
    s.terrain = detect_test::Terrain::kSlope;
    s.noise = 0.032;
    const formats::PointCloud tile = detect_test::make_tile(s);
    const detect::Result r = detect::run(detect::Params{}, {&tile, "ground"});
    CHECK(r.candidates.empty());
    // Every point is ground.
    for (auto c : r.classes) CHECK(c == detect::kClassGround);
  }
}

TEST_CASE("height above ground on a slope") {
  TileSpec s;
  s.terrain = detect_test::Terrain::kSlope;
  s.trees = {{0, 0, 3, 5, 11, 0.2}};
  s.offset = Eigen::Vector3d(0, 0, 250);
  const auto tile = detect_test::make_tile(s);
  const detect::Result r = detect::run(detect::Params{}, {&tile, "hag"});
  const auto& x = tile.col("x");
  const auto& y = tile.col("y");
  const auto& z = tile.col("z");
  for (std::size_t i = 0; i < tile.size(); i += 7) {
    const double truth = z[i] - 250 - detect_test::ground_z(s, x[i], y[i]);
    INFO("point " << x[i] << ", " << y[i] << ", " << z[i] << " label " << tile.col("label")[i]);
    CHECK(r.height[i] == Approx(truth).margin(0.05));
  }
}

TEST_CASE("bad tiles") {
  SECTION("no points") {
    formats::PointCloud empty;
    empty.add("x");
    empty.add("y");
    empty.add("z");
    CHECK_THROWS_AS(detect::run(detect::Params{}, {&empty, "empty.pcd"}), common::DataError);
    CHECK_THROWS_WITH(detect::run(detect::Params{}, {&empty, "empty.pcd"}), Catch::Contains("no points"));
  }
  SECTION("no coordinates") {
    formats::PointCloud c;
    c.add("intensity");
    c.resize(3);
    CHECK_THROWS_AS(detect::run(detect::Params{}, {&c, "odd.pcd"}), common::DataError);
  }
  SECTION("float32 coordinates at UTM magnitudes") {
    TileSpec s;
    s.half_extent = 5;
    s.offset = Eigen::Vector3d(500000, 4400000, 100);
    s.float64 = false;
    const formats::PointCloud tile = detect_test::make_tile(s);
    CHECK_THROWS_WITH(detect::run(detect::Params{}, {&tile, "utm32.pcd"}),
                      Catch::Contains("float32") && Catch::Contains("float64"));
  }
  SECTION("an extent too large for the DTM") {
    formats::PointCloud c;
    auto& x = c.add("x", formats::kFloat64);
    c.add("y", formats::kFloat64);
    c.add("z", formats::kFloat64);
    c.resize(2);
    x[1] = 1e6;
    c.col("y")[1] = 1e6;
    CHECK_THROWS_WITH(detect::run(detect::Params{}, {&c, "far.pcd"}), Catch::Contains("DTM cells"));
  }
  SECTION("bad parameters") {
    detect::Params p;
    p.max_width = 0.5;
    CHECK_THROWS_AS(detect::validate(p), common::UsageError);
    p = detect::Params{};
    p.voxel = 1e-6;
    CHECK_THROWS_WITH(detect::validate(p), Catch::Contains("--voxel must be in [1 mm, 100 m]"));
  }
  SECTION("a few points spread wide: refused by the cells per point, not run for minutes") {
    formats::PointCloud c = xyz_cloud({{0, 0, 0}, {1200, 1200, 3}, {500, 700, 1}});
    detect::Params half_metre;  // as --cell 0.5 given (the density rule would pick 2 m cells)
    half_metre.cell_from_density = false;
    CHECK_THROWS_WITH(detect::run(half_metre, {&c, "sparse.pcd"}),
                      Catch::Contains("its 3 points spread over 1200 m x 1200 m: 5.76e+06 DTM cells") &&
                          Catch::Contains("(4e+06 + 16 per point = 4e+06)"));
  }
  SECTION("objects farther apart than 2^21 voxels (item 10: --voxel named)") {
    // A 2.5 km strip of ground (0.5 m grid) with a 1.5 m box at each end: the object band
    // spans 2480 m, 2.48e6 voxels of 1 mm.
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i <= 5000; ++i)
      for (int j = 0; j <= 4; ++j) p.emplace_back(i * 0.5, j * 0.5, 0.0);
    for (const double x0 : {10.0, 2490.0})
      for (int i = 0; i < 10; ++i)
        for (int k = 0; k < 10; ++k) p.emplace_back(x0 + i * 0.1, 1.0, 0.6 + k * 0.1);
    detect::Params params;
    params.voxel = 0.001;
    params.voxel_from_density = false;  // as --voxel given
    const formats::PointCloud tile = xyz_cloud(p);
    CHECK_THROWS_WITH(
        detect::run(params, {&tile, "strip.pcd"}),
        Catch::Contains("strip.pcd: the points between --min-object-height and --max-height span") &&
            Catch::Contains("clustering voxels along an axis of --voxel 0.001 m: raise --voxel"));
  }
}

TEST_CASE("a sparse tile: the DTM relaxed only near its points stays on the terrain") {
  // 7 x 7 patches of 2 x 2 m (0.25 m grid, 3136 points) every 100 m on the plane
  // z = 0.05 x + 0.02 y: 1.45e6 DTM cells, far more than 16 per point, so only the cells within
  // 2 cells of a point are relaxed; every point is ground, its height within 2 cm of 0.
  std::vector<Eigen::Vector3d> p;
  for (int a = 0; a < 7; ++a)
    for (int b = 0; b < 7; ++b)
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
          const double x = a * 100.0 + i * 0.25, y = b * 100.0 + j * 0.25;
          p.emplace_back(x, y, 0.05 * x + 0.02 * y);
        }
  const formats::PointCloud tile = xyz_cloud(p);
  detect::Params fixed_cell;
  fixed_cell.cell_from_density = false;  // as --cell given: the 0.5 m DTM this case is about
  const detect::Result r = detect::run(fixed_cell, {&tile, "patches.pcd"});
  CHECK(r.stats.cells == 1204 * 1204);  // 601.75 m / 0.5 m, + 1
  CHECK(r.candidates.empty());
  CHECK(r.stats.ground_points == p.size());
  double worst = 0;
  for (const float h : r.height) worst = std::max(worst, double(std::abs(h)));
  CHECK(worst < 0.02);
}

TEST_CASE("same tile -> same index") {
  TileSpec s = three_vehicles(detect_test::Terrain::kFlat);
  s.noise = 0.008;
  const auto tile = detect_test::make_tile(s);
  formats::Provenance prov{"detect", "test", {}, {"t.pcd"}};
  const std::string a = detect::serialize_index(detect::run({}, {&tile, "a"}), {}, prov, "t.pcd", "");
  const std::string b = detect::serialize_index(detect::run({}, {&tile, "b"}), {}, prov, "t.pcd", "");
  CHECK(a == b);
  detect::Params euclid;
  euclid.clustering = detect::Clustering::kEuclidean;
  CHECK(detect::serialize_index(detect::run(euclid, {&tile, "c"}), {}, prov, "t.pcd", "") == a);
}

TEST_CASE("a tank-wide vehicle (3.54 m, body and turret) is one candidate") {
  for (const auto terrain : {detect_test::Terrain::kFlat, detect_test::Terrain::kSlope}) {
    TileSpec s;
    s.half_extent = 12;
    s.terrain = terrain;
    s.seed = 14;
    s.vehicles = {{1, -2, 0.3, 6.9, 3.54, 2.4, 5, true}};
    const auto tile = detect_test::make_tile(s);
    const detect::Result r = detect::run(detect::Params{}, {&tile, "tank"});
    CHECK(r.candidates.size() == 1);
    check_poses(s, tile, r);
  }
}

// Shape test (--min-planarity): a group of touching bushes and a young tree whose whole crown
// lies in the object band are vehicle-sized objects; they pass the footprint and height
// tests (shape test off) but are not made of planes.
TEST_CASE("bush groups and low crowns are rejected by the shape test, vehicles are not") {
  for (const double noise : {0.0, 0.032}) {
    INFO("noise " << noise);
    TileSpec s;
    s.half_extent = 15;
    s.seed = 41;
    s.noise = noise;
    s.terrain = detect_test::Terrain::kSlope;
    s.slope_deg = 8;
    // Three bushes in a row, touching: a 5.2 x 2 m group, 1.8 m high.
    s.bushes = {{-8, 6, 1.0, 0.2, 1.8}, {-6.4, 6.2, 1.0, 0.25, 1.9}, {-4.8, 6.0, 1.0, 0.2, 1.7}};
    // A young tree: crown from 1.5 to 4.2 m, 3.2 m across, all below --max-height.
    s.trees = {{6, 7, 1.6, 1.5, 4.2, 0.1}};
    s.vehicles = {{-2, -6, 0.4, 4.5, 1.8, 1.5, 1, true}, {7, -5, -0.8, 7.0, 2.5, 3.0, 2}};
    const auto tile = detect_test::make_tile(s);
    detect::Params off;
    off.min_planarity = 0;
    off.planarity_from_density = false;  // as --min-planarity given
    const detect::Result all = detect::run(off, {&tile, "off"});
    const documents::CandidateTruth truth = truth_of(tile, all, off);
    std::size_t vegetation = 0;
    for (std::size_t k = 0; k < all.candidates.size(); ++k) {
      const detect::Candidate& c = all.candidates[k];
      INFO("candidate " << c.id << " " << c.length << " x " << c.width << " x " << c.height << " planarity "
                        << c.planarity << " truth " << truth.candidates[k].instance);
      if (truth.candidates[k].instance == 0) {
        ++vegetation;
        CHECK(c.planarity < 0.1);
        CHECK(c.planar_area < 0.5);
      } else {
        CHECK(c.planarity > 0.3);
        CHECK(c.planar_area > 5);
      }
    }
    CHECK(vegetation == 2);  // the bush group and the young tree
    const detect::Result r = detect::run(detect::Params{}, {&tile, "on"});
    CHECK(r.candidates.size() == 2);
    CHECK(r.stats.rejected_shape == 2);
    check_poses(s, tile, r);
  }
}

// A vehicle under bushes: the bush points join its object and lower its planar share below
// --min-planarity, but the planar area of its panels keeps it.
TEST_CASE("a vehicle half under bushes passes the shape test") {
  TileSpec s;
  s.half_extent = 12;
  s.seed = 42;
  s.noise = 0.032;
  s.vehicles = {{0, 0, 0.2, 4.5, 1.8, 1.5, 3, true}};
  // Two bushes over the car's front half and side, reaching above its roof.
  s.bushes = {{1.3, 0.5, 1.3, 0.3, 2.4}, {0.2, -1.2, 1.2, 0.2, 2.2}};
  const auto tile = detect_test::make_tile(s);
  const detect::Result r = detect::run(detect::Params{}, {&tile, "bushes"});
  const auto found = candidates_of(tile, r, 3);
  REQUIRE(found.size() == 1);
  INFO("planarity " << found[0].c->planarity << " area " << found[0].c->planar_area << " purity "
                    << found[0].truth.purity);
  CHECK(found[0].truth.purity < 0.8);  // the bushes are in the object
  CHECK(found[0].c->planarity < detect::Params{}.min_planarity);
  CHECK(found[0].c->planar_area >= detect::Params{}.min_planar_area);
  CHECK(found[0].truth.coverage > 0.9);
  // The share alone would lose it.
  detect::Params share_only;
  share_only.min_planar_area = 1e9;
  CHECK(candidates_of(tile, detect::run(share_only, {&tile, "bushes"}), 3).empty());
}

TEST_CASE("the DTM cell follows the density: a closed canopy over sparse ground returns") {
  // The rule's values: 24 returns per cell, between 0.5 m (dense end) and 2 m.
  CHECK(detect::cell_for_density(1000) == 0.5);
  CHECK(detect::cell_for_density(96) == Approx(0.5));
  CHECK(detect::cell_for_density(24) == Approx(1.0));
  CHECK(detect::cell_for_density(6) == Approx(2.0));
  CHECK(detect::cell_for_density(1) == 2.0);
  // 40 x 40 m: ground returns at 0.8 per m2 under a canopy layer (14-16 m) of 22 per m2, as under
  // a closed tropical crown (forest_lareunion: 18% of the 0.5 m cells hold ground). With 0.5 m
  // cells only about 18% of the occupied cells reach the ground (refused: below 20%); the rule's
  // 1 m cell (density ~23 per m2) holds 0.8 ground returns on average, so most cells have one.
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> u(0.0, 40.0), crown(14.0, 16.0);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 1280; ++i) p.emplace_back(u(rng), u(rng), 0.0);
  for (int i = 0; i < 35200; ++i) p.emplace_back(u(rng), u(rng), crown(rng));
  const formats::PointCloud tile = xyz_cloud(p);
  detect::Params half_metre;
  half_metre.cell_from_density = false;
  CHECK_THROWS_WITH(detect::run(half_metre, {&tile, "canopy.pcd"}),
                    Catch::Contains("canopy.pcd: found ground in only") && Catch::Contains("0.5 m cells"));
  const detect::Result r = detect::run(detect::Params{}, {&tile, "canopy.pcd"});
  CHECK(r.density.cell_by_rule);
  CHECK(r.density.cell == Approx(std::sqrt(24.0 / r.density.all)));
  CHECK(r.density.cell > 0.95);
  CHECK(r.density.cell < 1.1);
  CHECK(r.candidates.empty());
  // The index names the cell applied, not the option's default.
  const auto index = nlohmann::json::parse(detect::serialize_index(r, detect::Params{}, {}, "canopy.pcd", ""));
  CHECK(index["ground"]["cell"].get<double>() == r.density.cell);
  CHECK(index["density"]["rule"]["dtm_cell_from"] == "density");
  // The ground returns are the ground: height above the DTM within 5 cm.
  double worst = 0;
  for (std::size_t i = 0; i < 1280; ++i) worst = std::max(worst, double(std::abs(r.height[i])));
  CHECK(worst < 0.05);
}
