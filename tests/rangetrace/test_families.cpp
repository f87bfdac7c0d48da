// Procedural vehicle families rendered (the catalogue itself: tests/sim/test_families.cpp):
// instances agree with POV-Ray's extents and render into scans whose shapes tell classes apart
// the way real ones differ (a pickup's open bed); a tile's truth names their classes.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/sim/families.h"
#include "rangetrace/rangetrace.h"
#include "rangetrace/tile.h"

using namespace canopy;
using namespace canopy::rangetrace;
using Eigen::Vector3d;

namespace {

const double kDeg = canopy::common::kDegree;

}  // namespace

TEST_CASE("families: POV-Ray's extents of the generated code match the generator's bounds") {
  Params p;
  for (const auto& c : family_classes()) {
    INFO(c.name);
    const FamilyInstance f = make_family_instance(c.name, 5);
    const auto [lo, hi] = model_bounds(load_model(std::string("family:") + c.name + ":5", MeshImport{}), p);
    CHECK((lo - f.lo).norm() < 0.01);
    CHECK((hi - f.hi).norm() < 0.01);
  }
}

namespace {

// Heights of the scan's target points in the rear third and the front two thirds of the
// vehicle (x along the vehicle), from a near-vertical view.
struct Profile {
  double rear_median = 0, front_max = 0;
  std::size_t points = 0;
};

Profile top_profile(const std::string& spec, std::uint64_t seed) {
  const Model m = load_model(spec, MeshImport{});
  SceneRecipe s;
  s.name = "top";
  s.views = {{0, 85 * kDeg}};
  Params p;
  p.size = 96;
  p.spacing = 0.08;
  p.seed = seed;
  const auto cloud = render_scan(m, s, p);
  std::vector<double> x, z;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.col("label")[i] != 1) continue;
    x.push_back(cloud.col("x")[i]);
    z.push_back(cloud.col("z")[i]);
  }
  const auto [xmin, xmax] = std::minmax_element(x.begin(), x.end());
  const double cut = *xmin + (*xmax - *xmin) / 3;
  std::vector<double> rear;
  Profile out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] < cut)
      rear.push_back(z[i]);
    else
      out.front_max = std::max(out.front_max, z[i]);
  }
  std::nth_element(rear.begin(), rear.begin() + rear.size() / 2, rear.end());
  out.rear_median = rear.empty() ? 0 : rear[rear.size() / 2];
  out.points = x.size();
  return out;
}

}  // namespace

TEST_CASE("families: a pickup's open bed is seen well below its cab roof, a van's rear is its roof") {
  for (int i : {1, 2}) {
    const Profile pickup = top_profile("family:pickup:" + std::to_string(i), 3);
    const Profile van = top_profile("family:van:" + std::to_string(i), 3);
    INFO(i << " pickup rear " << pickup.rear_median << " of " << pickup.front_max << ", van rear "
           << van.rear_median << " of " << van.front_max);
    REQUIRE(pickup.points > 300);
    REQUIRE(van.points > 300);
    CHECK(pickup.rear_median < pickup.front_max - 0.5);  // bed floor ~0.8 m under the cab roof
    CHECK(van.rear_median > van.front_max - 0.15);       // one box: the roof runs to the rear
  }
}

TEST_CASE("families: the same instance and seed give byte-identical scans") {
  SceneRecipe s;
  s.name = "two";
  s.views = {{20 * kDeg, 75 * kDeg}, {200 * kDeg, 60 * kDeg}};
  s.foliage_count = 40;
  Params p;
  p.size = 64;
  p.spacing = 0.1;
  p.seed = 11;
  const Model m = load_model("family:wheeled-apc:4", MeshImport{});
  const auto a = render_scan(m, s, p), b = render_scan(m, s, p);
  REQUIRE(a.size() > 100);
  CHECK(a.size() == b.size());
  bool same = true;
  for (const char* col : {"x", "y", "z", "label"}) {
    for (std::size_t i = 0; i < a.size() && same; ++i) same = a.col(col)[i] == b.col(col)[i];
  }
  CHECK(same);
}

TEST_CASE("families: a tile's truth names the class of family vehicles, and only of them") {
  const SceneRecipe s = parse_scene(
      "extent = 24m 12m\nterrain = flat\ntrees = 0\nbushes = 0\nhide = 0\n"
      "vehicle = family:wheel-loader:2 6 6 0\nvehicle = sedan 18 6 90\n"
      "flight_lines = 1\nheadings = 0\nlooks = 80deg/0\nspacing = 0.2m\n",
      "fam.scene");
  Params p;
  p.seed = 3;
  const Tile tile = build_tile(*s.tile, "fam.scene", p);
  const auto truth = nlohmann::json::parse(truth_json(tile, {}));
  REQUIRE(truth.at("vehicles").size() == 2);
  const auto& loader = truth["vehicles"][0];
  CHECK(loader.at("model") == "wheel-loader-2");
  CHECK(loader.at("class") == "wheel-loader");
  const auto f = make_family_instance("wheel-loader", 2);
  CHECK(loader.at("size")[0].get<double>() == Approx(f.hi.x() - f.lo.x()).margin(0.01));
  CHECK(truth["vehicles"][1].at("model") == "sedan");
  CHECK(!truth["vehicles"][1].contains("class"));

  const SceneRecipe r = parse_scene(
      "extent = 30m 30m\nterrain = flat\ntrees = 0\nbushes = 0\nhide = 0\n"
      "vehicles = random 3 from family:van:1,family:tank:2\n"
      "flight_lines = 1\nheadings = 0\nlooks = 80deg/0\nspacing = 0.2m\n",
      "random.scene");
  const auto random_truth = nlohmann::json::parse(truth_json(build_tile(*r.tile, "random.scene", p), {}));
  REQUIRE(random_truth.at("vehicles").size() == 3);
  for (const auto& v : random_truth["vehicles"]) {
    CHECK(v.at("class") == (v.at("model") == "van-1" ? "van" : "tank"));
  }
}
