// rangetrace tiles: hand-placed scenes with known geometry, rendered small (coarse pixels,
// few images) so the suite stays fast.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <fstream>
#include <string>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/points_io.h"
#include "rangetrace/tile.h"
#include "support/cli.h"

using namespace canopy;
using namespace canopy::rangetrace;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

const double kDeg = canopy::common::kDegree;

void write_text(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string slurp(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

// A box vehicle L x W x H (world: long along x), declared in POV-Ray's frame (y up).
std::string box_model(double l, double w, double h) {
  return "#declare Vehicle = box { <" + std::to_string(-l / 2) + ", 0, " + std::to_string(-w / 2) + ">, <" +
         std::to_string(l / 2) + ", " + std::to_string(h) + ", " + std::to_string(w / 2) + "> }\n";
}

Params small_params(std::uint64_t seed = 1) {
  Params p;
  p.seed = seed;
  p.threads = 2;
  return p;
}

// Distance from local point q to the surface of the box [-hl, hl] x [-hw, hw] x [0, h].
double box_distance(const Vector3d& q, double hl, double hw, double h) {
  const Vector3d c(0, 0, h / 2), half(hl, hw, h / 2);
  const Vector3d d = (q - c).cwiseAbs() - half;
  if ((d.array() <= 0).all()) return -d.maxCoeff();
  return d.cwiseMax(0.0).norm();
}

struct Rows {
  std::vector<Vector3d> p;
  std::vector<std::uint32_t> label;
  std::vector<int> instance;
};

Rows rows(const formats::PointCloud& c) {
  Rows r;
  for (std::size_t i = 0; i < c.size(); ++i) {
    r.p.emplace_back(c.col("x")[i], c.col("y")[i], c.col("z")[i]);
    r.label.push_back(static_cast<std::uint32_t>(c.col("label")[i]));
    r.instance.push_back(static_cast<int>(c.col("instance")[i]));
  }
  return r;
}

}  // namespace

TEST_CASE("tile recipes: keys, defaults and bounds, errors name the line") {
  const SceneRecipe s = parse_scene(
      "extent = 30m 20m\nterrain = slope 10deg 45deg\n"
      "vehicles = random 3 from sedan,tank\nlooks = 75deg/90deg 90deg\n",
      "t.scene");
  REQUIRE(s.tile);
  CHECK(s.tile->extent_x == 30);
  CHECK(s.tile->extent_y == 20);
  CHECK(s.tile->terrain == Terrain::kSlope);
  CHECK(s.tile->slope == Approx(10 * kDeg));
  CHECK(s.tile->random_vehicles == 3);
  CHECK(s.tile->random_models == std::vector<std::string>{"sedan", "tank"});
  REQUIRE(s.tile->looks.size() == 2);
  CHECK(s.tile->looks[0].azimuth == Approx(90 * kDeg));
  CHECK(s.tile->looks[1].elevation == Approx(90 * kDeg));
  CHECK(s.tile->trees_per_ha == 600);  // the default forest
  CHECK(s.tile->hide == -1);           // 2 with trees, 0 with `trees = 0`

  auto fails = [](const std::string& text, const std::string& what) {
    CHECK_THROWS_WITH(parse_scene(text, "bad.scene"), Catch::Contains("bad.scene") && Catch::Contains(what));
  };
  fails("extent = 40m\nfoo = 1\n", "line 2: unknown key 'foo'");
  fails("extent = 140m\n", "line 1: extent must lie in [5 m, 100 m]");
  fails("terrain = slope 20deg\n", "line 1: slope must lie in [0, 15 deg]");
  fails("extent = 40m\nviews = circle 12 75\n", "line 2: 'views' is a single-vehicle key");
  fails("foliage_count = 10\nextent = 40m\n", "line 2: 'extent' is a tile key");
  fails("extent = 20m\nvehicle = sedan 25 3 0\n", "line 2: vehicle 'sedan' lies outside the tile");
  fails("vehicles = random 100000 from sedan\n", "line 1: count 100000 exceeds the limit");
  fails("clutter = piano 2\n", "line 1: unknown clutter kind 'piano'");
  fails("trees = 1e9\n", "line 1: trees per hectare must lie in [0, 2000]");
  // Counts in the single-vehicle recipes are bounded too (a 29-byte recipe asked for 4 GB).
  fails("views = circle 2000000000 75\n", "line 1: 'views': 2000000000 exceeds the limit of 1000");
  fails("foliage_count = 2000000000\nviews = circle 2 75\n", "line 1: 'foliage_count': 2000000000 exceeds");
  fails("foliage_count = 2e9\nviews = circle 2 75\n", "line 1: '2e9' is not a count");
}

TEST_CASE("tile: per-instance labels lie inside each posed footprint and nowhere else") {
  // Models in a directory whose name holds a double quote (it once broke POV-Ray's #include
  // strings); recipe paths are relative to the recipe's directory.
  const auto dir = test::fresh_dir("rangetrace", "tile_hand");
  const auto models = dir / "my\"models";
  std::filesystem::create_directories(models);
  write_text(models / "long.inc", box_model(4.0, 2.0, 1.5));
  write_text(models / "short.inc", box_model(3.0, 1.6, 2.0));
  write_text(dir / "hand.scene",
             "# two vehicles, one tree, one boulder\nextent = 16m 12m\ntrees = 0\nbushes = 0\nhide = 0\n"
             "vehicle = my\"models/long.inc 4.5 4 30deg\n"
             "vehicle = my\"models/short.inc 11.5 7.5 -70deg\n"
             "tree = broadleaf 9 2.2 12m\nobject = boulder 3 9.5 0\nflight_lines = 1\n"
             "headings = 0\nlooks = 75deg/0 60deg/200deg 90deg\nspacing = 80mm\n"
             "canopy_spacing = 80mm\n");
  const SceneRecipe s = load_scene((dir / "hand.scene").string());
  Tile tile = build_tile(*s.tile, "hand.scene", small_params(5));
  REQUIRE(tile.vehicles.size() == 2);
  REQUIRE(tile.objects.size() == 1);
  REQUIRE(tile.trees.size() == 1);
  const TileScan scan = run_tile(&tile, small_params(5));
  const Rows r = rows(scan.cloud);
  REQUIRE(scan.points_per_view.size() == 3);
  int count[5] = {0, 0, 0, 0, 0};
  int per_instance[3] = {0, 0, 0};
  for (std::size_t i = 0; i < r.p.size(); ++i) {
    REQUIRE(r.label[i] <= 4);
    ++count[r.label[i]];
    const Vector3d& p = r.p[i];
    CHECK(p.x() >= 0);
    CHECK(p.x() <= 16);
    if (r.label[i] == formats::kLabelGround) CHECK(std::abs(p.z()) < 5e-4);
    if (r.label[i] != formats::kLabelTarget) {
      CHECK(r.instance[i] == 0);
      continue;
    }
    REQUIRE(r.instance[i] >= 1);
    REQUIRE(r.instance[i] <= 2);
    ++per_instance[r.instance[i]];
    const PlacedVehicle& v = tile.vehicles[r.instance[i] - 1];
    // Inside its own footprint (1 mm slack for points on the sides), outside the other's.
    std::array<Vector2d, 4> grown = v.footprint;
    const Vector2d c = (v.footprint[0] + v.footprint[2]) / 2;
    for (auto& q : grown) q += (q - c).normalized() * 1e-3;
    CHECK(in_polygon(p.head<2>(), grown));
    CHECK_FALSE(in_polygon(p.head<2>(), tile.vehicles[2 - r.instance[i]].footprint));
    // And on the posed box's surface: the decoded coordinates are exact to well under 1 mm.
    const Vector3d local = v.pose.r.transpose() * (p - v.pose.anchor);
    CHECK(box_distance(local, v.size.x() / 2, v.size.y() / 2, v.size.z()) < 5e-4);
  }
  CHECK(per_instance[1] > 300);
  CHECK(per_instance[2] > 300);
  CHECK(count[formats::kLabelFoliage] > 300);
  CHECK(count[formats::kLabelClutter] > 50);
  CHECK(count[formats::kLabelGround] > 5000);
  CHECK(tile.vehicles[0].size.isApprox(Vector3d(4, 2, 1.5), 1e-6));
  // The footprints of unpitched boxes are the rotated L x W rectangles.
  CHECK((tile.vehicles[0].footprint[1] - tile.vehicles[0].footprint[0]).norm() == Approx(4.0));
  CHECK((tile.vehicles[0].footprint[2] - tile.vehicles[0].footprint[1]).norm() == Approx(2.0));
  CHECK(tile.vehicles[0].canopy_cover == 0.0);
}

TEST_CASE("tile: canopy cover against an opaque disc of known area") {
  // Vehicle 1 (4 x 2 m = 8 m^2) under a disc of radius 0.8 m well inside its footprint;
  // vehicle 2 under a disc that covers it whole; vehicle 3 in the open.
  const auto dir = test::fresh_dir("rangetrace", "tile_cover");
  write_text(dir / "box.inc", box_model(4.0, 2.0, 1.5));
  write_text(dir / "cover.scene",
             "extent = 20m 10m\ntrees = 0\nbushes = 0\nhide = 0\nvehicle = box.inc 4 5 0\n"
             "vehicle = box.inc 10 5 90deg\nvehicle = box.inc 16 5 45deg\n"
             "canopy_disc = 4.3 5.2 6m 0.8m\ncanopy_disc = 10 5 7m 3m\n"
             "canopy_spacing = 10mm\nspacing = 0.25m\nflight_lines = 1\nheadings = 0\nlooks = 90deg\n");
  const SceneRecipe s = load_scene((dir / "cover.scene").string());
  Tile tile = build_tile(*s.tile, "cover.scene", small_params());
  run_tile(&tile, small_params());
  REQUIRE(tile.vehicles.size() == 3);
  const double want = canopy::common::kPi * 0.8 * 0.8 / 8.0;  // 0.2513
  CHECK(tile.vehicles[0].canopy_cover == Approx(want).margin(0.004));
  CHECK(tile.vehicles[1].canopy_cover == 1.0);
  CHECK(tile.vehicles[2].canopy_cover == 0.0);
}

TEST_CASE("tile: ground points lie on the slope; vehicles pitch and roll with it") {
  const auto dir = test::fresh_dir("rangetrace", "tile_slope");
  write_text(dir / "box.inc", box_model(4.0, 2.0, 1.5));
  // Ascent toward azimuth 30 deg; vehicle 1 faces uphill (pitch nose up), vehicle 2 across.
  write_text(dir / "slope.scene",
             "extent = 24m 16m\nterrain = slope 12deg 30deg\ntrees = 0\nbushes = 0\nhide = 0\n"
             "vehicle = box.inc 6 8 30deg\nvehicle = box.inc 17 8 120deg\nspacing = 0.1m\n"
             "flight_lines = 1\nheadings = 90deg\nlooks = 70deg/0 70deg/180deg\ncanopy_spacing = 0.2m\n");
  const SceneRecipe s = load_scene((dir / "slope.scene").string());
  Tile tile = build_tile(*s.tile, "slope.scene", small_params());
  const TileScan scan = run_tile(&tile, small_params());
  const Rows r = rows(scan.cloud);
  const double g = std::tan(12 * kDeg);
  const Vector2d up_dir(std::cos(30 * kDeg), std::sin(30 * kDeg));
  int ground = 0, vehicle = 0;
  for (std::size_t i = 0; i < r.p.size(); ++i) {
    const Vector3d& p = r.p[i];
    if (r.label[i] == formats::kLabelGround) {
      ++ground;
      const double plane = g * (p.head<2>() - Vector2d(12, 8)).dot(up_dir);
      CHECK(std::abs(p.z() - plane) < 5e-4);
    } else if (r.label[i] == formats::kLabelTarget) {
      ++vehicle;
      const PlacedVehicle& v = tile.vehicles[r.instance[i] - 1];
      const Vector3d local = v.pose.r.transpose() * (p - v.pose.anchor);
      CHECK(box_distance(local, 2.0, 1.0, 1.5) < 5e-4);
    }
  }
  CHECK(ground > 10000);
  CHECK(vehicle > 500);
  // Facing uphill: nose up by the slope angle (negative pitch about the left axis), no roll.
  CHECK(tile.vehicles[0].pose.pitch == Approx(-12 * kDeg).margin(1e-9));
  CHECK(tile.vehicles[0].pose.roll == Approx(0).margin(1e-9));
  CHECK(tile.vehicles[0].pose.heading == Approx(30 * kDeg));
  // Across the slope (uphill on its right): rolled by the slope angle, no pitch.
  CHECK(tile.vehicles[1].pose.pitch == Approx(0).margin(1e-9));
  CHECK(std::abs(tile.vehicles[1].pose.roll) == Approx(12 * kDeg).margin(1e-9));
  // Standing on the plane: the anchor is on the ground.
  for (const auto& v : tile.vehicles) {
    const double plane = g * (v.pose.anchor.head<2>() - Vector2d(12, 8)).dot(up_dir);
    CHECK(v.pose.anchor.z() == Approx(plane).margin(1e-9));
  }
}

TEST_CASE("tile: rolling terrain stays within +-2 m and the ground points lie on it") {
  SceneRecipe s = parse_scene(
      "extent = 14m\nterrain = rolling 2m 10m\ntrees = 0\nbushes = 0\nhide = 0\n"
      "flight_lines = 1\nheadings = 0\nlooks = 80deg/0\nspacing = 0.15m\n"
      "canopy_spacing = 0.3m\n",
      "rolling.scene");
  Tile tile = build_tile(*s.tile, "rolling.scene", small_params(9));
  const TerrainModel terrain(*s.tile, 9);
  CHECK(terrain.lo() >= -2.0 - 1e-9);
  CHECK(terrain.hi() <= 2.0 + 1e-9);
  CHECK(terrain.hi() - terrain.lo() > 1.0);
  const Rows r = rows(run_tile(&tile, small_params(9)).cloud);
  REQUIRE(r.p.size() > 3000);
  double worst = 0;
  for (const auto& p : r.p) worst = std::max(worst, std::abs(p.z() - terrain.height(p.x(), p.y())));
  CHECK(worst < 1e-3);
}

TEST_CASE("tile: same seed gives a byte-identical scan, another seed another forest") {
  SceneRecipe s = parse_scene(
      "extent = 12m\ntrees = 400\nbushes = 300\nclutter = logs 1\n"
      "vehicles = random 1 from sedan\nflight_lines = 1\nheadings = 0\n"
      "looks = 75deg/0\nspacing = 0.2m\ncanopy_spacing = 0.2m\n",
      "forest.scene");
  auto scan = [&](std::uint64_t seed, int threads) {
    Params p = small_params(seed);
    p.threads = threads;
    Tile tile = build_tile(*s.tile, "forest.scene", p);
    return formats::serialize_pcd(run_tile(&tile, p).cloud);
  };
  const std::string a = scan(4, 2);
  CHECK(a == scan(4, 1));
  CHECK(a != scan(5, 2));
}

TEST_CASE("tile: images traced in windows over strip and tile give the same scan and cover") {
  // Two flight lines with 20% overlap at 30 deg: each strip runs past the tile's edges, so the
  // windows leave out rows and columns that held only points append_view drops.
  SceneRecipe s = parse_scene(
      "extent = 16m 12m\nterrain = rolling 1m 10m\ntrees = 300\nbushes = 200\nclutter = logs 1\n"
      "vehicles = random 2 from sedan\nflight_lines = 2\nheadings = 30deg\n"
      "looks = 75deg/0 60deg/180deg\nspacing = 0.1m\ncanopy_spacing = 0.2m\n",
      "windows.scene");
  Params p = small_params(7);
  Tile tile = build_tile(*s.tile, "windows.scene", p);
  const std::vector<TileView> views = tile_views(tile);
  const double zlo = TerrainModel(tile.recipe, tile.seed).lo() - 1, zhi = tile.top + 1;
  double traced = 0, pixels = 0;
  for (const TileView& v : views) {
    const PixelWindow w = strip_window(v, tile.recipe, zlo, zhi);
    traced += double(w.col1 - w.col0 + 1) * (w.row1 - w.row0 + 1);
    pixels += double(v.width) * v.height;
  }
  CHECK(traced < 0.95 * pixels);
  auto scan = [&](bool window) {
    Params q = p;
    q.window = window;
    Tile t = build_tile(*s.tile, "windows.scene", q);
    const std::string bytes = formats::serialize_pcd(run_tile(&t, q).cloud);
    return std::make_pair(bytes, t.canopy_cover);
  };
  const auto windowed = scan(true), full = scan(false);
  CHECK(windowed.first.size() > 100000);
  CHECK(windowed.first == full.first);
  CHECK(windowed.second == full.second);
}

TEST_CASE("tile: a canopy image coded for its classes only gives the same cover and scan") {
  // Vehicles (instances in blue), trees, bushes and clutter under a nadir canopy image finer than
  // the scan: the class-only texture there must give every pixel the same blue, hence the
  // same cover per vehicle and over the tile, and leave the scan frames as they were.
  SceneRecipe s = parse_scene(
      "extent = 16m 12m\nterrain = rolling 1m 10m\ntrees = 600\nhide = 2\nbushes = 400\nclutter = logs 1 "
      "boulder 1\n"
      "vehicles = random 2 from sedan\nflight_lines = 1\nheadings = 0\n"
      "looks = 75deg/0\nspacing = 0.2m\ncanopy_spacing = 0.05m\n",
      "canopy.scene");
  auto render = [&](bool class_only) {
    Params q = small_params(11);
    q.canopy_class_only = class_only;
    Tile t = build_tile(*s.tile, "canopy.scene", q);
    const std::string bytes = formats::serialize_pcd(run_tile(&t, q).cloud);
    std::vector<double> cover = {t.canopy_cover};
    for (const auto& v : t.vehicles) cover.push_back(v.canopy_cover);
    return std::make_pair(bytes, cover);
  };
  const auto coded = render(true), depth = render(false);
  CHECK(coded.first == depth.first);
  CHECK(coded.second == depth.second);
  REQUIRE(coded.second.size() == 3);
  CHECK(coded.second[0] > 0.2);  // the canopy is there to measure
  double over_vehicles = 0;
  for (std::size_t k = 1; k < coded.second.size(); ++k) over_vehicles += coded.second[k];
  CHECK(over_vehicles > 0);
}

TEST_CASE("tile: decode_tile fills its reserved columns as appending image by image did") {
  // Synthetic frames (no POV-Ray): misses, depths outside the coded range, every class and
  // instances, over two headings x two lines x two looks whose strips overlap and run past the
  // tile; the reference is the former decoding, each image's kept hits appended row by row.
  SceneRecipe s = parse_scene(
      "extent = 16m 12m\nflight_lines = 2\nheadings = 0deg 30deg\nlooks = 75deg/0 60deg/180deg\n"
      "spacing = 0.25m\ncanopy_spacing = 0.5m\norigin = 500000.5 4100000.25 120\n",
      "decode.scene");
  const TileRecipe& r = *s.tile;
  std::vector<TileView> views = tile_views(r, -1, 6);
  views.insert(views.begin(), canopy_view(r, -1, 6));
  REQUIRE(views.size() == 9);
  std::vector<Image16> images(views.size());
  std::uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::uint32_t>(state >> 33);
  };
  for (std::size_t k = 1; k < views.size(); ++k) {
    Image16& img = images[k];
    img.width = views[k].width;
    img.height = views[k].height;
    img.rgb.resize(3 * static_cast<std::size_t>(img.width) * img.height);
    for (std::size_t q = 0; q < img.rgb.size(); q += 3) {
      const std::uint32_t u = next();
      img.rgb[q] = static_cast<std::uint16_t>(u % 17 == 0 ? 0 : u % 19 == 0 ? 65535 : next() % 65536);
      img.rgb[q + 1] = static_cast<std::uint16_t>(next() % 65536);
      img.rgb[q + 2] = static_cast<std::uint16_t>(u % 7 == 0 ? 0 : 1 + next() % 4 + 4 * (next() % 5));
    }
  }
  std::vector<int> asked;
  const TileScan scan = decode_tile(
      [&](int k) {
        asked.push_back(k);
        return images[k];
      },
      views, r);
  CHECK(asked == std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8});

  std::vector<std::vector<double>> want(9);
  std::vector<std::size_t> per_view;
  for (std::size_t k = 1; k < views.size(); ++k) {
    const TileView& v = views[k];
    TileHits hits;
    decode_tile_view(images[k], v, &hits);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < hits.p.size(); ++i) {
      const Vector3d& p = hits.p[i];
      if (p.x() < 0 || p.y() < 0 || p.x() > r.extent_x || p.y() > r.extent_y) continue;
      if (std::abs((p.head<2>() - v.strip_centre).dot(v.strip_across)) > v.strip_half) continue;
      ++kept;
      const Eigen::Vector3f t = v.toward.cast<float>();
      for (int a = 0; a < 3; ++a) {
        want[a].push_back(p[a] + r.origin[a]);
        want[3 + a].push_back(t[a]);
      }
      want[6].push_back(static_cast<double>(k - 1));
      // Class: 0 ground, 1 vegetation, 2 clutter, 3 vehicle (canopy/sim/tile.h).
      const std::uint32_t labels[] = {formats::kLabelGround, formats::kLabelFoliage, formats::kLabelClutter,
                                      formats::kLabelTarget};
      want[7].push_back(labels[hits.cls[i]]);
      want[8].push_back(hits.cls[i] == static_cast<std::uint32_t>(Class::kVehicle) ? hits.instance[i] : 0);
    }
    per_view.push_back(kept);
  }
  CHECK(scan.points_per_view == per_view);
  REQUIRE(scan.cloud.size() == want[0].size());
  CHECK(scan.cloud.size() > 5000);
  CHECK(scan.cloud.size() < 0.8 * (images.size() - 1) * images[1].rgb.size() / 3);  // some dropped
  const std::vector<std::string> names = {"x",        "y",        "z",     "sensor_x", "sensor_y",
                                          "sensor_z", "view_idx", "label", "instance"};
  CHECK(scan.cloud.names() == names);
  for (std::size_t c = 0; c < 9; ++c) {
    INFO(names[c]);
    const std::vector<double>& got = scan.cloud.col(c);
    CHECK(std::memcmp(got.data(), want[c].data(), got.size() * sizeof(double)) == 0);
  }
  std::set<double> classes(want[7].begin(), want[7].end());
  CHECK(classes.size() == 4);
  CHECK(formats::serialize_pcd(scan.cloud).size() > 0);
}

TEST_CASE("rangetrace CLI: bad tile recipes exit 1 naming the line, no output") {
  const auto dir = test::fresh_dir("rangetrace", "tile_bad");
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/rangetrace";
  struct Case {
    std::string recipe, want;
  };
  const Case cases[] = {
      {"extent = 20m\nbogus = 3\n", "line 2: unknown key 'bogus'"},
      {"extent = 20m\n\nvehicle = sedan 19 10 0\n", "line 3: vehicle 'sedan' at (19m, 10m) reaches outside"},
      {"extent = 20m 8m\nvehicle = sedan 30 3 0\n", "line 2: vehicle 'sedan' lies outside the tile"},
      {"vehicle = sedan 10 10 0\nvehicle = tank 12 11 90deg\n",
       "line 2: vehicle 'tank' at (12m, 11m) overlaps the vehicle of line 1"},
      {"extent = 20m\nvehicle = missing.ply 10 10 0\n", "line 2: vehicle model 'missing.ply'"},
      {"extent = 10m\nvehicles = random 9 from tank\n", "line 2: cannot place 9 vehicles"},
  };
  int k = 0;
  for (const auto& c : cases) {
    INFO(c.recipe);
    const auto recipe = dir / ("bad" + std::to_string(k) + ".scene");
    const auto out = dir / ("out" + std::to_string(k) + ".pcd");
    const auto truth = dir / ("truth" + std::to_string(k) + ".json");
    write_text(recipe, c.recipe);
    std::string err;
    const int rc =
        test::sh(bin + " --scene " + recipe.string() + " -o " + out.string() + " --truth " + truth.string(),
                 dir / "err.txt", &err);
    CHECK(rc == 1);
    CHECK_THAT(err, Catch::Contains(recipe.string()) && Catch::Contains(c.want));
    CHECK_FALSE(test::exists(out));
    CHECK_FALSE(test::exists(truth));
    ++k;
  }
}

TEST_CASE("rangetrace CLI: a tile scan with truth.json, georeferenced in float64") {
  const auto dir = test::fresh_dir("rangetrace", "tile_cli");
  write_text(dir / "geo.scene",
             "extent = 12m 10m\ntrees = 0\nbushes = 0\nhide = 0\nvehicle = sedan 6 5 10deg\n"
             "origin = 500000 4400000 120\nflight_lines = 1\nheadings = 0\nlooks = 90deg\n"
             "spacing = 0.1m\ncanopy_spacing = 0.1m\n");
  std::string err;
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/rangetrace";
  REQUIRE(test::sh(bin + " --scene " + (dir / "geo.scene").string() + " -o " + (dir / "geo.pcd").string() +
                       " --truth " + (dir / "truth.json").string(),
                   dir / "err.txt", &err) == 0);
  const formats::PointCloud c = formats::read_pcd((dir / "geo.pcd").string());
  CHECK(c.type("x") == formats::kFloat64);
  CHECK(c.has("instance"));
  std::set<double> xs;
  double zmin = 1e18;
  for (std::size_t i = 0; i < c.size(); ++i) {
    xs.insert(c.col("x")[i]);
    CHECK(c.col("x")[i] >= 500000);
    CHECK(c.col("x")[i] <= 500012);
    CHECK(c.col("y")[i] >= 4400000);
    if (c.col("label")[i] == formats::kLabelGround) zmin = std::min(zmin, c.col("z")[i]);
  }
  CHECK(xs.size() > 100);  // float32 would leave a handful of distinct eastings
  CHECK(zmin == Approx(120).margin(1e-3));
  const std::string truth = slurp(dir / "truth.json");
  CHECK_THAT(truth, Catch::Contains("\"format\": \"canopy.scene_truth\"") &&
                        Catch::Contains("\"model\": \"sedan\"") && Catch::Contains("\"canopy_cover\": 0.0") &&
                        Catch::Contains("500006") && Catch::Contains("\"view_idx\": 0") &&
                        Catch::Contains("\"elevation\": 90.0"));
  // The picture from above, with the footprints drawn.
  REQUIRE(test::sh(bin + " --scene " + (dir / "geo.scene").string() + " --size 64 --picture " +
                       (dir / "geo.png").string(),
                   dir / "err.txt", &err) == 0);
  CHECK(slurp(dir / "geo.png").substr(1, 3) == "PNG");
}

TEST_CASE("rangetrace CLI: a tile written as .las reads back in float64 with labels and instances") {
  // One run to .las, one to .pcd (same seed): the LAS holds the same points to its 1 mm grid,
  // the same labels and instance ids; only the extension chose the format.
  const auto dir = test::fresh_dir("rangetrace", "tile_las");
  write_text(dir / "two.scene",
             "extent = 16m 10m\ntrees = 0\nbushes = 0\nhide = 0\nvehicle = sedan 4 5 0\n"
             "vehicle = tank 11.5 5 90deg\norigin = 500000 4400000 120\nflight_lines = 1\n"
             "headings = 0\nlooks = 90deg\nspacing = 0.1m\ncanopy_spacing = 0.1m\n");
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/rangetrace";
  std::string err;
  for (const char* ext : {"las", "pcd"}) {
    REQUIRE(test::sh(bin + " --seed 3 --scene " + (dir / "two.scene").string() + " -o " +
                         (dir / (std::string("two.") + ext)).string(),
                     dir / "err.txt", &err) == 0);
  }
  CHECK(slurp(dir / "two.las").substr(0, 4) == "LASF");
  const formats::PointCloud las = formats::read_points((dir / "two.las").string());
  const formats::PointCloud pcd = formats::read_pcd((dir / "two.pcd").string());
  REQUIRE(las.size() == pcd.size());
  REQUIRE(las.size() > 1000);
  CHECK(las.type("x") == formats::kFloat64);
  REQUIRE(las.has("label"));
  REQUIRE(las.has("instance"));
  std::set<double> instances, xs;
  std::size_t vehicle_points = 0;
  double worst = 0;
  for (std::size_t i = 0; i < las.size(); ++i) {
    for (const char* c : {"x", "y", "z"}) worst = std::max(worst, std::abs(las.col(c)[i] - pcd.col(c)[i]));
    CHECK(las.col("label")[i] == pcd.col("label")[i]);
    CHECK(las.col("instance")[i] == pcd.col("instance")[i]);
    xs.insert(las.col("x")[i]);
    const bool vehicle = las.col("label")[i] == formats::kLabelTarget;
    CHECK((las.col("instance")[i] > 0) == vehicle);
    if (vehicle) {
      ++vehicle_points;
      instances.insert(las.col("instance")[i]);
      // Instance 1 is the sedan at x = 4 m, instance 2 the tank at x = 11.5 m.
      CHECK(las.col("x")[i] - 500000 < (las.col("instance")[i] == 1 ? 8.0 : 16.0));
      CHECK(las.col("x")[i] - 500000 > (las.col("instance")[i] == 1 ? 0.0 : 8.0));
    }
  }
  CHECK(worst <= 0.0005 + 1e-9);  // LAS stores 1 mm steps: rounding moves a point by <= 0.5 mm
  CHECK(xs.size() > 100);         // float32 would leave a handful of distinct eastings
  CHECK(vehicle_points > 100);
  CHECK(instances == std::set<double>{1, 2});
  // An unknown extension is refused before any rendering, exit 2, no output.
  const int rc = test::sh(bin + " --scene " + (dir / "two.scene").string() + " -o " +
                              (dir / "two.xyz").string() + " --truth " + (dir / "t.json").string(),
                          dir / "err.txt", &err);
  CHECK(rc == 2);
  CHECK_THAT(err, Catch::Contains("two.xyz") && Catch::Contains(".las"));
  CHECK_FALSE(err.find("render:") != std::string::npos);
  CHECK_FALSE(test::exists(dir / "t.json"));
}

TEST_CASE("scene recipes: mutated recipes are refused with an Error, never a crash") {
  // A cheap deterministic fuzz of the recipe parser in the ordinary build (fuzz/fuzz_scene.cpp
  // is the coverage-guided one): byte flips, insertions and deletions of every recipe.
  std::vector<std::string> seeds;
  for (const char* name : {"circle.scene", "flyby.scene", "unoccluded.scene", "forest.scene"}) {
    seeds.push_back(slurp(std::filesystem::path(CANOPY_SOURCE_DIR) / "share/scenes" / name));
  }
  seeds.push_back(
      "extent = 30m 20m\nterrain = rolling 2m 10m\ntree = conifer 3 4 12m\n"
      "canopy_disc = 1 2 3m 1m\nobject = fence 5 5 10deg\norigin = 500000 4400000 7\n"
      "vehicle = sedan 10 10 0 units=mm up=y\nlooks = 90deg 60deg/45deg\n");
  const std::string alphabet = "0123456789 =.-e#\n/abcdefghijklmnopqrstuvwxyz,x\t\"";
  std::uint64_t state = 12345;
  auto next = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return state >> 33;
  };
  int refused = 0, accepted = 0;
  for (int round = 0; round < 3000; ++round) {
    std::string text = seeds[next() % seeds.size()];
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t at = next() % text.size();
      const char c = alphabet[next() % alphabet.size()];
      switch (next() % 3) {
        case 0: text[at] = c; break;
        case 1: text.insert(text.begin() + static_cast<long>(at), c); break;
        default: text.erase(at, 1 + next() % 8); break;
      }
    }
    try {
      const SceneRecipe s = parse_scene(text, "mutant.scene");
      ++accepted;
      CHECK(s.views.size() <= 10000);
      CHECK(s.foliage_count <= 100000);
      if (s.tile) {
        CHECK(s.tile->extent_x <= 100);
        CHECK(s.tile->random_vehicles <= 200);
      }
    } catch (const common::Error& e) {
      ++refused;
      CHECK_THAT(std::string(e.what()), Catch::Contains("mutant.scene"));
    }
  }
  CHECK(refused > 100);
  CHECK(accepted > 100);
}

TEST_CASE("tile: random vehicles are seeded, inside the tile, apart, and stand on rolling ground") {
  SceneRecipe s = parse_scene(
      "extent = 50m\nterrain = rolling 2m 15m\n"
      "vehicles = random 10 from earthmover,obj1,sedan,semi,tank\n"
      "clutter = shed 1 container 2 boulder 3\ntrees = 300\n",
      "random.scene");
  const Tile a = build_tile(*s.tile, "random.scene", small_params(21));
  const Tile b = build_tile(*s.tile, "random.scene", small_params(21));
  const Tile c = build_tile(*s.tile, "random.scene", small_params(22));
  REQUIRE(a.vehicles.size() == 10);
  REQUIRE(a.objects.size() == 6);
  const TerrainModel terrain(*s.tile, 21);
  for (std::size_t i = 0; i < a.vehicles.size(); ++i) {
    const PlacedVehicle& v = a.vehicles[i];
    CHECK(v.instance == static_cast<int>(i) + 1);
    CHECK(v.pose.anchor == b.vehicles[i].pose.anchor);
    for (const auto& p : v.footprint) {
      CHECK(p.x() >= 1.0);
      CHECK(p.y() >= 1.0);
      CHECK(p.x() <= 49.0);
      CHECK(p.y() <= 49.0);
    }
    // No corner of one footprint inside another (2 m apart by construction).
    for (std::size_t j = 0; j < a.vehicles.size(); ++j) {
      if (j == i) continue;
      for (const auto& p : v.footprint) CHECK_FALSE(in_polygon(p, a.vehicles[j].footprint));
    }
    // Standing on the ground: the bottom never below it, and touching it somewhere.
    double lowest_gap = 1e9;
    for (int u = -2; u <= 2; ++u) {
      for (int w = -1; w <= 1; ++w) {
        const Vector3d q = v.pose.anchor + v.pose.r * Vector3d(u / 2.0 * v.size.x() / 2, w * v.size.y() / 2, 0);
        const double gap = q.z() - terrain.height(q.x(), q.y());
        CHECK(gap > -1e-9);
        lowest_gap = std::min(lowest_gap, gap);
      }
    }
    CHECK(lowest_gap < 1e-9);
    CHECK(std::abs(v.pose.pitch) < 20 * kDeg);
  }
  CHECK(a.vehicles[0].pose.anchor != c.vehicles[0].pose.anchor);
  // Trunks keep clear of the vehicles.
  for (const auto& t : a.trees) {
    if (t.bush) continue;
    for (const auto& v : a.vehicles) CHECK_FALSE(in_polygon(t.base.head<2>(), v.footprint));
  }
}
