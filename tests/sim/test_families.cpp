// The procedural vehicle families catalogue (canopy/sim/families.h): instances stay within
// their class ranges, are deterministic per (class, instance), and load as models by their
// family:<class>:<instance> spec (rendered: tests/rangetrace/test_families.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "canopy/common/error.h"
#include "canopy/sim/families.h"
#include "canopy/sim/model.h"

using namespace canopy;
using namespace canopy::sim;
using Eigen::Vector3d;

namespace {

bool within(double v, const FamilyRange& r) { return v >= r.lo - 1e-6 && v <= r.hi + 1e-6; }

}  // namespace

TEST_CASE("families: twelve classes with sane ranges") {
  const auto& classes = family_classes();
  REQUIRE(classes.size() == 12);
  std::set<std::string> names;
  for (const auto& c : classes) {
    names.insert(c.name);
    CHECK(c.length.lo < c.length.hi);
    CHECK(c.width.lo < c.width.hi);
    CHECK(c.height.lo < c.height.hi);
    CHECK(c.width.hi < c.length.lo);  // long axis along x
  }
  for (const char* n : {"sedan", "hatchback", "suv", "pickup", "van", "box-truck", "semi-tractor", "bus",
                        "wheeled-apc", "tracked-apc", "tank", "wheel-loader"}) {
    CHECK(names.count(n) == 1);
  }
}

TEST_CASE("families: 300 instances of every class lie within the class ranges, on the ground, centred") {
  for (const auto& c : family_classes()) {
    FamilyRange seen_length{1e9, -1e9};
    for (int i = 0; i < 300; ++i) {
      const FamilyInstance f = make_family_instance(c.name, i);
      INFO(f.name);
      const Vector3d size = f.hi - f.lo;
      CHECK(within(size.x(), c.length));
      CHECK(within(size.y(), c.width));
      CHECK(within(size.z(), c.height));
      CHECK(std::abs(f.lo.z()) < 1e-9);             // wheels or tracks on the ground
      CHECK(std::abs(f.lo.x() + f.hi.x()) < 1e-6);  // centred along
      CHECK(std::abs(f.lo.y() + f.hi.y()) < 1e-6);  // and across
      seen_length.lo = std::min(seen_length.lo, size.x());
      seen_length.hi = std::max(seen_length.hi, size.x());
    }
    // The draws span most of the class range (not one fixed size).
    INFO(c.name);
    CHECK(seen_length.hi - seen_length.lo > 0.8 * (c.length.hi - c.length.lo));
  }
}

TEST_CASE("families: same (class, instance) gives the same text; others differ") {
  const FamilyInstance a = make_family_instance("suv", 17), b = make_family_instance("suv", 17);
  CHECK(a.pov == b.pov);
  CHECK(a.name == "suv-17");
  CHECK(a.vehicle_class == "suv");
  CHECK(make_family_instance("suv", 18).pov != a.pov);
  CHECK(make_family_instance("pickup", 17).pov != a.pov);
  CHECK(a.pov.find("#declare Vehicle = union {") != std::string::npos);
  CHECK(a.pov.find("texture {") == std::string::npos);  // rangetrace applies its own outermost
  // The text is pinned: a change of the generator changes every modelbase built from it.
  CHECK(a.pov.substr(0, 60) == "// suv-17: instance 17 of the procedural class suv (canopy f");
}

TEST_CASE("families: specs and errors") {
  const Model m = load_model("family:tank:3", MeshImport{});
  CHECK(m.name == "tank-3");
  CHECK(m.vehicle_class == "tank");
  CHECK(m.include_dir.empty());
  CHECK(m.inline_code == make_family_instance("tank", 3).pov);
  CHECK(load_model("sedan", MeshImport{}).vehicle_class.empty());  // built-ins carry no class
  CHECK_THROWS_AS(load_model("family:tractor:1", MeshImport{}), common::UsageError);
  CHECK_THROWS_AS(load_model("family:tank", MeshImport{}), common::UsageError);
  CHECK_THROWS_AS(load_model("family:tank:-1", MeshImport{}), common::UsageError);
  CHECK_THROWS_AS(load_model("family:tank:1x", MeshImport{}), common::UsageError);
  CHECK_THROWS_AS(load_model("family:tank:1234567890", MeshImport{}), common::UsageError);
  try {
    make_family_instance("lorry", 0);
    FAIL("no error");
  } catch (const common::UsageError& e) {
    CHECK(std::string(e.what()).find("wheel-loader") != std::string::npos);  // names the classes
  }
}
