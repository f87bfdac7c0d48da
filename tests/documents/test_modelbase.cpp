// documents/modelbase.h: listing a modelbase directory, reading one graph and a model's class,
// every error naming the directory or the file.
#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/modelbase.h"
#include "canopy/documents/segment_graph.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using namespace canopy;

namespace {

documents::SegmentGraph one_segment(int id) {
  documents::SegmentGraph g;
  documents::Segment s;
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
  const fs::path dir = test::fresh_dir("documents", "modelbase-list");
  documents::write_segment_graph(one_segment(1), (dir / "tank.json").string());
  documents::write_segment_graph(one_segment(2), (dir / "earthmover.json").string());
  documents::write_segment_graph(one_segment(3), (dir / "b.json").string());
  std::ofstream(dir / "tank.pcd") << "not a graph";
  std::ofstream(dir / "tank.class") << "tank";
  fs::create_directories(dir / "sub.json");  // a directory named like a graph
  const auto entries = documents::list_modelbase(dir.string());
  REQUIRE(entries.size() == 3);
  CHECK(entries[0].name == "b");
  CHECK(entries[1].name == "earthmover");
  CHECK(entries[2].name == "tank");
  CHECK(entries[2].path == (dir / "tank.json").string());
  CHECK(documents::read_segment_graph(entries[1].path).segments.at(0).segment_id == 2);
}

TEST_CASE("list_modelbase and read_segment_graph: errors name the directory or the file") {
  const fs::path dir = test::fresh_dir("documents", "modelbase-errors");
  const std::string missing = (dir / "none").string();
  CHECK(error_of([&] { documents::list_modelbase(missing); }) ==
        missing + ": modelbase directory does not exist");
  std::ofstream(dir / "file.json") << "{}";
  const std::string file = (dir / "file.json").string();
  CHECK_THAT(error_of([&] { documents::list_modelbase(file); }),
             Catch::StartsWith(file + ": modelbase is not a directory"));
  fs::create_directories(dir / "empty");
  CHECK_THAT(error_of([&] { documents::list_modelbase((dir / "empty").string()); }),
             Catch::Contains("holds no <model>.json"));
  std::ofstream(dir / "broken.json") << "{ not json";
  const std::string broken = (dir / "broken.json").string();
  CHECK_THAT(error_of([&] { documents::read_segment_graph(broken); }), Catch::StartsWith(broken + ": "));
  CHECK_THAT(error_of([&] { documents::read_segment_graph(file); }), Catch::StartsWith(file + ": "));
}

TEST_CASE("read_model_class: one word of at most 64 characters, none without a file") {
  const fs::path dir = test::fresh_dir("documents", "modelbase-class");
  std::ofstream(dir / "suv-3.class") << "suv\n";
  CHECK(documents::read_model_class(dir.string(), "suv-3") == std::optional<std::string>("suv"));
  CHECK(!documents::read_model_class(dir.string(), "tank"));
  const std::string cause = ": expected one class name (one word, at most 64 characters)";
  for (const auto& [name, text] :
       std::vector<std::pair<std::string, std::string>>{{"empty", ""},
                                                        {"blank", " \n"},
                                                        {"two", "suv van\n"},
                                                        {"long", std::string(65, 'a')},
                                                        {"huge", std::string(5000, ' ') + "suv"}}) {
    std::ofstream(dir / (name + ".class")) << text;
    CHECK(error_of([&] { documents::read_model_class(dir.string(), name); }) ==
          (dir / (name + ".class")).string() + cause);
  }
}
