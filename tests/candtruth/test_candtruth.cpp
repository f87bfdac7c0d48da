// candtruth on a hand-placed labelled tile: every count, coverage and purity is known by
// construction (issue 30: the candidates' truth, outside detect).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "candtruth/candtruth.h"
#include "canopy/common/error.h"
#include "canopy/formats/labels.h"

using namespace canopy;

namespace {

struct Builder {
  formats::PointCloud tile;
  std::vector<double>*x, *y, *z, *label, *instance;
  Builder() {
    x = &tile.add("x", formats::kFloat64);
    y = &tile.add("y", formats::kFloat64);
    z = &tile.add("z", formats::kFloat64);
    label = &tile.add("label", formats::kUint32);
    instance = &tile.add("instance", formats::kUint32);
  }
  void add(double px, double py, double pz, std::uint32_t l, std::uint32_t id) {
    x->push_back(px);
    y->push_back(py);
    z->push_back(pz);
    label->push_back(l);
    instance->push_back(id);
    tile.resize(x->size());
  }
};

// A candidate at (cx, cy, cz), its x axis `heading` from +x toward +y.
documents::Candidate candidate(const std::string& id, double cx, double cy, double cz, double heading,
                               double length, double width, double height) {
  documents::Candidate c;
  c.id = id;
  const double ch = std::cos(heading), sh = std::sin(heading);
  c.transform = {ch, -sh, 0, cx, sh, ch, 0, cy, 0, 0, 1, cz, 0, 0, 0, 1};
  c.length = length;
  c.width = width;
  c.height = height;
  return c;
}

// The scene (margin 0.5):
//  c0001 at (10, 0), axis-aligned, 4 x 2 x 1.5: vehicle 1's 100 points, 50 ground in the
//        footprint and 10 in the margin, 25 foliage in the margin above the height;
//        vehicle 1 has 20 more points far away (coverage 100 / 120, purity 100 / 125).
//  c0002 at (30, 0, 2), heading 30 degrees, 4 x 1 x 1.5: vehicle 2's 40 points along its local x
//        axis out to 1.9 m (inside only if the transform is inverted right), 10 points of
//        instance 2 labelled foliage (not the vehicle's), one vehicle 2 point 0.1 m above the
//        box and one 0.1 m below it (outside; they count in the tile: coverage 40 / 42, purity 40 / 50).
//  c0003 at (-20, -20): 30 ground points, no vehicle (instance 0).
//  vehicle 3: 5 points far from every candidate.
struct Scene {  // not copied: `in` borrows `b.tile`
  Builder b;
  candtruth::Inputs in;
  Scene() {
    for (int i = 0; i < 100; ++i)
      b.add(8.5 + 0.03 * i, -0.5 + 0.01 * i, 0.3 + 0.01 * i, formats::kLabelTarget, 1);
    for (int i = 0; i < 50; ++i) b.add(8.2 + 0.07 * i, -0.8 + 0.03 * i, 0.0, formats::kLabelGround, 0);
    for (int i = 0; i < 10; ++i) b.add(12.3, -0.5 + 0.1 * i, 0.0, formats::kLabelGround, 0);  // in the margin
    for (int i = 0; i < 25; ++i) b.add(9.0 + 0.05 * i, 1.2, 1.8, formats::kLabelFoliage, 0);
    for (int i = 0; i < 20; ++i) b.add(60 + 0.1 * i, 60, 0.5, formats::kLabelTarget, 1);
    const double h = 30 * M_PI / 180;
    for (int i = 0; i < 40; ++i) {
      const double s = -1.9 + 3.8 * i / 39.0;  // along the local x axis
      b.add(30 + s * std::cos(h), s * std::sin(h), 2.5, formats::kLabelTarget, 2);
    }
    for (int i = 0; i < 10; ++i) b.add(30 + 0.05 * i, 0.05 * i, 3.0, formats::kLabelFoliage, 2);
    b.add(30, 0, 2 + 1.5 + 0.5 + 0.1, formats::kLabelTarget, 2);  // above the box
    b.add(30.1, 0, 2 - 0.5 - 0.1, formats::kLabelTarget, 2);      // below it
    for (int i = 0; i < 30; ++i) b.add(-21 + 0.07 * i, -20, 0, formats::kLabelGround, 0);
    for (int i = 0; i < 5; ++i) b.add(-60, 60 + i, 0.4, formats::kLabelTarget, 3);
    in.tile = &b.tile;
    in.tile_name = "tile.pcd";
    in.index_name = "cands/index.json";
    in.index.margin = 0.5;
    in.index.tile_points = static_cast<std::int64_t>(b.tile.size());
    in.index.candidates = {candidate("c0001", 10, 0, 0, 0, 4, 2, 1.5),
                           candidate("c0002", 30, 0, 2, h, 4, 1, 1.5),
                           candidate("c0003", -20, -20, 0, 0, 4, 2, 1.5)};
  }
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
};

std::string data_error(const candtruth::Params& p, const candtruth::Inputs& in, std::string* file) {
  try {
    candtruth::run(p, in);
  } catch (const common::DataError& e) {
    *file = e.file();
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("candtruth: counts, coverage and purity of hand-placed candidates") {
  const Scene s;
  const candtruth::Outputs t = candtruth::run({}, s.in);
  CHECK(t.tile == "tile.pcd");
  CHECK(t.index == "cands/index.json");
  REQUIRE(t.candidates.size() == 3);
  const auto& a = t.candidates[0];
  CHECK(a.id == "c0001");
  CHECK(a.crop_points == 185);
  CHECK(a.instance == 1);
  CHECK(a.points == 100);
  CHECK(a.coverage == Approx(100.0 / 120));
  CHECK(a.purity == Approx(100.0 / 125));
  const auto& b = t.candidates[1];
  CHECK(b.crop_points == 50);
  CHECK(b.instance == 2);
  CHECK(b.points == 40);
  CHECK(b.coverage == Approx(40.0 / 42));
  CHECK(b.purity == Approx(40.0 / 50));
  const auto& c = t.candidates[2];
  CHECK(c.crop_points == 30);
  CHECK(c.instance == 0);
  CHECK(c.points == 0);
  CHECK(c.coverage == 0);
  CHECK(c.purity == 0);
  REQUIRE(t.instances.size() == 3);
  CHECK(t.instances[0].instance == 1);
  CHECK(t.instances[0].points == 120);
  CHECK(t.instances[0].candidates == std::vector<std::string>{"c0001"});
  CHECK(t.instances[1].points == 42);
  CHECK(t.instances[1].candidates == std::vector<std::string>{"c0002"});
  CHECK(t.instances[2].instance == 3);
  CHECK(t.instances[2].candidates.empty());
}

TEST_CASE(
    "candtruth: a margin given overrides the index's; without a label field every instance point counts") {
  Scene s;
  candtruth::Params wide;
  wide.margin = 0.0;
  const candtruth::Outputs narrow = candtruth::run(wide, s.in);
  // Without the margin the ground in c0001's footprint (z = 0 is the box's bottom face) stays;
  // the ground in the margin and the foliage at 1.8 m (above 1.5) go.
  CHECK(narrow.candidates[0].crop_points == 150);
  CHECK(narrow.candidates[0].purity == Approx(1.0));
  s.b.tile.remove("label");
  const candtruth::Outputs unlabelled = candtruth::run({}, s.in);
  // Now the 10 instance-2 points labelled foliage are vehicle 2's too, and nothing is ground.
  CHECK(unlabelled.candidates[1].points == 50);
  CHECK(unlabelled.candidates[1].purity == Approx(1.0));
  CHECK(unlabelled.candidates[0].purity == Approx(100.0 / 185));
  CHECK(unlabelled.instances[1].points == 52);
}

TEST_CASE("candtruth: refusals name the file") {
  std::string file;
  Scene s;
  s.in.index.margin.reset();
  CHECK_THAT(data_error({}, s.in, &file), Catch::Contains("gives no crop margin"));
  CHECK(file == "cands/index.json");
  candtruth::Params m;
  m.margin = 0.5;
  CHECK(data_error(m, s.in, &file).empty());
  Scene other;
  other.in.index.tile_points = 7;
  CHECK_THAT(data_error({}, other.in, &file), Catch::Contains("was made from a tile of 7 points"));
  Scene none;
  none.b.tile.remove("instance");
  CHECK_THAT(data_error({}, none.in, &file), Catch::Contains("has no 'instance' field"));
  CHECK(file == "tile.pcd");
  Scene bad;
  bad.b.tile.col("instance")[3] = 2.5;
  CHECK_THAT(data_error({}, bad.in, &file), Catch::Contains("point 3: field 'instance' is not an integer"));
  candtruth::Params neg;
  neg.margin = -1.0;
  CHECK_THROWS_AS(candtruth::validate(neg), common::UsageError);
}

TEST_CASE("candtruth: a box tilted across its y axis keeps the points its lean carries sideways") {
  // A frame tilted 60 degrees about the tile's x axis: local z leans toward -y, so a point 4 m up
  // the local z axis sits 3.46 m beside the centre in y, outside the 2 x 1 m footprint's reach
  // (half-diagonal 1.12 m + margin) unless the lean's y component is counted.
  Builder b;
  const double a = 60 * M_PI / 180;
  for (int i = 0; i < 10; ++i) {
    const double lz = 3.5 + 0.05 * i;  // along local z
    b.add(0, -lz * std::sin(a), lz * std::cos(a), formats::kLabelTarget, 1);
  }
  candtruth::Inputs in;
  in.tile = &b.tile;
  in.tile_name = "tilted.pcd";
  in.index_name = "index.json";
  in.index.margin = 0.0;
  documents::Candidate c;
  c.id = "c0001";
  c.transform = {1, 0, 0, 0, 0, std::cos(a), -std::sin(a), 0, 0, std::sin(a), std::cos(a), 0, 0, 0, 0, 1};
  c.length = 2;
  c.width = 1;
  c.height = 4;
  in.index.candidates = {c};
  const candtruth::Outputs t = candtruth::run({}, in);
  CHECK(t.candidates[0].crop_points == 10);
  CHECK(t.candidates[0].instance == 1);
}
