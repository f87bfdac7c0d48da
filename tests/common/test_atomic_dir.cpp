// common::AtomicDir: a directory built beside its destination and swapped into place as a whole
// (detect's output directory). Hand-made directories in the test's temporary directory.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "canopy/common/atomic_dir.h"
#include "canopy/common/error.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using canopy::common::AtomicDir;
using canopy::common::DataError;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

const std::string kTemp = ".out.tmp" + std::to_string(::getpid());
const std::string kOld = ".out.old" + std::to_string(::getpid());

}  // namespace

TEST_CASE("AtomicDir: a new directory appears whole at publish, its temporary name is gone", "[atomic_dir]") {
  const fs::path parent = canopy::test::fresh_dir("common", "atomic_dir_new");
  {
    AtomicDir d(parent, "out", "out", "");
    CHECK(d.temp() == parent / kTemp);
    d.write("a.txt", "hello");
    d.write("b.txt", "");
    CHECK(names_in(parent) == std::vector<std::string>{kTemp});  // nothing at the path yet
    bool removed_old = false;
    d.publish([] { return false; }, [&](const fs::path&) { removed_old = true; });
    CHECK_FALSE(removed_old);
  }
  CHECK(names_in(parent) == std::vector<std::string>{"out"});
  CHECK(names_in(parent / "out") == std::vector<std::string>{"a.txt", "b.txt"});
  CHECK(slurp(parent / "out" / "a.txt") == "hello");
}

TEST_CASE("AtomicDir: an existing directory is exchanged, or moved aside, and the old one handed back",
          "[atomic_dir]") {
  for (const bool no_exchange : {false, true}) {
    const fs::path parent = canopy::test::fresh_dir("common", "atomic_dir_replace");
    fs::create_directory(parent / "out");
    canopy::test::write_file(parent / "out" / "old.txt", "old");
    std::vector<std::string> steps;
    fs::path old_at;
    std::vector<std::string> old_held;
    {
      AtomicDir d(parent, "out", "out", "", {[&](const std::string& s) { steps.push_back(s); }, no_exchange});
      d.write("new.txt", "new");
      d.publish([] { return true; },
                [&](const fs::path& old) {
                  old_at = old;
                  old_held = names_in(old);
                  // The new directory is already at the path while the old one is removed.
                  CHECK(slurp(parent / "out" / "new.txt") == "new");
                  fs::remove_all(old);
                });
    }
    CHECK(old_held == std::vector<std::string>{"old.txt"});
    if (no_exchange) {
      CHECK(steps == std::vector<std::string>{"aside", "swapped"});
      CHECK(old_at == parent / kOld);
    } else {
      CHECK(steps == std::vector<std::string>{"swapped"});
      CHECK(old_at == parent / kTemp);  // the names were exchanged
    }
    CHECK(names_in(parent) == std::vector<std::string>{"out"});
    CHECK(names_in(parent / "out") == std::vector<std::string>{"new.txt"});
  }
}

TEST_CASE("AtomicDir: not published (an error, a refusal) leaves the path as it was, no temporary",
          "[atomic_dir]") {
  const fs::path parent = canopy::test::fresh_dir("common", "atomic_dir_abandoned");
  fs::create_directory(parent / "out");
  canopy::test::write_file(parent / "out" / "old.txt", "old");
  SECTION("destroyed without publish") {
    {
      AtomicDir d(parent, "out", "out", "");
      d.write("new.txt", "new");
    }
  }
  SECTION("the check refuses the replacement") {
    AtomicDir d(parent, "out", "out", "");
    d.write("new.txt", "new");
    bool removed_old = false;
    CHECK_THROWS_WITH(d.publish([]() -> bool { throw std::runtime_error("not ours"); },
                                [&](const fs::path&) { removed_old = true; }),
                      "not ours");
    CHECK_FALSE(removed_old);
  }
  CHECK(names_in(parent) == std::vector<std::string>{"out"});
  CHECK(names_in(parent / "out") == std::vector<std::string>{"old.txt"});
}

TEST_CASE("AtomicDir: refusals name the file", "[atomic_dir]") {
  const fs::path parent = canopy::test::fresh_dir("common", "atomic_dir_errors");
  AtomicDir d(parent, "out", "out", "");
  d.write("a.txt", "1");
  try {
    d.write("a.txt", "2");  // files are new: never overwritten
    FAIL("no error");
  } catch (const DataError& e) {
    CHECK(std::string(e.what()).find(kTemp + "/a.txt: cannot create: File exists") != std::string::npos);
  }
  d.remove("a.txt");
  CHECK(names_in(d.temp()).empty());
  CHECK_THROWS_AS(d.remove("a.txt"), DataError);
  // A second one for the same path in the same process: its temporary name is taken.
  CHECK_THROWS_WITH(AtomicDir(parent, "out", "out", ""),
                    Catch::Contains(kTemp + ": cannot create a temporary directory: File exists"));
  CHECK_THROWS_WITH(AtomicDir(parent / "missing", "out", "out", ""),
                    Catch::Contains("cannot create a temporary directory: No such file or directory"));
}

TEST_CASE("for_each_leftover_dir: the unlocked .<name>.tmp<digits> and .<name>.old<digits> directories",
          "[atomic_dir]") {
  const fs::path parent = canopy::test::fresh_dir("common", "atomic_dir_leftovers");
  for (const char* d :
       {".out.tmp123", ".out.old45", ".out.tmpx", ".out.tmp", ".other.tmp1", "out", ".out.old7x"}) {
    fs::create_directory(parent / d);
  }
  canopy::test::write_file(parent / ".out.tmp9", "a file, not a directory");
  AtomicDir live(parent, "out", "out", "");  // .out.tmp<pid>: locked by this live run
  std::vector<std::string> seen;
  canopy::common::for_each_leftover_dir(parent, "out",
                                        [&](const fs::path& p) { seen.push_back(p.filename().string()); });
  CHECK(seen == std::vector<std::string>{".out.old45", ".out.tmp123"});
}
