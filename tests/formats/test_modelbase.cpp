// formats/modelbase.h: listing a modelbase directory and reading one graph, every error naming
// the directory or the file.
#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/formats/modelbase.h"
#include "canopy/formats/segment_graph.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using namespace canopy;

namespace {

formats::SegmentGraph one_segment(int id) {
  formats::SegmentGraph g;
  formats::Segment s;
  s.segment_id = id;
  s.vertex_count = 3;
  s.area = 1.5;
  s.normal = {0, 0, 1};
  g.segments.push_back(s);
  return g;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const common::DataError& e) { return e.what(); }  // "<file>: <cause>"
  return "no error";
}

}  // namespace

TEST_CASE("list_modelbase: the <model>.json files sorted by name, nothing else") {
  const fs::path dir = test::fresh_dir("formats", "modelbase-list");
  formats::write_segment_graph(one_segment(1), (dir / "tank.json").string());
  formats::write_segment_graph(one_segment(2), (dir / "earthmover.json").string());
  formats::write_segment_graph(one_segment(3), (dir / "b.json").string());
  std::ofstream(dir / "tank.pcd") << "not a graph";
  std::ofstream(dir / "tank.class") << "tank";
  fs::create_directories(dir / "sub.json");  // a directory named like a graph
  const auto entries = formats::list_modelbase(dir.string());
  REQUIRE(entries.size() == 3);
  CHECK(entries[0].name == "b");
  CHECK(entries[1].name == "earthmover");
  CHECK(entries[2].name == "tank");
  CHECK(entries[2].path == (dir / "tank.json").string());
  CHECK(formats::read_segment_graph(entries[1].path).segments.at(0).segment_id == 2);
}

TEST_CASE("list_modelbase and read_segment_graph: errors name the directory or the file") {
  const fs::path dir = test::fresh_dir("formats", "modelbase-errors");
  const std::string missing = (dir / "none").string();
  CHECK(error_of([&] { formats::list_modelbase(missing); }) ==
        missing + ": modelbase directory does not exist");
  std::ofstream(dir / "file.json") << "{}";
  const std::string file = (dir / "file.json").string();
  CHECK_THAT(error_of([&] { formats::list_modelbase(file); }),
             Catch::StartsWith(file + ": modelbase is not a directory"));
  fs::create_directories(dir / "empty");
  CHECK_THAT(error_of([&] { formats::list_modelbase((dir / "empty").string()); }),
             Catch::Contains("holds no <model>.json"));
  std::ofstream(dir / "broken.json") << "{ not json";
  const std::string broken = (dir / "broken.json").string();
  CHECK_THAT(error_of([&] { formats::read_segment_graph(broken); }), Catch::StartsWith(broken + ": "));
  CHECK_THAT(error_of([&] { formats::read_segment_graph(file); }), Catch::StartsWith(file + ": "));
}
