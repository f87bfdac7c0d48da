// The gmatch binary: a modelbase directory in, a ranked match result out; bad modelbases
// fail with exit 1, name the file and leave no output.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "canopy/common/atomic_file.h"
#include "support/cli.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"
#include "fixtures/gmatch_graphs.h"

namespace fs = std::filesystem;
using namespace gmatch_test;

namespace {

const std::string kBin = std::string(CANOPY_BIN_DIR) + "/gmatch";

fs::path fresh_dir(const std::string& name) { return canopy::test::fresh_dir("gmatch", name); }

using canopy::test::sh;

fs::path make_modelbase(const fs::path& dir) {
  const fs::path mb = dir / "modelbase";
  fs::create_directories(mb);
  canopy::documents::write_segment_graph(vehicle(), (mb / "sedan.json").string());
  canopy::documents::write_segment_graph(vehicle(6.5, 2.4, 1.2, 1.6, 1.0, 2.0, 0.5),
                                         (mb / "truck.json").string());
  canopy::documents::write_segment_graph(random_graph(3, 25), (mb / "blob.json").string());
  return mb;
}

}  // namespace

TEST_CASE("gmatch ranks the true model first, byte-identical on reruns", "[gmatch][cli]") {
  const fs::path dir = fresh_dir("ok");
  const fs::path mb = make_modelbase(dir);
  const fs::path object = dir / "segments.json";
  canopy::documents::write_segment_graph(transformed(perturbed(vehicle(), 8), 1.1, 0.0, {3, 4, 0}),
                                         object.string());
  std::string err;
  const std::string base = kBin + " -i " + object.string() + " --modelbase " + mb.string();
  REQUIRE(sh(base + " -o " + (dir / "a.json").string(), dir / "err", &err) == 0);
  REQUIRE(err.find("best sedan") != std::string::npos);
  REQUIRE(err.find("entropy") != std::string::npos);
  REQUIRE(sh(base + " --threads 2 -o " + (dir / "b.json").string(), dir / "err", &err) == 0);
  const auto a = canopy::common::read_file((dir / "a.json").string());
  REQUIRE(a == canopy::common::read_file((dir / "b.json").string()));
  // gmatch sets no pose: no "pose" key (the match result's optional key, baseline --hypotheses').
  CHECK(a.find("\"pose\"") == std::string::npos);

  const auto result = canopy::documents::read_match_result((dir / "a.json").string());
  REQUIRE(result.models.size() == 3);
  REQUIRE(result.models[0].model == "sedan");
  REQUIRE(result.models[0].rank == 1);
  REQUIRE(result.models[0].score > result.models[1].score);
  REQUIRE(result.error_form == "bounded");
  REQUIRE(result.entropy > 0);
  REQUIRE(result.entropy < std::log2(3.0));
  REQUIRE(result.models[0].pairs.size() == 11);

  // The printed form is selectable and recorded.
  REQUIRE(sh(base + " --error thesis -o " + (dir / "t.json").string(), dir / "err", &err) == 0);
  REQUIRE(canopy::documents::read_match_result((dir / "t.json").string()).error_form == "thesis");
  // The shipped defaults are accepted as a config file and change nothing.
  REQUIRE(
      sh(base + " --config " + CANOPY_SOURCE_DIR + "/share/params/gmatch.ini -o " + (dir / "c.json").string(),
         dir / "err", &err) == 0);
  const auto c = canopy::documents::read_match_result((dir / "c.json").string());
  REQUIRE(c.models[0].score == result.models[0].score);
}

TEST_CASE("a malformed modelbase file is named, exit 1, no output", "[gmatch][cli]") {
  const fs::path dir = fresh_dir("bad");
  const fs::path mb = make_modelbase(dir);
  {
    std::ofstream f(mb / "broken.json");
    f << "{\"format\": \"canopy.segment_graph\", \"version\": 1, \"segments\": [";
  }
  const fs::path object = dir / "segments.json";
  canopy::documents::write_segment_graph(vehicle(), object.string());
  const fs::path out = dir / "match.json";
  std::string err;
  const std::string cmd =
      kBin + " -i " + object.string() + " --modelbase " + mb.string() + " -o " + out.string();
  REQUIRE(sh(cmd, dir / "err", &err) == 1);
  REQUIRE(err.find("broken.json") != std::string::npos);
  REQUIRE(err.find("gmatch: error:") != std::string::npos);
  REQUIRE_FALSE(fs::exists(out));

  // A well-formed graph that cannot be matched (zero area) is named too.
  fs::remove(mb / "broken.json");
  auto zero = vehicle();
  zero.segments[1].area = 0;
  canopy::documents::write_segment_graph(zero, (mb / "zero.json").string());
  REQUIRE(sh(cmd, dir / "err", &err) == 1);
  REQUIRE(err.find("zero.json") != std::string::npos);
  REQUIRE_FALSE(fs::exists(out));
}

TEST_CASE("a model graph over the segment limit is refused before its tables are built", "[gmatch][cli]") {
  // 20 000 segments used to cost 6.3 GB and 16 s (tables grow with the square of the count).
  const fs::path dir = fresh_dir("huge");
  const fs::path mb = make_modelbase(dir);
  canopy::documents::write_segment_graph(random_graph(7, 2001), (mb / "huge.json").string());
  const fs::path object = dir / "segments.json";
  canopy::documents::write_segment_graph(vehicle(), object.string());
  const fs::path out = dir / "match.json";
  std::string err;
  REQUIRE(sh(kBin + " -i " + object.string() + " --modelbase " + mb.string() + " -o " + out.string(),
             dir / "err", &err) == 1);
  CHECK(err.find("huge.json") != std::string::npos);
  CHECK(err.find("2001 segments") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // At the limit it is matched.
  canopy::documents::write_segment_graph(random_graph(7, 2000), (mb / "huge.json").string());
  CHECK(sh(kBin + " -i " + object.string() + " --modelbase " + mb.string() + " -o " + out.string(),
           dir / "err", &err) == 0);
}

TEST_CASE("an empty or missing modelbase is an error", "[gmatch][cli]") {
  const fs::path dir = fresh_dir("empty");
  const fs::path mb = dir / "modelbase";
  fs::create_directories(mb);
  std::ofstream(mb / "README.txt") << "not a model\n";
  const fs::path object = dir / "segments.json";
  canopy::documents::write_segment_graph(vehicle(), object.string());
  const fs::path out = dir / "match.json";
  std::string err;
  const std::string head = kBin + " -i " + object.string() + " -o " + out.string();
  REQUIRE(sh(head + " --modelbase " + mb.string(), dir / "err", &err) == 1);
  REQUIRE(err.find("no <model>.json") != std::string::npos);
  REQUIRE(sh(head + " --modelbase " + (dir / "nowhere").string(), dir / "err", &err) == 1);
  REQUIRE(sh(head, dir / "err", &err) == 2);  // --modelbase is required
  REQUIRE_FALSE(fs::exists(out));
}

TEST_CASE("gmatch --format table prints one line per model, named by the input path", "[gmatch][cli]") {
  const fs::path dir = fresh_dir("table");
  const fs::path mb = make_modelbase(dir);
  const fs::path trial = dir / "sedan" / "circle" / "noise-8";
  fs::create_directories(trial);
  const fs::path object = trial / "segments.json";
  canopy::documents::write_segment_graph(transformed(vehicle(), 0.4, 0.0, {1, 2, 0}), object.string());
  std::string err;
  const std::string base = kBin + " -i " + object.string() + " --modelbase " + mb.string();
  REQUIRE(sh(base + " --format table -o " + (dir / "t.txt").string(), dir / "err", &err) == 0);
  const std::string t = canopy::common::read_file((dir / "t.txt").string());
  REQUIRE(t.find("# object " + trial.string() + ",") == 0);
  REQUIRE(t.find("\n1 sedan ") != std::string::npos);
  REQUIRE(std::count(t.begin(), t.end(), '\n') == 5);  // two header lines + three models
  REQUIRE(err.find(trial.string() + ": best sedan") != std::string::npos);
  // The one-sided coverage stays selectable (ablation) and changes the recorded parameters.
  REQUIRE(sh(base + " --coverage model -o " + (dir / "m.json").string(), dir / "err", &err) == 0);
  const auto m = canopy::documents::read_match_result((dir / "m.json").string());
  bool recorded = false;
  for (const auto& [k, v] : m.provenance.parameters) recorded |= k == "coverage" && v == "model";
  REQUIRE(recorded);
  REQUIRE(sh(base + " --coverage neither -o " + (dir / "x.json").string(), dir / "err", &err) == 2);
}
