// detect's output directory replacement (tools/detect/output.h): only what detect can prove it
// wrote is replaced; at every step the old or the new complete output is at the path; leftovers
// of killed runs are removed by the next run. A kill between two steps is a real SIGKILL of a
// forked child at a hook of write_output (issue 25, items 2 and 8).
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/ply.h"
#include "detect/crops.h"
#include "detect/output.h"
#include "support/cli.h"

using namespace canopy;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// A tile of 3 points and a result with `n` candidates of 3 points each (no detection run).
struct Fixture {
  formats::PointCloud tile;
  detect::Result result;
};

Fixture fixture(int n) {
  Fixture f;
  auto& x = f.tile.add("x", formats::kFloat64);
  f.tile.add("y", formats::kFloat64);
  f.tile.add("z", formats::kFloat64);
  f.tile.resize(3);
  for (int i = 0; i < 3; ++i) x[std::size_t(i)] = i;
  f.result.stats.points = 3;
  f.result.height.assign(3, 0.f);
  f.result.classes.assign(3, detect::kClassGround);
  for (int k = 1; k <= n; ++k) {
    detect::Candidate c;
    char id[16];
    std::snprintf(id, sizeof id, "c%04d", k);
    c.id = id;
    auto& cx = c.cloud.add("x", formats::kFloat32);
    c.cloud.add("y", formats::kFloat32);
    c.cloud.add("z", formats::kFloat32);
    c.cloud.resize(3);
    for (int i = 0; i < 3; ++i) cx[std::size_t(i)] = k + i;
    f.result.candidates.push_back(std::move(c));
  }
  return f;
}

void write(const fs::path& out, int candidates, const detect::WriteHooks& hooks = {},
           const std::string& tile = "tile.pcd") {
  const Fixture f = fixture(candidates);
  const formats::Provenance prov{"detect", "test", {}, {tile}};
  detect::write_output(out.string(), f.tile, f.result, detect::Params{}, prov, tile, true, hooks);
}

// Runs write() in a child that is killed with `sig` at hook step `at`; returns the child's
// status. The child's signal dispositions are the defaults (not Catch2's handlers).
int write_killed_at(const fs::path& out, int candidates, const std::string& at, int sig, bool no_exchange) {
  const pid_t pid = fork();
  if (pid == 0) {
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) std::signal(s, SIG_DFL);
    detect::WriteHooks hooks;
    hooks.no_exchange = no_exchange;
    hooks.step = [&](const std::string& step) {
      if (step == at) raise(sig);
    };
    try {
      write(out, candidates, hooks);
    } catch (...) { _exit(3); }
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

std::size_t candidates_in(const fs::path& out) {
  std::ifstream f(out / "index.json");
  return Json::parse(f)["candidates"].size();
}

// The entries beside `out` whose names begin with ".<name>." (temporaries, leftovers).
std::vector<std::string> beside(const fs::path& out) {
  std::vector<std::string> v;
  const std::string prefix = "." + out.filename().string() + ".";
  for (const auto& e : fs::directory_iterator(out.parent_path())) {
    const std::string n = e.path().filename().string();
    if (n.compare(0, prefix.size(), prefix) == 0) v.push_back(n);
  }
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

// A complete output: check_output_dir accepts it (manifest, sizes, hashes) and it has n candidates.
void require_complete(const fs::path& out, std::size_t n) {
  REQUIRE(fs::is_directory(out));
  REQUIRE_NOTHROW(detect::check_output_dir(out.string(), "-"));
  CHECK(candidates_in(out) == n);
}

void touch(const fs::path& p, const std::string& text = "x") { std::ofstream(p) << text; }

}  // namespace

TEST_CASE("output: a fresh output and its manifest") {
  const fs::path dir = test::fresh_dir("detect", "out_fresh");
  const fs::path out = dir / "cands";
  write(out, 2);
  CHECK(listing(out) ==
        std::vector<std::string>{"c0001.pcd", "c0002.pcd", "classes.ply", "index.json", "manifest.json"});
  std::ifstream f(out / "manifest.json");
  const Json m = Json::parse(f);
  CHECK(m["format"] == "canopy.detect_manifest");
  CHECK(m["version"] == 1);
  REQUIRE(m["files"].size() == 4);
  CHECK(m["files"][3]["name"] == "index.json");  // the index last, as written
  for (const auto& e : m["files"]) {
    CHECK(e["bytes"].get<std::uintmax_t>() == fs::file_size(out / e["name"].get<std::string>()));
    CHECK(e["sha256"].get<std::string>().size() == 64);
  }
  // SHA-256 of the index, by sha256sum (coreutils), an independent implementation.
  const fs::path sum = dir / "sum.txt";
  REQUIRE(test::run("cd '" + out.string() + "' && sha256sum index.json > '" + sum.string() + "'") == 0);
  std::ifstream s(sum);
  std::string hash;
  s >> hash;
  CHECK(m["files"][3]["sha256"] == hash);
  CHECK(beside(out).empty());
  // A re-run replaces it.
  write(out, 3);
  require_complete(out, 3);
  CHECK(beside(out).empty());
}

TEST_CASE("output: what is refused, and nothing is deleted") {
  const fs::path dir = test::fresh_dir("detect", "out_refused");
  const fs::path out = dir / "cands";
  SECTION("a directory holding a file called index.json (replay case 3)") {
    fs::create_directories(out / "src");
    touch(out / "index.json", "{\"name\": \"my-web-app\"}");
    touch(out / "app.js", "precious");
    touch(out / "src" / "main.c", "code");
    CHECK_THROWS_WITH(write(out, 1), Catch::Contains(out.string() + ": refusing to replace it") &&
                                         Catch::Contains("no manifest.json") &&
                                         Catch::Contains("app.js, index.json, src/"));
    CHECK(listing(out) == std::vector<std::string>{"app.js", "index.json", "src"});
    CHECK(fs::exists(out / "src" / "main.c"));
  }
  SECTION("a previous output with a file the user added") {
    write(out, 1);
    touch(out / "NOTES.txt");
    CHECK_THROWS_WITH(write(out, 2), Catch::Contains("NOTES.txt, which detect did not write"));
    CHECK(fs::exists(out / "NOTES.txt"));
    CHECK(candidates_in(out) == 1);
  }
  SECTION("a previous output with a file changed since") {
    write(out, 1);
    { std::ofstream(out / "c0001.pcd", std::ios::app) << " "; }
    CHECK_THROWS_WITH(write(out, 2), Catch::Contains("c0001.pcd changed since detect wrote it"));
    CHECK(candidates_in(out) == 1);
  }
  SECTION("a previous output with a listed file missing") {
    write(out, 2);
    fs::remove(out / "c0002.pcd");
    CHECK_THROWS_WITH(write(out, 1), Catch::Contains("c0002.pcd, listed in its manifest.json, missing"));
  }
  SECTION("a previous output holding the input tile") {
    write(out, 1);
    touch(out / "tile.pcd");
    CHECK_THROWS_WITH(write(out, 2, {}, (out / "tile.pcd").string()),
                      Catch::Contains("holds the input tile"));
    CHECK(fs::exists(out / "tile.pcd"));
  }
  SECTION("a manifest that is not detect's") {
    fs::create_directories(out);
    touch(out / "manifest.json", "{\"format\": \"something\", \"version\": 1}");
    touch(out / "index.json");
    CHECK_THROWS_WITH(write(out, 1), Catch::Contains("manifest.json is not detect's"));
    CHECK(fs::exists(out / "index.json"));
  }
  SECTION("a chain directory holding something the chain does not write") {
    write(out, 1);
    fs::create_directories(out / "c0001");
    touch(out / "c0001" / "samples.pcd");
    touch(out / "c0001" / "notes.txt");
    CHECK_THROWS_WITH(write(out, 2), Catch::Contains("c0001/notes.txt"));
    CHECK(fs::exists(out / "c0001" / "notes.txt"));
  }
  SECTION("a directory for a candidate the output does not list") {
    write(out, 1);
    fs::create_directories(out / "c0002");
    CHECK_THROWS_WITH(write(out, 2), Catch::Contains("c0002/"));
  }
  SECTION("a file") {
    touch(out, "keep me");
    CHECK_THROWS_WITH(write(out, 1), Catch::Contains("exists and is not a directory"));
    CHECK(fs::is_regular_file(out));
  }
  SECTION("a missing parent directory is not created") {
    CHECK_THROWS_WITH(write(dir / "no" / "cands", 1),
                      Catch::Contains("directory '" + (dir / "no").string() + "' does not exist"));
    CHECK(!fs::exists(dir / "no"));
  }
  CHECK(beside(out).empty());
}

TEST_CASE("output: what is replaced") {
  const fs::path dir = test::fresh_dir("detect", "out_replaced");
  const fs::path out = dir / "cands";
  SECTION("an empty directory") {
    fs::create_directories(out);
    write(out, 1);
    require_complete(out, 1);
  }
  SECTION("a previous output with the chain's per-candidate directories (mk/scenes.mk)") {
    write(out, 2);
    fs::create_directories(out / "c0001");
    for (const char* n :
         {"samples.pcd", "samples.pcd.log", "samples.pcd.time", "mesh.ply", "segments.json", "verdict.json",
          "baseline-ransac.json", "match.json.time.tmp", ".mesh.tmp77-0.ply"}) {
      touch(out / "c0001" / n);
    }
    write(out, 1);
    require_complete(out, 1);
    CHECK(!fs::exists(out / "c0001" / "samples.pcd"));  // the old chain outputs went with the old index
  }
  SECTION("an output written before manifests (index.json by detect names every file)") {
    write(out, 2);
    fs::remove(out / "manifest.json");
    write(out, 1);
    require_complete(out, 1);
    SECTION("... but not with a file its index does not name") {
      fs::remove(out / "manifest.json");
      touch(out / "NOTES.txt");
      CHECK_THROWS_WITH(write(out, 1),
                        Catch::Contains("NOTES.txt, which detect did not write (not in its index.json)"));
    }
  }
  SECTION("through a symbolic link: the directory it names; the link stays") {
    fs::create_directories(dir / "real");
    fs::create_directory_symlink("real", dir / "link");
    write(dir / "link", 1);
    CHECK(fs::is_symlink(dir / "link"));
    require_complete(dir / "real", 1);
    write(dir / "link", 2);
    CHECK(fs::is_symlink(dir / "link"));
    require_complete(dir / "real", 2);
    CHECK(beside(dir / "real").empty());
  }
  SECTION("a dangling symbolic link: the directory it names is created") {
    fs::create_directory_symlink("made", dir / "link");
    write(dir / "link", 1);
    require_complete(dir / "made", 1);
  }
  CHECK(beside(out).empty());
}

TEST_CASE("output: at every step the old or the new complete output is at the path") {
  const fs::path dir = test::fresh_dir("detect", "out_steps");
  const fs::path out = dir / "cands";
  write(out, 1);
  std::vector<std::string> steps;
  detect::WriteHooks hooks;
  hooks.step = [&](const std::string& step) {
    steps.push_back(step);
    require_complete(out, step == "swapped" ? 2 : 1);
  };
  write(out, 2, hooks);
  CHECK(steps == std::vector<std::string>{"created", "written", "swapped"});
  require_complete(out, 2);
  CHECK(beside(out).empty());
}

TEST_CASE("output: killed runs (SIGKILL) leave a complete output, and the next run removes their leftovers") {
  const fs::path dir = test::fresh_dir("detect", "out_killed");
  const fs::path out = dir / "cands";
  write(out, 1);
  SECTION("killed after the swap, before the old output is removed") {
    const int status = write_killed_at(out, 2, "swapped", SIGKILL, false);
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGKILL);
    require_complete(out, 2);
    REQUIRE(beside(out).size() == 1);  // .cands.tmp<pid>: the old output
    CHECK(beside(out)[0].rfind(".cands.tmp", 0) == 0);
    write(out, 3);
    require_complete(out, 3);
  }
  SECTION("killed before the swap") {
    for (const char* at : {"created", "written"}) {
      INFO(at);
      const int status = write_killed_at(out, 2, at, SIGKILL, false);
      REQUIRE(WIFSIGNALED(status));
      require_complete(out, 1);
      CHECK(beside(out).size() == 1);
    }
    // One leftover, not two: the second child's run removed the first one's (not locked, marked).
    write(out, 3);
    require_complete(out, 3);
  }
  SECTION("killed between the two renames of the fallback (no RENAME_EXCHANGE)") {
    const int status = write_killed_at(out, 2, "aside", SIGKILL, true);
    REQUIRE(WIFSIGNALED(status));
    // The documented window of the fallback: nothing at the path, both outputs beside it.
    CHECK(!fs::exists(out));
    CHECK(beside(out).size() == 2);
    write(out, 3);
    require_complete(out, 3);
  }
  SECTION("the fallback, not killed") {
    detect::WriteHooks hooks;
    hooks.no_exchange = true;
    write(out, 2, hooks);
    require_complete(out, 2);
  }
  CHECK(beside(out).empty());
}

TEST_CASE("output: SIGTERM or SIGINT while writing removes the temporary directory") {
  const fs::path dir = test::fresh_dir("detect", "out_sigterm");
  const fs::path out = dir / "cands";
  for (const int sig : {SIGTERM, SIGINT}) {
    INFO("signal " << sig);
    fs::remove_all(out);
    // A fresh output.
    int status = write_killed_at(out, 2, "written", sig, false);
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    CHECK(!fs::exists(out));
    CHECK(beside(out).empty());
    // Replacing an output.
    write(out, 1);
    status = write_killed_at(out, 2, "created", sig, false);
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    require_complete(out, 1);
    CHECK(beside(out).empty());
  }
}

TEST_CASE("output: leftovers of other runs") {
  const fs::path dir = test::fresh_dir("detect", "out_leftovers");
  const fs::path out = dir / "cands";
  write(out, 1);
  SECTION("a live run's (locked) temporary directory is left alone") {
    const fs::path live = dir / ".cands.tmp999999999";
    fs::create_directories(live);
    touch(live / ".detect-partial", "");
    const int fd = ::open(live.c_str(), O_RDONLY | O_DIRECTORY);
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX) == 0);
    write(out, 2);  // the lock is per open file description: this run's flock fails
    CHECK(fs::exists(live));
    ::close(fd);
    write(out, 3);
    CHECK(!fs::exists(live));
  }
  SECTION("an older detect's leftovers: .cands.old<pid> (a whole output) and .cands.tmp<pid> (partial)") {
    fs::copy(out, dir / ".cands.old4242");
    fs::remove(dir / ".cands.old4242" / "manifest.json");  // older detects wrote no manifest
    fs::create_directories(dir / ".cands.tmp4243");
    write(out, 2);
    CHECK(beside(out).empty());
  }
  SECTION("a directory named like a leftover without detect's marks is left alone") {
    fs::create_directories(dir / ".cands.tmp4244");
    touch(dir / ".cands.tmp4244" / "mine.txt");
    write(out, 2);
    CHECK(fs::exists(dir / ".cands.tmp4244" / "mine.txt"));
    fs::remove_all(dir / ".cands.tmp4244");
  }
  CHECK_NOTHROW(detect::check_output_dir(out.string(), "-"));
  CHECK(beside(out).empty());
}

TEST_CASE("output: classes.ply written in pieces is the PLY of the classification cloud, byte for byte") {
  // cost.md §17: the file is made block by block (never whole in memory); the bytes are those
  // formats::serialize_ply writes for classification_cloud with the same comments.
  Fixture f = fixture(1);
  const std::size_t n = 70000;  // more than one block of 65 536 rows
  auto& x = f.tile.col("x");
  auto& y = f.tile.col("y");
  auto& z = f.tile.col("z");
  f.tile.resize(n);
  f.result.height.resize(n);
  f.result.classes.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 500000.0 + 0.013 * double(i);
    y[i] = 5400000.0 - 0.007 * double(i);
    z[i] = 100.0 + 1e-4 * double(i % 1000);
    f.result.height[i] = 0.001f * float(i % 4000);
    f.result.classes[i] = static_cast<std::uint8_t>(i % 5);  // 4 (no such class) draws as 3
  }
  f.result.origin = Eigen::Vector3d(500000.0, 5400000.0, 100.0);
  const std::vector<std::string> prov{"detect (canopy) test", "parameter cell = 500mm"};
  formats::Mesh m;
  m.vertices = detect::classification_cloud(f.tile, f.result);
  m.vertices.comments = prov;
  m.vertices.comments.push_back("classes 1 ground (brown), 2 vegetation/other (green), 3 candidate (red)");
  m.vertices.comments.push_back("origin 500000 5400000 100 (add to x y z for tile coordinates)");
  const std::string whole = formats::serialize_ply(m);
  std::string pieces;
  int calls = 0;
  detect::classes_ply(f.tile, f.result, prov, [&](const char* p, std::size_t k) {
    pieces.append(p, k);
    ++calls;
  });
  CHECK(calls == 3);  // the header, then two blocks
  CHECK(pieces.size() == whole.size());
  CHECK(pieces == whole);
  CHECK(detect::classes_ply(f.tile, f.result, prov) == whole);
  // And what write_output wrote, listed in the manifest with its size.
  const fs::path dir = test::fresh_dir("detect", "classes_pieces");
  const formats::Provenance p{"detect", "test", {}, {"tile.pcd"}};
  detect::write_output((dir / "out").string(), f.tile, f.result, detect::Params{}, p, "tile.pcd", true);
  const formats::Mesh back = formats::read_ply((dir / "out" / "classes.ply").string());
  CHECK(back.vertices.size() == n);
  CHECK(back.vertices.col("class")[4] == 4);
  CHECK(back.vertices.col("red")[4] == 230);
  CHECK(back.vertices.col("x")[1] == Approx(0.013));
  const Json manifest = Json::parse(std::ifstream((dir / "out" / "manifest.json").string()));
  bool listed = false;
  for (const auto& file : manifest["files"]) {
    if (file["name"] == "classes.ply") listed = file["bytes"] == fs::file_size(dir / "out" / "classes.ply");
  }
  CHECK(listed);
}
