// The prepared models' side (baseline --prepare / --model-cache; issue 31): the same rankings
// as computing it per candidate, bit for bit, and a truncated, altered or mismatched file is
// refused with its name. Files only under the test's own temporary directory.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "baseline/baseline.h"
#include "baseline/model_cache.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "shapes.h"
#include "support/cli.h"

namespace bl = canopy::baseline;
namespace fs = std::filesystem;
using namespace baseline_test;

namespace {

const std::string kBin = std::string(CANOPY_BIN_DIR) + "/baseline";

std::vector<bl::Model> box_and_cylinder() { return {{"box", box()}, {"cylinder", cylinder()}}; }

std::vector<bl::SurfaceStamp> stamps() { return {{"box", 100, 0x1234}, {"cylinder", 200, 0x5678}}; }

// The message of the DataError that `f` throws, after checking it names `file`.
template <typename F>
std::string refusal(F f, const std::string& file) {
  try {
    f();
  } catch (const canopy::common::DataError& e) {
    CHECK(e.file() == file);
    return e.what();
  }
  FAIL("no DataError");
  return "";
}

}  // namespace

TEST_CASE("baseline: the prepared models' side gives the same rankings as computing it",
          "[baseline][cache]") {
  const Cloud raw = scene(box(), pose(0.4, {1, -2, 0}), {0, -1, 0}, 0.01, 5);
  const Cloud cand = bl::candidate_from_cloud(to_cloud(raw), "scene", 0.3);
  const auto models = box_and_cylinder();
  bl::Params p;
  const bl::PreparedModels prepared = bl::prepare_models(models, p, true, true);
  const std::string file = bl::serialize_prepared(prepared, p, stamps());
  const bl::PreparedModels read = bl::parse_prepared(file, "models.bin", p, stamps());
  REQUIRE(read.models.size() == 2);
  CHECK(read.models[0].points.size() == prepared.models[0].points.size());
  CHECK(read.models[0].features.size() == read.models[0].points.size());
  // Written again from what was read: the same bytes.
  CHECK(bl::serialize_prepared(read, p, stamps()) == file);
  for (const std::string methods : {"both", "vfh", "fpfh"}) {
    INFO(methods);
    p.methods = methods;
    const std::string computed = bl::serialize(bl::run(p, {&cand, &models}), "s", {}, {"s"});
    const std::string cached = bl::serialize(bl::run(p, {&cand, nullptr, &read}), "s", {}, {"s"});
    CHECK(cached == computed);
    if (methods == "both") CHECK(computed.find("\"model\": \"box\"") != std::string::npos);
  }
}

TEST_CASE("baseline: a truncated, altered or mismatched prepared file is refused by name",
          "[baseline][cache]") {
  const auto models = box_and_cylinder();
  const bl::Params p;
  const std::string file = bl::serialize_prepared(bl::prepare_models(models, p, true, true), p, stamps());
  const std::string path = "dir/models.bin";
  const auto parse = [&](const std::string& bytes, const bl::Params& q, const std::vector<bl::SurfaceStamp>& s) {
    return [&, bytes, q, s] { bl::parse_prepared(bytes, path, q, s); };
  };
  // Truncated in the body and in the header; empty.
  CHECK(refusal(parse(file.substr(0, file.size() - 7), p, stamps()), path).find("truncated") !=
        std::string::npos);
  CHECK(refusal(parse(file.substr(0, 60), p, stamps()), path).find("header") != std::string::npos);
  CHECK(refusal(parse("", p, stamps()), path).find("not a canopy.baseline-models") != std::string::npos);
  // One bit of the body flipped; a byte appended.
  std::string flipped = file;
  flipped[file.size() - 1000] ^= 0x10;
  CHECK(refusal(parse(flipped, p, stamps()), path).find("corrupt") != std::string::npos);
  CHECK(refusal(parse(file + "x", p, stamps()), path).find("corrupt") != std::string::npos);
  // Another version.
  std::string v2 = file;
  v2.replace(v2.find(" 1\n"), 3, " 2\n");
  CHECK(refusal(parse(v2, p, stamps()), path).find("version '2' unknown") != std::string::npos);
  // Other parameters of the models' side.
  bl::Params q;
  q.voxel = 0.25;
  CHECK(refusal(parse(file, q, stamps()), path).find("prepared with voxel 0.2") != std::string::npos);
  q = bl::Params{};
  q.views = 6;
  CHECK(refusal(parse(file, q, stamps()), path).find("views") != std::string::npos);
  // Parameters of the candidate's side only are no mismatch.
  q = bl::Params{};
  q.ransac_iterations = 10;
  q.min_height = 0.5;
  CHECK_NOTHROW(bl::parse_prepared(file, path, q, stamps()));
  // Another modelbase: a surface changed, one more, another name.
  auto s = stamps();
  s[1].fnv1a ^= 1;
  CHECK(refusal(parse(file, p, s), path).find("cylinder.pcd changed") != std::string::npos);
  s = stamps();
  s.push_back({"crate", 1, 1});
  CHECK(refusal(parse(file, p, s), path).find("another modelbase") != std::string::npos);
  s = stamps();
  s[0].name = "boxx";
  CHECK(refusal(parse(file, p, s), path).find("'box' where the modelbase has 'boxx'") != std::string::npos);
}

TEST_CASE("baseline --prepare and --model-cache: same bytes; a bad cache exits 1 naming it",
          "[baseline][cache][cli]") {
  const fs::path dir = canopy::test::fresh_dir("baseline", "cache");
  fs::create_directories(dir / "modelbase");
  canopy::formats::write_pcd(to_cloud(box()), (dir / "modelbase" / "box.pcd").string());
  canopy::formats::write_pcd(to_cloud(cylinder()), (dir / "modelbase" / "cylinder.pcd").string());
  canopy::formats::write_pcd(to_cloud(scene(box(), pose(1.0, {2, 3, 0}), {0, 1, 0}, 0.01, 3)),
                             (dir / "samples.pcd").string());
  const std::string mb = " --modelbase " + (dir / "modelbase").string();
  const std::string cache = (dir / "models.bin").string();
  const std::string run = kBin + " -i " + (dir / "samples.pcd").string() + mb;
  std::string err;
  REQUIRE(canopy::test::sh(kBin + " --prepare" + mb + " -o " + cache, dir / "err", &err) == 0);
  for (const std::string mode : {"", " --verdict fpfh", " --verdict vfh"}) {
    INFO(mode);
    REQUIRE(canopy::test::sh(run + mode + " -o " + (dir / "a.json").string(), dir / "err", &err) == 0);
    REQUIRE(canopy::test::sh(run + mode + " --model-cache " + cache + " -o " + (dir / "b.json").string(),
                             dir / "err", &err) == 0);
    CHECK(err.find("(prepared)") != std::string::npos);
    CHECK(canopy::common::read_file((dir / "a.json").string()) ==
          canopy::common::read_file((dir / "b.json").string()));
  }
  const fs::path out = dir / "out.json";
  const std::string cached = run + " --model-cache ";
  // Truncated.
  const std::string bytes = canopy::common::read_file(cache);
  canopy::test::write_file(dir / "short.bin", bytes.substr(0, bytes.size() / 2));
  CHECK(canopy::test::sh(cached + (dir / "short.bin").string() + " -o " + out.string(), dir / "err", &err) == 1);
  CHECK(err.find("short.bin") != std::string::npos);
  CHECK(err.find("truncated") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // Missing.
  CHECK(canopy::test::sh(cached + (dir / "none.bin").string() + " -o " + out.string(), dir / "err", &err) == 1);
  CHECK(err.find("none.bin") != std::string::npos);
  // Other parameters.
  CHECK(canopy::test::sh(cached + cache + " --voxel 0.3m -o " + out.string(), dir / "err", &err) == 1);
  CHECK(err.find("models.bin") != std::string::npos);
  CHECK(err.find("voxel") != std::string::npos);
  // The modelbase changed since: a surface rewritten.
  canopy::formats::write_pcd(to_cloud(box(4.2)), (dir / "modelbase" / "box.pcd").string());
  CHECK(canopy::test::sh(cached + cache + " -o " + out.string(), dir / "err", &err) == 1);
  CHECK(err.find("models.bin") != std::string::npos);
  CHECK(err.find("box.pcd changed") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // --prepare is its own mode.
  CHECK(canopy::test::sh(kBin + " --prepare --verdict fpfh" + mb + " -o " + out.string(), dir / "err", &err) ==
        2);
}
