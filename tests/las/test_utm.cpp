// Real-world coordinates end to end: a rendered scan shifted to UTM (E 500 000, N 4 400 000)
// must give the same samples (up to the shift), mesh, segments and ranking through
// fitvox | cocone | ncut | gmatch as the unshifted scan. Also the tools' LAS input and output
// and the format-choosing errors, on the same rendered scan.
#include <array>
#include <algorithm>
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include "canopy/formats/las.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/points_io.h"
#include "canopy/documents/segment_graph.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using namespace canopy::formats;
using namespace canopy::documents;

using canopy::test::run;
using canopy::test::sh;

namespace {

constexpr double kEast = 500000, kNorth = 4400000;  // a multiple of the 0.128 m voxel edge

std::string bin(const std::string& tool) { return std::string(CANOPY_BIN_DIR) + "/" + tool; }

// Renders once per test run: a two-model modelbase (sedan, tank; unoccluded) and a noisy
// sedan under foliage (256 x 256 pixels at 40 mm, to keep the test short).
const fs::path& scene_dir() {
  static const fs::path dir = [] {
    const fs::path d = canopy::test::fresh_dir("las", "utm");
    fs::create_directories(d / "mb");
    const std::string rt = bin("rangetrace") + " -q --size 256 --spacing 40mm";
    for (const std::string m : {"sedan", "tank"}) {
      REQUIRE(run(rt + " --model " + m + " --scene unoccluded --seed 11 | " + bin("fitvox") + " -q | " +
                  bin("cocone") + " -q | " + bin("ncut") + " -q --seed 11 -o " +
                  (d / "mb" / (m + ".json")).string()) == 0);
    }
    REQUIRE(run(rt + " --model sedan --scene circle --seed 12 | " + bin("addnoise") +
                " -q --sigma 4mm --seed 12 -o " + (d / "scan.pcd").string()) == 0);
    return d;
  }();
  return dir;
}

// fitvox | cocone | ncut | gmatch on `scan`, every intermediate kept as <tag>.*.
void pipeline(const fs::path& d, const std::string& scan, const std::string& tag) {
  const std::string p = (d / tag).string();
  REQUIRE(run(bin("fitvox") + " -q -i " + scan + " -o " + p + ".samples.pcd") == 0);
  REQUIRE(run(bin("cocone") + " -q -i " + p + ".samples.pcd -o " + p + ".mesh.ply") == 0);
  REQUIRE(run(bin("ncut") + " -q --seed 12 -i " + p + ".mesh.ply -o " + p + ".segments.json") == 0);
  REQUIRE(run(bin("gmatch") + " -q -i " + p + ".segments.json --modelbase " + (d / "mb").string() + " -o " +
              p + ".match.json") == 0);
}

// The unshifted run, made by the first test case (or here when a case runs alone).
void ensure_plain(const fs::path& d) {
  if (!fs::exists(d / "plain.match.json")) pipeline(d, (d / "scan.pcd").string(), "plain");
}

std::size_t distinct(const std::vector<double>& v) { return std::set<double>(v.begin(), v.end()).size(); }

}  // namespace

TEST_CASE("a UTM-shifted scan gives the same samples, mesh, segments and ranking", "[las][utm]") {
  const fs::path& d = scene_dir();
  PointCloud scan = read_points((d / "scan.pcd").string());
  REQUIRE(scan.type("x") == kFloat32);
  for (double& v : scan.col("x")) v += kEast;
  for (double& v : scan.col("y")) v += kNorth;
  write_points(scan, (d / "scan_utm.pcd").string());  // promoted to float64 x y
  REQUIRE(read_points((d / "scan_utm.pcd").string()).type("y") == kFloat64);

  pipeline(d, (d / "scan.pcd").string(), "plain");
  pipeline(d, (d / "scan_utm.pcd").string(), "utm");

  // Samples: same rows; coordinates equal after removing the shift to 1 µm. Shifting the input
  // costs the half-ulp of 4.4e6 m in double (4.7e-10 m); fitvox's resampling (a surface fitted
  // to the scan points in a ball) can move a point across a ball's edge at that level, which
  // moves a sample by up to ~0.3 µm — so not bit for bit, but far below float32's 0.25 m.
  const PointCloud a = read_points((d / "plain.samples.pcd").string());
  const PointCloud b = read_points((d / "utm.samples.pcd").string());
  REQUIRE(a.size() > 500);
  REQUIRE(b.size() == a.size());
  CHECK(a.type("x") == kFloat32);  // near the origin the files are what they always were
  CHECK(b.type("x") == kFloat64);
  // float32 gave 192 distinct x among 3126 samples; float64 keeps (almost) every one distinct.
  CHECK(distinct(b.col("x")) + 2 >= distinct(a.col("x")));
  CHECK(distinct(b.col("x")) * 10 > b.size() * 9);
  double worst_p = 0, worst_n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst_p = std::max({worst_p, std::fabs(b.col("x")[i] - kEast - a.col("x")[i]),
                        std::fabs(b.col("y")[i] - kNorth - a.col("y")[i]),
                        std::fabs(b.col("z")[i] - a.col("z")[i])});
    for (const char* n : {"normal_x", "normal_y", "normal_z"})
      worst_n = std::max(worst_n, std::fabs(b.col(n)[i] - a.col(n)[i]));
    CHECK(b.col("point_count")[i] == a.col("point_count")[i]);
  }
  CHECK(worst_p < 1e-6);
  CHECK(worst_n < 1e-6);

  // Mesh: the same vertices; triangles the same up to the few that sub-micrometre sample
  // differences can flip in cocone's Delaunay-based choices (at most 1%).
  const Mesh ma = read_ply((d / "plain.mesh.ply").string());
  const Mesh mb = read_ply((d / "utm.mesh.ply").string());
  CHECK(ma.faces.size() > 300);
  {
    std::set<std::array<std::size_t, 3>> fa, fb;
    auto key = [](const auto& f) {
      std::array<std::size_t, 3> k{static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]),
                                   static_cast<std::size_t>(f[2])};
      std::sort(k.begin(), k.end());
      return k;
    };
    for (const auto& f : ma.faces) fa.insert(key(f));
    for (const auto& f : mb.faces) fb.insert(key(f));
    std::size_t common = 0;
    for (const auto& k : fa) common += fb.count(k);
    CHECK(common * 100 >= fa.size() * 99);
    CHECK(common * 100 >= fb.size() * 99);
  }
  CHECK(mb.vertices.size() == ma.vertices.size());
  CHECK(mb.vertices.type("x") == kFloat64);

  // Segments: the same segmentation up to those few triangles: same number of segments (±1),
  // and the total area within 1%.
  const SegmentGraph ga = read_segment_graph((d / "plain.segments.json").string());
  const SegmentGraph gb = read_segment_graph((d / "utm.segments.json").string());
  REQUIRE(ga.segments.size() > 3);
  CHECK(gb.segments.size() + 1 >= ga.segments.size());
  CHECK(gb.segments.size() <= ga.segments.size() + 1);
  double area_a = 0, area_b = 0;
  for (const auto& sg : ga.segments) area_a += sg.area;
  for (const auto& sg : gb.segments) area_b += sg.area;
  CHECK(area_b == Approx(area_a).epsilon(0.01));

  // Ranking: same order, scores within 0.01.
  const MatchResult ra = read_match_result((d / "plain.match.json").string());
  const MatchResult rb = read_match_result((d / "utm.match.json").string());
  REQUIRE(ra.models.size() == 2);
  CHECK(ra.models[0].model == "sedan");
  for (std::size_t m = 0; m < 2; ++m) {
    CHECK(rb.models[m].model == ra.models[m].model);
    CHECK(rb.models[m].score == Approx(ra.models[m].score).margin(0.01));
  }
}

TEST_CASE("a UTM scan as LAS (1 mm grid) runs through the tools and ranks the same", "[las][utm][cli]") {
  const fs::path& d = scene_dir();
  PointCloud scan = read_points((d / "scan.pcd").string());
  for (double& v : scan.col("x")) v += kEast;
  for (double& v : scan.col("y")) v += kNorth;
  const std::string las = (d / "scan_utm.las").string();
  write_points(scan, las);
  // Stdin: the format comes from the bytes.
  REQUIRE(run("cat " + las + " | " + bin("addnoise") + " -q --sigma 0 -o " + (d / "copy.las").string()) == 0);
  const PointCloud copy = read_las((d / "copy.las").string());
  REQUIRE(copy.size() == scan.size());
  CHECK(copy.has("sensor_x"));  // canopy fields travel as Extra Bytes
  CHECK(copy.type("label") == kUint32);
  pipeline(d, (d / "copy.las").string(), "las");
  ensure_plain(d);
  const PointCloud s = read_points((d / "las.samples.pcd").string());
  const PointCloud a = read_points((d / "plain.samples.pcd").string());
  CHECK(s.type("x") == kFloat64);
  // The 1 mm grid moves points by up to 0.5 mm: close to, not equal to, the float run.
  CHECK(std::fabs(static_cast<double>(s.size()) - static_cast<double>(a.size())) <
        0.05 * static_cast<double>(a.size()));
  const MatchResult r = read_match_result((d / "las.match.json").string());
  CHECK(r.models[0].model == "sedan");

  // fitvox writes LAS when asked by name; pcd2ply and cocone read it.
  REQUIRE(run(bin("fitvox") + " -q -i " + las + " -o " + (d / "samples.las").string()) == 0);
  CHECK(read_las((d / "samples.las").string()).has("mean_curvature"));
  REQUIRE(run(bin("cocone") + " -q -i " + (d / "samples.las").string() + " -o " +
              (d / "from_las.ply").string()) == 0);
  CHECK(read_ply((d / "from_las.ply").string()).faces.size() > 300);
  REQUIRE(run(bin("pcd2ply") + " -q -i " + (d / "samples.las").string() + " -o " +
              (d / "samples.ply").string()) == 0);
  CHECK(read_points((d / "samples.ply").string()).size() == read_las((d / "samples.las").string()).size());
}

TEST_CASE("tools: wrong formats are named, unknown output extensions are usage errors", "[las][cli]") {
  const fs::path& d = scene_dir();
  const fs::path err = d / "err.txt";
  std::string e;
  ensure_plain(d);
  // A mesh where points are expected.
  CHECK(sh(bin("fitvox") + " -q -i " + (d / "plain.mesh.ply").string() + " -o " + (d / "no.pcd").string(),
           err, &e) == 1);
  CHECK(e.find("plain.mesh.ply: this is a PLY mesh with") != std::string::npos);
  CHECK(e.find("faces; fitvox reads points") != std::string::npos);
  CHECK_FALSE(fs::exists(d / "no.pcd"));
  // A JSON document.
  CHECK(sh(bin("addnoise") + " -q -i " + (d / "plain.segments.json").string() + " -o " + (d / "no.pcd").string(),
           err, &e) == 1);
  CHECK(e.find("this is a JSON document (canopy.segment_graph)") != std::string::npos);
  // Output names: an unknown extension is a usage error before any work.
  CHECK(sh(bin("fitvox") + " -q -i " + (d / "scan.pcd").string() + " -o " + (d / "samples.txt").string(), err,
           &e) == 2);
  CHECK(e.find("unknown extension '.txt'") != std::string::npos);
  CHECK_FALSE(fs::exists(d / "samples.txt"));
  CHECK(sh(bin("addnoise") + " -q -i " + (d / "scan.pcd").string() + " -o " + (d / "noisy.xyz").string(), err,
           &e) == 2);
  CHECK(e.find("unknown extension '.xyz'") != std::string::npos);
  // No extension: PCD, the default (FIFOs and devices have none).
  REQUIRE(run(bin("addnoise") + " -q -i " + (d / "scan.pcd").string() + " -o " + (d / "noisy").string()) == 0);
  CHECK(read_points((d / "noisy").string()).size() == read_points((d / "scan.pcd").string()).size());
  // -o samples.ply writes PLY (it wrote PCD before).
  REQUIRE(run(bin("fitvox") + " -q -i " + (d / "scan.pcd").string() + " -o " +
              (d / "fitvox_samples.ply").string()) == 0);
  const Mesh m = read_ply((d / "fitvox_samples.ply").string());
  CHECK(m.faces.empty());
  CHECK(m.vertices.size() == read_points((d / "plain.samples.pcd").string()).size());
}
