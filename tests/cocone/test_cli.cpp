// The cocone binary: files, pipes, bad input (exit codes, no partial output).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fixtures/cocone_samples.h"
#include "support/cli.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "cocone/cocone.h"

namespace fs = std::filesystem;
namespace fm = canopy::formats;

namespace {

const std::string kBin = std::string(CANOPY_BIN_DIR) + "/cocone";

fs::path tmp_dir() {
  const fs::path d = fs::path(CANOPY_TEST_TMP) / "cocone";
  fs::create_directories(d);
  return d;
}

int sh(const std::string& cmd) { return canopy::test::run(cmd); }

// The shared Fibonacci sphere, every sample labelled as target.
fm::PointCloud ball(int n, double r, double zc) {
  fm::PointCloud c = cocone_test::fibonacci_ball(n, r, zc);
  auto& label = c.add("label", fm::kUint32);
  for (int i = 0; i < n; ++i) label[i] = 1;
  return c;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST_CASE("cocone -i samples.pcd -o mesh.ply, and as a pipe filter, byte-identical") {
  const auto d = tmp_dir();
  fm::write_pcd(ball(800, 1.0, 1.5), (d / "ball.pcd").string());
  const auto out1 = d / "mesh1.ply", out2 = d / "mesh2.ply";
  REQUIRE(sh(kBin + " -q -i " + (d / "ball.pcd").string() + " -o " + out1.string()) == 0);
  REQUIRE(sh("cat " + (d / "ball.pcd").string() + " | " + kBin + " -q > " + out2.string()) == 0);
  const auto m = fm::read_ply(out1.string());
  CHECK(m.faces.size() > 0);
  CHECK(m.vertices.has("label"));
  // The pipe gives the same mesh (only the provenance comment names the input differently).
  const auto m2 = fm::read_ply(out2.string());
  CHECK(m2.faces == m.faces);
  CHECK(m2.vertices.col("x") == m.vertices.col("x"));
  // Provenance in the one format of every tool (formats/provenance.h).
  REQUIRE(m.vertices.comments.size() >= 3);
  CHECK(m.vertices.comments.front() == "cocone (canopy) " CANOPY_VERSION);
  CHECK(std::count(m.vertices.comments.begin(), m.vertices.comments.end(), "parameter flat-angle = 60deg") == 1);
  CHECK(m.vertices.comments.back() == "input " + (d / "ball.pcd").string());
  // Same input, same parameters: byte-identical file.
  const auto out3 = d / "mesh3.ply";
  REQUIRE(sh(kBin + " -q -i " + (d / "ball.pcd").string() + " -o " + out3.string()) == 0);
  CHECK((slurp(out1) == slurp(out3)));
}

TEST_CASE("bad input exits 1 with a message naming the file and writes nothing") {
  const auto d = tmp_dir();
  const auto out = d / "never.ply";
  fs::remove(out);
  { std::ofstream(d / "garbage.pcd") << "this is not a pcd\n"; }
  CHECK(sh(kBin + " -i " + (d / "garbage.pcd").string() + " -o " + out.string() + " 2>/dev/null") == 1);
  CHECK(!fs::exists(out));
  // Missing field z.
  fm::PointCloud c = ball(50, 1, 2);
  c.remove("z");
  fm::write_pcd(c, (d / "noz.pcd").string());
  CHECK(sh(kBin + " -i " + (d / "noz.pcd").string() + " -o " + out.string() + " 2>" +
           (d / "err.txt").string()) == 1);
  CHECK(slurp(d / "err.txt").find("noz.pcd") != std::string::npos);
  CHECK(!fs::exists(out));
  // Everything below 300 mm: zero faces after post-processing is an error.
  fm::write_pcd(ball(300, 0.1, 0.0), (d / "low.pcd").string());
  CHECK(sh(kBin + " -i " + (d / "low.pcd").string() + " -o " + out.string() + " 2>" +
           (d / "err.txt").string()) == 1);
  CHECK(slurp(d / "err.txt").find("no triangle left") != std::string::npos);
  CHECK(!fs::exists(out));
  // Coplanar samples.
  fm::PointCloud flat;
  flat.resize(16);
  flat.add("x");
  flat.add("y");
  flat.add("z");
  auto& x = flat.col("x");
  auto& y = flat.col("y");
  for (int i = 0; i < 16; ++i) {
    x[i] = i % 4;
    y[i] = i / 4 + 0.1 * i;
  }
  fm::write_pcd(flat, (d / "flat.pcd").string());
  CHECK(sh(kBin + " -i " + (d / "flat.pcd").string() + " -o " + out.string() + " 2>" +
           (d / "err.txt").string()) == 1);
  CHECK(slurp(d / "err.txt").find("coplanar") != std::string::npos);
  CHECK(!fs::exists(out));
}

TEST_CASE("a bad option value is a usage error (exit 2)") {
  CHECK(sh(kBin + " --max-aspect -1 -i /dev/null 2>/dev/null") == 2);
  CHECK(sh(kBin + " --min-height 3parsecs -i /dev/null 2>/dev/null") == 2);
}
