// The report's "Disk" section (tools/report/disk_section.h): bytes per part of a hand-built
// output directory, a hard-linked file counted once, a symbolic link not followed.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "report/disk_section.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using namespace canopy;

namespace {
void bytes(const fs::path& p, std::size_t n) {
  fs::create_directories(p.parent_path());
  std::ofstream(p.string()) << std::string(n, 'x');
}
}  // namespace

TEST_CASE("disk section: parts, hard links once, symbolic links not followed") {
  const fs::path out = test::fresh_dir("report", "disk") / "out";
  bytes(out / "sedan" / "circle" / "scan.pcd", 1000);
  bytes(out / "tank" / "circle" / "noise-0" / "samples.pcd", 300);
  // The 0 mm scan is a hard link to the render: counted once, in the first part met.
  fs::create_hard_link(out / "sedan" / "circle" / "scan.pcd", out / "sedan" / "circle" / "noise-0-scan.pcd");
  bytes(out / "scenes" / "light" / "tile-1" / "scan.pcd", 5000);
  bytes(out / "ablation" / "x.json", 20);
  bytes(out / "experiment.txt", 7);
  // A link to a big file elsewhere adds nothing.
  bytes(out.parent_path() / "elsewhere.bin", 100000);
  fs::create_symlink(out.parent_path() / "elsewhere.bin", out / "scenes" / "link.bin");
  fs::create_directory_symlink(out.parent_path(), out / "loop");
  const auto parts = report::disk_parts(out.string(), {"sedan", "tank", "obj1"});
  REQUIRE(parts.size() == 4);
  CHECK(parts[0].name == "thesis trials");
  CHECK(parts[0].bytes == 1300);
  CHECK(parts[0].files == 2);
  CHECK(parts[1].name == "ablation");
  CHECK(parts[1].bytes == 20);
  CHECK(parts[2].name == "scenes");
  CHECK(parts[2].bytes == 5000);
  CHECK(parts[3].name == "other files");
  CHECK(parts[3].bytes == 7);
  const std::string md = report::disk_markdown(parts, "out");
  CHECK(md.find("| thesis trials | 2 | 0.0 |") != std::string::npos);
  CHECK(md.find("| scenes | 1 | 0.0 |") != std::string::npos);
  CHECK(md.find("| **all** | 5 | **0.0** |") != std::string::npos);
  // Megabytes: 2.5 MB in one part.
  bytes(out / "families" / "big.pcd", 2500000);
  const auto more = report::disk_parts(out.string(), {"sedan", "tank"});
  CHECK(report::disk_markdown(more, "out").find("| families | 1 | 2.5 |") != std::string::npos);
  // No output directory: no parts.
  CHECK(report::disk_parts((out / "missing").string(), {}).empty());
}
