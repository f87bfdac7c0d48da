// Relocatable install (issue 12): `cmake --install` to a temporary prefix, the prefix moved,
// and the moved rangetrace renders a built-in model with the moved share/canopy (and fails
// when that copy lacks the model: the source tree is not used); CANOPY_SHARE overrides.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli.h"

namespace fs = std::filesystem;
using canopy::test::fresh_dir;
using canopy::test::sh;

namespace {
std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

bool is_png(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in && std::string(sig, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}
}  // namespace

TEST_CASE("an installed canopy still renders after its prefix is moved") {
  const fs::path d = fresh_dir("install", "moved");
  std::string err;
  REQUIRE(sh(std::string(CANOPY_CMAKE_COMMAND) + " --install " + q(CANOPY_BUILD_DIR) + " --prefix " +
                 q(d / "first") + " > " + q(d / "install.log"),
             d / "err", &err) == 0);
  for (const char* tool :
       {"rangetrace", "addnoise", "fitvox", "cocone", "ncut", "gmatch", "pcd2ply", "report", "figures"}) {
    CHECK(fs::exists(d / "first" / "bin" / tool));
  }
  CHECK(fs::exists(d / "first" / "share" / "canopy" / "models" / "sedan.inc"));
  CHECK(fs::exists(d / "first" / "share" / "canopy" / "scenes" / "circle.scene"));
  CHECK(fs::exists(d / "first" / "share" / "canopy" / "thesis" / "results.csv"));
  fs::rename(d / "first", d / "moved");

  // -v lists nothing about paths; the picture is the proof: POV-Ray found sedan.inc.
  const std::string rangetrace = "env -u CANOPY_SHARE " + q(d / "moved" / "bin" / "rangetrace") +
                                 " -q --model sedan --size 32 --picture ";
  REQUIRE(sh(rangetrace + q(d / "sedan.png"), d / "err", &err) == 0);
  CHECK(is_png(d / "sedan.png"));

  // The moved copy is the one used: without its sedan.inc the render fails, although the
  // source tree still has one.
  fs::rename(d / "moved" / "share" / "canopy" / "models" / "sedan.inc", d / "sedan.inc");
  CHECK(sh(rangetrace + q(d / "none.png"), d / "err", &err) == 1);
  CHECK_FALSE(fs::exists(d / "none.png"));

  // CANOPY_SHARE overrides: pointing it at a copy that has the model renders again.
  fs::create_directories(d / "other" / "models");
  fs::copy(d / "moved" / "share" / "canopy" / "models", d / "other" / "models");
  fs::copy_file(d / "sedan.inc", d / "other" / "models" / "sedan.inc");
  CHECK(sh("CANOPY_SHARE=" + q(d / "other") + " " + q(d / "moved" / "bin" / "rangetrace") +
               " -q --model sedan --size 32 --picture " + q(d / "other.png"),
           d / "err", &err) == 0);
  CHECK(is_png(d / "other.png"));
  fs::remove_all(d / "moved");  // the binaries are large; keep the test tree small
}
