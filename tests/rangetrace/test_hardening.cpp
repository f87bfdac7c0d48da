// rangetrace hardening (issue 12): awkward include paths, POV-Ray messages naming the user's
// file, the model-size warning, and signals stopping everything at once.
#include <catch2/catch.hpp>

#include <dirent.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "support/cli.h"

using namespace canopy;

namespace {

void write_text(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string bin() { return std::string(CANOPY_BIN_DIR) + "/rangetrace"; }

// Single-quoted for the shell (the test paths hold no single quote).
std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

std::vector<pid_t> children_of(pid_t parent) {
  std::vector<pid_t> out;
  if (DIR* d = ::opendir("/proc")) {
    while (dirent* e = ::readdir(d)) {
      const pid_t pid = std::atoi(e->d_name);
      if (pid <= 0) continue;
      std::ifstream status("/proc/" + std::to_string(pid) + "/status");
      for (std::string line; std::getline(status, line);) {
        if (line.rfind("PPid:", 0) == 0) {
          if (std::atoi(line.c_str() + 5) == parent) out.push_back(pid);
          break;
        }
      }
    }
    ::closedir(d);
  }
  return out;
}

// Processes (of any parent: POV-Ray runs in its own PID namespace under bwrap) whose working
// directory lies under `dir`: POV-Ray works in rangetrace's private directory there.
std::vector<pid_t> working_in(const std::filesystem::path& dir) {
  std::vector<pid_t> out;
  const std::string prefix = std::filesystem::canonical(dir).string() + "/";
  if (DIR* d = ::opendir("/proc")) {
    while (dirent* e = ::readdir(d)) {
      const pid_t pid = std::atoi(e->d_name);
      if (pid <= 0) continue;
      char cwd[4096];
      const ssize_t n = ::readlink(("/proc/" + std::to_string(pid) + "/cwd").c_str(), cwd, sizeof cwd - 1);
      if (n > 0 && std::string(cwd, n).rfind(prefix, 0) == 0) out.push_back(pid);
    }
    ::closedir(d);
  }
  return out;
}

// Waits up to 5 s for every process working under `dir` to be gone.
bool none_left_in(const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  while (!working_in(dir).empty()) {
    if (std::chrono::steady_clock::now() - start > std::chrono::seconds(5)) {
      for (pid_t p : working_in(dir)) {
        std::ifstream st("/proc/" + std::to_string(p) + "/stat");
        std::string t;
        std::getline(st, t);
        WARN("DEBUG left: " << t);
      }
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return true;
}

bool has_temp_dir(const std::filesystem::path& dir) {
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().filename().string().rfind("rangetrace-", 0) == 0) return true;
  }
  return false;
}

// Starts rangetrace on a render of many seconds (12 views of 1536^2 pixels under foliage) with
// TMPDIR = tmpdir, writing `out`; returns its pid.
pid_t start_long_render(const std::string& tmpdir, const std::string& out) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setenv("TMPDIR", tmpdir.c_str(), 1);
    const std::string b = bin();
    ::execl(b.c_str(), b.c_str(), "-q", "--model", "tank", "--scene", "circle", "--size", "1536", "--spacing",
            "10mm", "-o", out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// The POV-Ray processes of rangetrace `pid` once both are rendering (or those there are after 20 s).
std::vector<pid_t> wait_for_povray(pid_t pid) {
  std::vector<pid_t> kids;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
    kids = children_of(pid);
    if (kids.size() >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return kids;
}

}  // namespace

TEST_CASE("rangetrace CLI: a .inc in a directory with a space and a quote; errors name it") {
  const auto top = test::fresh_dir("rangetrace", "awkward");
  const auto dir = top / "with space \"q\"";
  const auto err_file = top / "err.txt";  // test::sh does not quote it
  std::filesystem::create_directories(dir);
  write_text(dir / "helper part.inc", "#declare Half = 1;\n");
  write_text(dir / "my \"model\".inc",
             "#include \"helper part.inc\"\n#declare Vehicle = box { <-2, 0, -Half>, <2, 1.5, Half> }\n");
  std::string err;
  const auto out = dir / "out.pcd";
  REQUIRE(test::sh(bin() + " --model " + q(dir / "my \"model\".inc") +
                       " --scene unoccluded --size 24 --spacing 0.4m -o " + q(out),
                   err_file, &err) == 0);
  CHECK(test::exists(out));

  write_text(dir / "bad.inc", "#declare Vehicle = union { box { 0, 1 }\n  spere { 0, 1 } }\n");
  CHECK(test::sh(
            bin() + " --model " + q(dir / "bad.inc") + " --scene unoccluded --size 8 -o " + q(dir / "bad.pcd"),
            err_file, &err) == 1);
  CHECK_THAT(err,
             Catch::Contains("File '" + (dir / "bad.inc").string() + "' line 2") && Catch::Contains("spere"));
  CHECK_FALSE(test::exists(dir / "bad.pcd"));

  // An include that leaves a brace open fails in the generated file: the message says where
  // to look.
  write_text(dir / "open.inc", "#declare Vehicle = union { box { <-1, 0, -1>, <1, 1, 1> }\n");
  CHECK(test::sh(bin() + " --model " + q(dir / "open.inc") + " --scene unoccluded --size 8 -o " +
                     q(dir / "open.pcd"),
                 err_file, &err) == 1);
  CHECK_THAT(err, Catch::Contains("check '" + (dir / "open.inc").string() + "' for an unclosed {"));
}

TEST_CASE("rangetrace CLI: a model of 40 m warns about --units mm before rendering") {
  const auto dir = test::fresh_dir("rangetrace", "huge");
  // 4000 x 1500 x 1000 "m": a 4 m vehicle modelled in millimetres.
  write_text(dir / "huge.inc", "#declare Vehicle = box { <-2000, 0, -750>, <2000, 1000, 750> }\n");
  std::string err;
  test::sh(bin() + " --model " + q(dir / "huge.inc") + " --scene unoccluded --size 8 -o " + q(dir / "huge.pcd"),
           dir / "err.txt", &err);
  const auto warn = err.find("did you forget --units mm?");
  CHECK(warn != std::string::npos);
  CHECK(warn < err.find("render:"));
  // Larger than the crop box but under 30 m: the other warning.
  write_text(dir / "long.inc", "#declare Vehicle = box { <-7, 0, -1>, <7, 2, 1> }\n");
  REQUIRE(test::sh(bin() + " --model " + q(dir / "long.inc") + " --scene unoccluded --size 8 -o " +
                       q(dir / "long.pcd"),
                   dir / "err.txt", &err) == 0);
  CHECK_THAT(err, Catch::Contains("larger than the crop box"));
}

TEST_CASE("rangetrace CLI: SIGINT, SIGTERM, SIGPIPE and SIGXFSZ stop POV-Ray at once and leave no temp dir") {
  // SIGPIPE and SIGXFSZ (stderr on a closed pipe, a file too large): common's atomic writer dies
  // of these (kCleanupSignals); rangetrace's POV-Ray cleanup used to handle SIGINT, SIGTERM and
  // SIGHUP only, so its private directory stayed behind.
  for (const int sig : {SIGINT, SIGTERM, SIGPIPE, SIGXFSZ}) {
    INFO("signal " << sig);
    const auto dir = test::fresh_dir("rangetrace", "signal" + std::to_string(sig));
    const std::string tmpdir = (dir / "tmp").string();
    std::filesystem::create_directories(tmpdir);
    const std::string out = (dir / "scan.pcd").string();
    const pid_t pid = start_long_render(tmpdir, out);
    REQUIRE(pid >= 0);
    std::vector<pid_t> kids = wait_for_povray(pid);
    REQUIRE(kids.size() >= 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kids = children_of(pid);
    REQUIRE(has_temp_dir(tmpdir));
    CHECK_FALSE(working_in(tmpdir).empty());  // POV-Ray, seen from here
    const auto sent = std::chrono::steady_clock::now();
    ::kill(pid, sig);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    CHECK(seconds < 2.0);
    for (const pid_t k : kids) CHECK(::kill(k, 0) != 0);  // killed and reaped
    CHECK(none_left_in(tmpdir));                          // nor any POV-Ray inside the jail
    CHECK_FALSE(has_temp_dir(tmpdir));
    CHECK_FALSE(test::exists(out));
  }
}

TEST_CASE("rangetrace CLI: a signal ignored at the start (nohup, a script's background job) stays ignored") {
  // nohup ignores SIGHUP, a shell script's `cmd &` ignores SIGINT: rangetrace's cleanup handler
  // used to replace the ignore and so died of the signal its caller had asked it to ignore.
  for (const int sig : {SIGHUP, SIGINT}) {
    INFO("signal " << sig);
    const auto dir = test::fresh_dir("rangetrace", "ignored" + std::to_string(sig));
    const std::string tmpdir = (dir / "tmp").string();
    std::filesystem::create_directories(tmpdir);
    const std::string out = (dir / "scan.pcd").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::signal(sig, SIG_IGN);
      ::setenv("TMPDIR", tmpdir.c_str(), 1);
      const std::string b = bin();
      ::execl(b.c_str(), b.c_str(), "-q", "--model", "sedan", "--scene", "circle", "--size", "256", "-o",
              out.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    REQUIRE(pid > 0);
    REQUIRE(wait_for_povray(pid).size() >= 1);
    ::kill(pid, sig);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(test::exists(out));
    CHECK_FALSE(has_temp_dir(tmpdir));
  }
}

TEST_CASE("rangetrace CLI: after SIGKILL, POV-Ray dies too and the next run removes the directory") {
  const auto dir = test::fresh_dir("rangetrace", "sigkill");
  const std::string tmpdir = (dir / "tmp").string();
  std::filesystem::create_directories(tmpdir);
  // A directory of a live process (this test) and one without an owner stay.
  std::filesystem::create_directories(dir / "tmp" / "rangetrace-live00");
  write_text(dir / "tmp" / "rangetrace-live00" / "owner", std::to_string(::getpid()) + "\n");
  std::filesystem::create_directories(dir / "tmp" / "rangetrace-noown0");
  const pid_t pid = start_long_render(tmpdir, (dir / "scan.pcd").string());
  REQUIRE(pid >= 0);
  const std::vector<pid_t> kids = wait_for_povray(pid);
  REQUIRE(kids.size() >= 1);
  ::kill(pid, SIGKILL);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (const pid_t k : kids) {
    // The children got SIGKILL when their parent died; reparented, they are reaped by init
    // (or are zombies of a subreaper): none may still be running.
    std::ifstream st("/proc/" + std::to_string(k) + "/stat");
    std::string text;
    std::getline(st, text);
    const auto paren = text.rfind(')');
    const char state = paren == std::string::npos || paren + 2 >= text.size() ? 'X' : text[paren + 2];
    CHECK((state == 'Z' || state == 'X'));
  }
  CHECK(none_left_in(tmpdir));  // nor any POV-Ray inside the jail
  int stale = 0;
  for (const auto& e : std::filesystem::directory_iterator(tmpdir)) {
    const auto n = e.path().filename().string();
    if (n != "rangetrace-live00" && n != "rangetrace-noown0") ++stale;
  }
  CHECK(stale == 1);  // the killed run's directory
  std::string err;
  REQUIRE(test::sh("TMPDIR=" + q(tmpdir) + " " + bin() + " --model sedan --scene unoccluded --size 8 -o " +
                       q(dir / "next.pcd"),
                   dir / "err.txt", &err) == 0);
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(tmpdir))
    left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  CHECK(left == std::vector<std::string>{"rangetrace-live00", "rangetrace-noown0"});
}

TEST_CASE("rangetrace CLI: a tile's scan and truth.json are written together or not at all") {
  // The directory of one output disappears while POV-Ray renders: the other output must not
  // be written either (an OutputSet commits both after both are complete).
  for (const bool lose_truth : {true, false}) {
    INFO("losing the directory of " << (lose_truth ? "truth.json" : "the scan"));
    const auto dir = test::fresh_dir("rangetrace", lose_truth ? "pair_truth" : "pair_scan");
    std::filesystem::create_directories(dir / "scan");
    std::filesystem::create_directories(dir / "truth");
    write_text(dir / "t.scene",
               "extent = 12m 10m\ntrees = 0\nbushes = 0\nhide = 0\nvehicle = sedan 6 5 10deg\n"
               "flight_lines = 1\nheadings = 0\nlooks = 90deg 60deg/0deg\nspacing = 0.02m\n"
               "canopy_spacing = 0.02m\n");
    const std::string scan = (dir / "scan" / "tile.las").string();
    const std::string truth = (dir / "truth" / "truth.json").string();
    const std::string recipe = (dir / "t.scene").string();
    const std::string err = (dir / "err.txt").string();
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      if (std::freopen(err.c_str(), "w", stderr) == nullptr) ::_exit(126);
      const std::string b = bin();
      ::execl(b.c_str(), b.c_str(), "--scene", recipe.c_str(), "-o", scan.c_str(), "--truth", truth.c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // Both outputs were checked before POV-Ray started; remove one directory while it runs.
    const auto start = std::chrono::steady_clock::now();
    while (children_of(pid).empty() && std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::filesystem::remove_all(dir / (lose_truth ? "truth" : "scan"));
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    std::ifstream f(err);
    const std::string msg((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    CHECK_THAT(msg, Catch::Contains(lose_truth ? "truth.json" : "tile.las"));
    CHECK_FALSE(msg.find("render:") == std::string::npos);  // it failed after the work
    CHECK_FALSE(test::exists(scan));
    CHECK_FALSE(test::exists(truth));
    if (test::exists(dir / "scan")) CHECK(std::filesystem::is_empty(dir / "scan"));
    if (test::exists(dir / "truth")) CHECK(std::filesystem::is_empty(dir / "truth"));
  }
}
