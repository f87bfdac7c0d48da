// The ncut binary: PLY mesh in, segment graph JSON (+ coloured PLY) out; bad input exits 1
// and leaves no output; reruns are byte-identical.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "canopy/common/atomic_file.h"
#include "support/cli.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/formats/ply.h"
#include "fixtures/ncut_meshes.h"

namespace fs = std::filesystem;
using namespace canopy;

namespace {

const std::string kBin = std::string(CANOPY_BIN_DIR) + "/ncut";

fs::path fresh_dir(const std::string& name) { return canopy::test::fresh_dir("ncut", name); }

using canopy::test::sh;

formats::Mesh to_mesh(const ncut::testing::TestMesh& m, bool normals) {
  formats::Mesh out;
  out.vertices.resize(m.in.points.size());
  for (const char* f : {"x", "y", "z"}) out.vertices.add(f, formats::kFloat32);
  if (normals) {
    for (const char* f : {"normal_x", "normal_y", "normal_z"}) out.vertices.add(f, formats::kFloat32);
  }
  out.vertices.add("label", formats::kUint32);
  for (std::size_t i = 0; i < m.in.points.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      out.vertices.col(std::string(1, "xyz"[k]))[i] = m.in.points[i][k];
      if (normals) out.vertices.col(std::string("normal_") + "xyz"[k])[i] = m.in.normals[i][k];
    }
    out.vertices.col("label")[i] = m.part[i] == 5 ? 2 : 1;  // the top face is "foliage"
  }
  for (const auto& f : m.in.faces) out.faces.push_back({f[0], f[1], f[2]});
  return out;
}

}  // namespace

TEST_CASE("ncut segments a box mesh, writes the coloured mesh, byte-identical reruns") {
  const fs::path dir = fresh_dir("ok");
  const auto box = ncut::testing::box({1.8, 1.0, 0.7}, 0.1);
  formats::write_ply(to_mesh(box, true), (dir / "mesh.ply").string());
  const std::string base = kBin + " -i " + (dir / "mesh.ply").string() + " --seed 7";
  std::string err;
  const std::string cmd = base + " -o " + (dir / "a.json").string() + " --colored " + (dir / "a.ply").string();
  REQUIRE(sh(cmd, dir / "err", &err) == 0);
  CHECK(err.find("ncut: segment:") != std::string::npos);
  const std::string first_json = common::read_file((dir / "a.json").string());
  const std::string first_ply = common::read_file((dir / "a.ply").string());
  REQUIRE(sh(cmd, dir / "err", &err) == 0);
  CHECK(common::read_file((dir / "a.json").string()) == first_json);
  CHECK(common::read_file((dir / "a.ply").string()) == first_ply);

  const documents::SegmentGraph g = documents::read_segment_graph((dir / "a.json").string());
  CHECK(g.segments.size() == 6);
  CHECK(g.adjacency.size() == 12);
  CHECK(g.provenance.tool == "ncut");
  int foliage = 0;
  for (const auto& s : g.segments) {
    CHECK(s.label_purity == Approx(1.0));
    foliage += s.label == 2;
  }
  CHECK(foliage == 1);

  const formats::Mesh colored = formats::read_ply((dir / "a.ply").string());
  REQUIRE(colored.vertices.has("segment"));
  REQUIRE(colored.vertices.has("red"));
  const auto& seg = colored.vertices.col("segment");
  for (const auto& s : g.segments) {
    for (int v : s.vertices) CHECK(seg[v] == s.segment_id);
  }
  const auto c = ncut::segment_colour(static_cast<int>(seg[0]));
  CHECK(colored.vertices.col("green")[0] == c[1]);

  // Through a pipe, and with --config of the shipped defaults: the same document.
  REQUIRE(sh("cat " + (dir / "mesh.ply").string() + " | " + kBin + " --seed 7 --config " + CANOPY_SOURCE_DIR +
                 "/share/params/ncut.ini > " + (dir / "c.json").string(),
             dir / "err", &err) == 0);
  const documents::SegmentGraph gc = documents::read_segment_graph((dir / "c.json").string());
  CHECK(gc.segments.size() == g.segments.size());
  for (std::size_t k = 0; k < gc.segments.size(); ++k) {
    CHECK(gc.segments[k].vertices == g.segments[k].vertices);
  }
}

TEST_CASE("ncut computes normals when the mesh has none, and says so") {
  const fs::path dir = fresh_dir("nonormals");
  formats::write_ply(to_mesh(ncut::testing::two_planes(1.0, 0.1), false), (dir / "mesh.ply").string());
  std::string err;
  REQUIRE(sh(kBin + " -i " + (dir / "mesh.ply").string() + " -o " + (dir / "s.json").string(), dir / "err",
             &err) == 0);
  CHECK(err.find("no normals") != std::string::npos);
  CHECK(documents::read_segment_graph((dir / "s.json").string()).segments.size() >= 2);
}

TEST_CASE("ncut rejects bad input with exit 1 and no output; bad options with exit 2") {
  const fs::path dir = fresh_dir("bad");
  std::string err;
  {
    std::ofstream f(dir / "garbage.ply");
    f << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n2\n";
  }
  CHECK(sh(kBin + " -i " + (dir / "garbage.ply").string() + " -o " + (dir / "o.json").string(), dir / "err",
           &err) == 1);
  CHECK(err.find("garbage.ply") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "o.json"));

  formats::Mesh no_faces = to_mesh(ncut::testing::two_planes(0.5, 0.1), true);
  no_faces.faces.clear();
  formats::write_ply(no_faces, (dir / "points.ply").string());
  CHECK(sh(kBin + " -i " + (dir / "points.ply").string() + " -o " + (dir / "o.json").string() +
               " --colored " + (dir / "o.ply").string(),
           dir / "err", &err) == 1);
  CHECK(err.find("no faces") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "o.json"));
  CHECK_FALSE(fs::exists(dir / "o.ply"));

  CHECK(sh(kBin + " -i " + (dir / "points.ply").string() + " --exponent cubic", dir / "err", &err) == 2);
  CHECK(sh(kBin + " -i " + (dir / "points.ply").string() + " --max-ncut 0", dir / "err", &err) == 2);
  CHECK(sh(kBin + " -i " + (dir / "missing.ply").string(), dir / "err", &err) == 1);
}
