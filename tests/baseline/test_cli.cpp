// The baseline binary: a modelbase of <model>.pcd surfaces and a candidate PCD in, a
// canopy.baseline ranking out; bad inputs fail with exit 1, name the file and leave no output.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/formats/pcd.h"
#include "shapes.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using namespace baseline_test;

namespace {

const std::string kBin = std::string(CANOPY_BIN_DIR) + "/baseline";

fs::path setup(const std::string& name) {
  const fs::path dir = canopy::test::fresh_dir("baseline", name);
  fs::create_directories(dir / "modelbase");
  canopy::formats::write_pcd(to_cloud(box()), (dir / "modelbase" / "box.pcd").string());
  canopy::formats::write_pcd(to_cloud(cylinder()), (dir / "modelbase" / "cylinder.pcd").string());
  std::ofstream(dir / "modelbase" / "box.json") << "{}";  // other entries are ignored
  const Cloud scan = scene(box(), pose(1.0, {2, 3, 0}), {0, 1, 0}, 0.01, 3);
  canopy::formats::write_pcd(to_cloud(scan), (dir / "samples.pcd").string());
  return dir;
}

}  // namespace

TEST_CASE("baseline ranks the box first in both methods, byte-identical on reruns", "[baseline][cli]") {
  const fs::path dir = setup("ok");
  const std::string base =
      kBin + " -i " + (dir / "samples.pcd").string() + " --modelbase " + (dir / "modelbase").string();
  std::string err;
  REQUIRE(canopy::test::sh(base + " -o " + (dir / "a.json").string(), dir / "err", &err) == 0);
  CHECK(err.find("vfh: best box") != std::string::npos);
  CHECK(err.find("fpfh: best box") != std::string::npos);
  REQUIRE(canopy::test::sh(base + " -o " + (dir / "b.json").string(), dir / "err", &err) == 0);
  const std::string a = canopy::common::read_file((dir / "a.json").string());
  CHECK(a == canopy::common::read_file((dir / "b.json").string()));
  const auto j = nlohmann::json::parse(a);
  CHECK(j["format"] == "canopy.baseline");
  CHECK(j["version"] == 1);
  REQUIRE(j["methods"].size() == 2);
  for (const auto& m : j["methods"]) {
    REQUIRE(m["models"].size() == 2);
    CHECK(m["models"][0]["model"] == "box");
    CHECK(m["models"][0]["rank"] == 1);
  }
  CHECK(j["methods"][1]["models"][0]["pose"].size() == 16);
  // One method only.
  REQUIRE(canopy::test::sh(base + " --methods vfh -o " + (dir / "v.json").string(), dir / "err", &err) == 0);
  CHECK(nlohmann::json::parse(canopy::common::read_file((dir / "v.json").string()))["methods"].size() == 1);
}

TEST_CASE("baseline: bad inputs are named, exit 1, no output", "[baseline][cli]") {
  const fs::path dir = setup("bad");
  const fs::path out = dir / "out.json";
  std::string err;
  const std::string tail = " -o " + out.string();
  // Missing modelbase directory.
  CHECK(canopy::test::sh(kBin + " -i " + (dir / "samples.pcd").string() + " --modelbase " +
                             (dir / "nowhere").string() + tail,
                         dir / "err", &err) == 1);
  CHECK(err.find("nowhere") != std::string::npos);
  // A modelbase without surfaces.
  fs::create_directories(dir / "empty");
  CHECK(canopy::test::sh(
            kBin + " -i " + (dir / "samples.pcd").string() + " --modelbase " + (dir / "empty").string() + tail,
            dir / "err", &err) == 1);
  CHECK(err.find("no <model>.pcd") != std::string::npos);
  // A broken surface is named.
  std::ofstream(dir / "modelbase" / "broken.pcd") << "# .PCD v0.7\nFIELDS x y\n";
  CHECK(canopy::test::sh(kBin + " -i " + (dir / "samples.pcd").string() + " --modelbase " +
                             (dir / "modelbase").string() + tail,
                         dir / "err", &err) == 1);
  CHECK(err.find("broken.pcd") != std::string::npos);
  fs::remove(dir / "modelbase" / "broken.pcd");
  // A candidate without normals.
  auto pc = to_cloud(box());
  pc.remove("normal_x");
  canopy::formats::write_pcd(pc, (dir / "nonormals.pcd").string());
  CHECK(canopy::test::sh(kBin + " -i " + (dir / "nonormals.pcd").string() + " --modelbase " +
                             (dir / "modelbase").string() + tail,
                         dir / "err", &err) == 1);
  CHECK(err.find("nonormals.pcd") != std::string::npos);
  // Bad parameters are usage errors.
  CHECK(canopy::test::sh(kBin + " -i " + (dir / "samples.pcd").string() + " --modelbase " +
                             (dir / "modelbase").string() + " --feature-radius 0.1m" + tail,
                         dir / "err", &err) == 2);
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("baseline: iteration and view counts are bounded (round 3, case 16)", "[baseline][cli]") {
  const fs::path dir = setup("bounds");
  const fs::path out = dir / "out.json";
  const std::string cmd = kBin + " -i " + (dir / "samples.pcd").string() + " --modelbase " +
                          (dir / "modelbase").string() + " -o " + out.string();
  std::string err;
  // The replay's values ran > 180 s; now usage errors naming the option and its bound.
  for (const auto& [option, bound] : std::vector<std::pair<std::string, std::string>>{
           {"--views 1000000", "--views must be in [0, 64]"},
           {"--ransac-iterations 2147483647", "--ransac-iterations must be in [1, 100000]"},
           {"--icp-iterations 2147483647", "--icp-iterations must be in [0, 500]"},
           {"--views 65", "--views must be in [0, 64]"},
           {"--ransac-iterations 100001", "--ransac-iterations must be in [1, 100000]"},
           {"--icp-iterations 501", "--icp-iterations must be in [0, 500]"}}) {
    INFO(option);
    CHECK(canopy::test::sh(cmd + " " + option, dir / "err", &err) == 2);
    CHECK(err.find(bound) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
  // The bounds themselves are accepted (the cheap one run here: VFH at 64 views).
  CHECK(canopy::test::sh(cmd + " --methods vfh --views 64", dir / "err", &err) == 0);
  CHECK(fs::exists(out));
}
