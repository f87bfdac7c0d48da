// documents/areas.h: areas.json (canopy.areas v1) as areas writes it and report reads it.
#include <catch2/catch.hpp>

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/areas.h"

using namespace canopy;

namespace {

documents::Areas example() {
  documents::Areas a;
  a.visible = 44.5;
  a.samples = 23.25;
  a.mesh = 21;
  a.segments = 20.5;
  a.matched = 18.75;
  a.spacing = 0.03;
  a.cell = 0.045;
  a.voxel = 0.128;
  a.max_segments = 15;
  a.target_points = 1234;
  a.target_samples = 321;
  return a;
}

}  // namespace

TEST_CASE("areas: the writer's text, byte for byte, and it reads back to the same values") {
  const std::string text = documents::write_areas(example(), {"scan.pcd", "a \"b\".pcd"});
  CHECK(text ==
        "{\"format\": \"canopy.areas\", \"version\": 1,\n \"provenance\": {\"tool\": \"areas\", \"version\": "
        "\"" CANOPY_VERSION
        "\", \"inputs\": [\"scan.pcd\", \"a \\\"b\\\".pcd\"]},\n \"spacing\": 0.03, \"cell\": 0.045, "
        "\"voxel\": 0.128, "
        "\"max_segments\": 15,\n \"target_points\": 1234, \"target_samples\": 321,\n \"visible\": 44.5, "
        "\"samples\": "
        "23.25, \"mesh\": 21.0, \"segments\": 20.5, \"matched\": 18.75}\n");
  const documents::Areas b = documents::read_areas(text, "a.json");
  CHECK(b.visible == 44.5);
  CHECK(b.samples == 23.25);
  CHECK(b.mesh == 21);
  CHECK(b.segments == 20.5);
  CHECK(b.matched == 18.75);
  CHECK(b.spacing == 0.03);
  CHECK(b.cell == 0.045);
  CHECK(b.voxel == 0.128);
  CHECK(b.max_segments == 15);
  CHECK(b.target_points == 1234);
  CHECK(b.target_samples == 321);
}

TEST_CASE("areas: the writer refuses a non-finite area") {
  documents::Areas a = example();
  a.mesh = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(documents::write_areas(a, {}), Catch::Contains("non-finite"));
}

TEST_CASE("areas: number_text is the shortest text that reads back") {
  CHECK(documents::number_text(0.045) == "0.045");
  CHECK(documents::number_text(1e-6) == "1e-06");
  CHECK(documents::number_text(-1e308) == "-1e+308");
  CHECK(documents::number_text(2) == "2.0");
}

TEST_CASE("areas: refusals name the file and the problem") {
  CHECK_THROWS_WITH(documents::read_areas("{\"format\": \"canopy.segment_graph\", \"version\": 1}", "x.json"),
                    Catch::Contains("x.json") && Catch::Contains("canopy.areas"));
  CHECK_THROWS_WITH(documents::read_areas("not json", "y.json"), Catch::Contains("y.json"));
  // Every member typed: no cast from 1.5 to 1, no negative area, the version checked.
  const std::string text = documents::write_areas(example(), {"scan.pcd"});
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    REQUIRE(at != std::string::npos);
    return t.replace(at, from.size(), to);
  };
  for (const auto& [from, to, why] : std::vector<std::array<std::string, 3>>{
           {"\"max_segments\": 15", "\"max_segments\": 15.5", "max_segments must be an integer"},
           {"\"max_segments\": 15", "\"max_segments\": 0", "max_segments must be an integer"},
           {"\"max_segments\": 15", "\"max_segments\": 100001", "max_segments must be at most 100000"},
           {"\"target_points\": 1234", "\"target_points\": -1", "target_points must be an integer"},
           {"\"target_points\": 1234", "\"target_points\": 1e30", "target_points must be an integer"},
           {"\"target_samples\": 321", "\"target_samples\": 9007199254740993",
            "target_samples must be an integer"},
           {"\"segments\": 20.5", "\"segments\": -1e+308", "segments must be a number >= 0"},
           {"\"cell\": 0.045", "\"cell\": 0", "cell must be a positive number"},
           {"\"visible\": 44.5", "\"visible\": \"44.5\"", "visible must be a number"},
           {"\"visible\": 44.5, ", "", "missing \"visible\""},
           {"\"version\": 1", "\"version\": 2", "version 2"},
           {"\"version\": 1", "\"version\": 1.0", "version"}}) {
    INFO(to);
    CHECK_THROWS_WITH(documents::read_areas(edited(from, to), "z.json"),
                      Catch::Contains("z.json") && Catch::Contains(why));
  }
}
