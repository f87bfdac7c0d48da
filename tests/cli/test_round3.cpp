// Issue 25 (reliability round 3), the cases of /work/shared/data/malformed/round3/replay.sh
// that concern outputs, provenance, numbers and the readers, each run against the tool
// binaries as the replay runs them. The scripts run under bash (process substitution,
// pipefail) in a private directory; no tool writes to a system path.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "support/cli.h"

namespace fs = std::filesystem;
using canopy::test::fresh_dir;

namespace {

const std::string kBin = CANOPY_BIN_DIR;
const std::string kSrc = CANOPY_SOURCE_DIR;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs `script` with bash in `dir` (B = the bin directory, D = the reproducers of tests/cli/data,
// F = those of tests/formats/data, L = tests/las/data); returns the exit status, stderr in *err.
int bash(const fs::path& dir, const std::string& script, std::string* err) {
  {
    std::ofstream f(dir / "t.sh");
    f << "set -u\nB='" << kBin << "'\nD='" << kSrc << "/tests/cli/data'\nF='" << kSrc
      << "/tests/formats/data'\nL='" << kSrc << "/tests/las/data'\n"
      << script << "\n";
  }
  return canopy::test::sh("cd '" + dir.string() + "' && bash t.sh", dir / "err.txt", err);
}

const char* const kOnePcd =
    "printf 'VERSION 0.7\\nFIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nCOUNT 1 1 1\\nWIDTH 1\\nHEIGHT 1\\n"
    "POINTS 1\\nDATA ascii\\n1 2 3\\n' > one.pcd\n";

}  // namespace

TEST_CASE("round 3: -o >(cmd), /dev/stdout and /proc/self/fd/1 into a pipe are written through") {
  const fs::path d = fresh_dir("cli", "r3_pipes");
  std::string err;
  REQUIRE(bash(d, std::string(kOnePcd) + "$B/addnoise -q -i one.pcd --sigma 1mm -o ref.pcd", &err) == 0);
  const std::string ref = slurp(d / "ref.pcd");
  REQUIRE(ref.size() > 100);
  // Process substitution: /dev/fd/63 of the tool, a pipe. The reader marks when it is done.
  CHECK(bash(d,
             "$B/addnoise -q -i one.pcd --sigma 1mm -o >(cat > ps.out; touch ps.done)\n"
             "for i in $(seq 100); do [ -e ps.done ] && break; sleep 0.1; done",
             &err) == 0);
  CHECK(err.empty());
  CHECK(slurp(d / "ps.out") == ref);
  CHECK(bash(d, "set -o pipefail; $B/addnoise -q -i one.pcd --sigma 1mm -o /dev/stdout | cat > piped.out",
             &err) == 0);
  CHECK(slurp(d / "piped.out") == ref);
  CHECK(bash(d, "set -o pipefail; $B/addnoise -q -i one.pcd --sigma 1mm -o /proc/self/fd/1 | cat > piped2.out",
             &err) == 0);
  CHECK(slurp(d / "piped2.out") == ref);
  // pcd2ply and fitvox too (every tool goes through the same writer); pcd2ply's PLY into a pipe.
  CHECK(bash(d,
             "set -o pipefail; $B/pcd2ply -q -i ref.pcd -o /dev/stdout | cat > p.ply; $B/pcd2ply -q -i "
             "ref.pcd -o ref.ply",
             &err) == 0);
  CHECK(slurp(d / "p.ply") == slurp(d / "ref.ply"));
  // A descriptor not open for writing is refused, naming the path; nothing is written.
  CHECK(bash(d, "$B/addnoise -q -i one.pcd -o /dev/fd/0 < one.pcd", &err) == 1);
  CHECK_THAT(err, Catch::Contains("/dev/fd/0: names descriptor 0, which is open for reading only"));
  CHECK(slurp(d / "one.pcd").find("1 2 3") != std::string::npos);
}

TEST_CASE("round 3: -o /dev/stdout >> log appends instead of replacing the log") {
  const fs::path d = fresh_dir("cli", "r3_append");
  std::string err;
  REQUIRE(bash(d, std::string(kOnePcd) + "$B/addnoise -q -i one.pcd -o ref.pcd", &err) == 0);
  CHECK(bash(d,
             "echo 'first line of a log, must survive' > log.txt\n"
             "$B/addnoise -q -i one.pcd -o /dev/stdout >> log.txt\n"
             "$B/addnoise -q -i one.pcd -o /proc/self/fd/1 >> log.txt",
             &err) == 0);
  CHECK(slurp(d / "log.txt") ==
        "first line of a log, must survive\n" + slurp(d / "ref.pcd") + slurp(d / "ref.pcd"));
}

TEST_CASE("round 3: ncut's two outputs: /dev/stdout and - are one output; --colored into a pipe") {
  const fs::path d = fresh_dir("cli", "r3_ncut");
  std::string err;
  // The 6 x 6 grid of the 1e30 reproducer with its vertex 0 back at x = 0.
  REQUIRE(bash(d, "sed '0,/^1e+30 /s//0.0 /' $D/ply-vertex-1e30.ply > grid.ply", &err) == 0);
  REQUIRE(slurp(d / "grid.ply").find("1e+30") == std::string::npos);
  CHECK(bash(d, "$B/ncut -q -i grid.ply -o /dev/stdout --colored -", &err) == 2);
  CHECK_THAT(err, Catch::Contains("both write to stdout"));
  CHECK(bash(d,
             "set -o pipefail; $B/ncut -q -i grid.ply -o seg.json --colored /dev/stdout | cat > c.ply\n"
             "$B/ncut -q -i grid.ply -o seg2.json --colored /dev/stdout > c2.ply",
             &err) == 0);
  CHECK(slurp(d / "c.ply") == slurp(d / "c2.ply"));  // the pipe got what a file gets
  CHECK(slurp(d / "seg.json") == slurp(d / "seg2.json"));
  CHECK(slurp(d / "c.ply").rfind("ply\n", 0) == 0);
}

TEST_CASE("round 3: a newline in an input path stays inside one header comment") {
  const fs::path d = fresh_dir("cli", "r3_newline");
  std::string err;
  CHECK(bash(d,
             std::string(kOnePcd) +
                 "nl=$(printf 'in\\nPOINTS 1\\nDATA ascii\\n0 0 0\\n.pcd'); cp one.pcd \"$nl\"\n"
                 "$B/addnoise -q -i \"$nl\" -o nl.pcd\n"
                 "$B/pcd2ply -q -i nl.pcd -o nl.ply\n"  // canopy reads its own output back
                 "$B/addnoise -q -i nl.ply -o back.pcd\n"
                 "$B/pcd2ply -q -i \"$nl\" -o nl2.ply && $B/addnoise -q -i nl2.ply -o back2.las\n"
                 "$B/pcd2ply -q -i back2.las -o back3.ply",
             &err) == 0);
  CHECK(err.empty());
  const std::string back = slurp(d / "back.pcd");
  CHECK(back.find("# input in\\nPOINTS 1\\nDATA ascii\\n0 0 0\\n.pcd\n") != std::string::npos);
  CHECK(back.find("\nDATA ascii\n") == std::string::npos);             // the path's lines are no header lines
  CHECK(back.find("\nPOINTS 1\nDATA binary\n") != std::string::npos);  // the real header's
  CHECK(slurp(d / "back3.ply").find("comment input in\\nPOINTS 1\\nDATA ascii\\n0 0 0\\n.pcd\n") !=
        std::string::npos);
}

TEST_CASE("round 3: '8 mm', 1e-400, -0 and hex numbers are usage errors naming the option") {
  const fs::path d = fresh_dir("cli", "r3_numbers");
  std::string err;
  REQUIRE(bash(d, kOnePcd, &err) == 0);
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --sigma '8 mm' -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--sigma: '8 mm': no space between the number and its unit (write 8mm)"));
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --sigma 1e-400 -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--sigma: '1e-400' is out of range"));
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --sigma -0 -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--sigma: '-0' is a negative zero"));
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --sigma 0x10 -o a.pcd", &err) == 2);
  CHECK(bash(d, "$B/fitvox -q -i one.pcd --support 0x1p0 -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--support") && Catch::Contains("'0x1p0' is not a decimal number"));
  CHECK(bash(d, "$B/fitvox -q -i one.pcd --max-rms 0x1p0 -o a.pcd", &err) == 2);
  CHECK(bash(d, "$B/ncut -q -i x.ply --tolerance 0x1p-20 -o a.json", &err) == 2);
  CHECK(bash(d, "$B/ncut -q -i x.ply --tolerance 1e-400 -o a.json", &err) == 2);
  CHECK_FALSE(fs::exists(d / "a.pcd"));
  CHECK_FALSE(fs::exists(d / "a.json"));
  // What stays accepted: 0, a plain decimal with or without a unit.
  CHECK(
      bash(d,
           "$B/addnoise -q -i one.pcd --sigma 0 -o a.pcd && $B/addnoise -q -i one.pcd --sigma 0.5mm -o b.pcd",
           &err) == 0);
}

TEST_CASE("round 3: the readers' and stages' refusals name the file, exit 1, leave no output") {
  const fs::path d = fresh_dir("cli", "r3_refusals");
  std::string err;
  struct Case {
    std::string command, message;
  };
  const Case cases[] = {
      {"$B/fitvox -q -i $D/pcd-x-1e30.pcd -o out.pcd",
       "pcd-x-1e30.pcd: voxel index overflow: point 0 has x = 1e+30"},
      {"$B/ncut -q -i $D/ply-vertex-1e30.ply -o out.json", "ply-vertex-1e30.ply: point set extent exceeds"},
      {"$B/ncut -q -i $D/ply-all-vertices-identical.ply -o out.json",
       "ply-all-vertices-identical.ply: all 50 faces have zero area"},
      {"$B/ncut -q -i $F/ply-face-uchar-count-wraps.ply -o out.json",
       "ply-face-uchar-count-wraps.ply: 3072 bytes of data after the last element"},
      {"$B/pcd2ply -q -i $F/pcd-no-xyz.pcd -o out.ply", "pcd-no-xyz.pcd: field 'x' missing"},
      {"$B/pcd2ply -q -i $L/las-trunc-at-point-offset.las -o out.ply",
       "las-trunc-at-point-offset.las: point data truncated: header says 100 points"},
      {"$B/addnoise -q -i $L/las12-count0-with-data.las -o out.pcd",
       "las12-count0-with-data.las: LAS header says 0 points of 34 bytes, but 3400 more bytes"},
  };
  for (const Case& c : cases) {
    INFO(c.command);
    CHECK(bash(d, c.command, &err) == 1);
    CHECK_THAT(err, Catch::Contains(c.message));
    CHECK_FALSE(fs::exists(d / "out.pcd"));
    CHECK_FALSE(fs::exists(d / "out.json"));
    CHECK_FALSE(fs::exists(d / "out.ply"));
  }
}

TEST_CASE("stop 71: --support and --margin bounds, bare-metre warnings, config file lines") {
  const fs::path d = fresh_dir("cli", "s71_bounds");
  std::string err;
  REQUIRE(bash(d, kOnePcd, &err) == 0);
  CHECK(bash(d, "$B/fitvox -q -i one.pcd --support 1e9 -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--support must be 'auto' or in (0, 4] voxel edges (given 1e9)"));
  CHECK(bash(d, "$B/detect -q -i one.pcd --margin 1000m -o dx", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--margin must be in [0, 10m] (given 1000m)"));
  CHECK(bash(d, "$B/detect -q -i one.pcd --margin 1000 -o dx", &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean 1000mm?") &&
                      Catch::Contains("(--margin 1000 was read as 1000 m: bare numbers are metres)"));
  CHECK(bash(d, "$B/fitvox -q -i one.pcd --noise nan -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--noise: 'nan' is not a length"));
  bash(d, "$B/fitvox -q -i one.pcd --noise 8 -o a.pcd", &err);
  CHECK_THAT(err, Catch::Contains("--noise 8 is 8m (bare numbers are metres): did you mean 8mm?"));
  bash(d, "$B/ncut -q -i x.ply --radius 512 -o a.json", &err);
  CHECK_THAT(err, Catch::Contains("--radius 512 is 512m") && Catch::Contains("did you mean 512mm?"));
  // A sensible metre value (1 m, 2x the default) does not warn.
  bash(d, "$B/ncut -q -i x.ply --radius 1 -o a.json", &err);
  CHECK_THAT(err, !Catch::Contains("did you mean"));
  REQUIRE(bash(d,
               "printf 'sigma = 8 mm\\n' > c1.ini; printf 'sigma=8mm ; c\\n' > c4.ini; "
               "printf 'sigma=8mm\\nsigma=4mm\\n' > c6.ini; printf '[addnoise]\\nsigma=8mm\\n' > c3.ini",
               &err) == 0);
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --config c1.ini -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("c1.ini: line 1: sigma = 8 mm: a blank inside the value"));
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --config c4.ini -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("c4.ini: line 1: sigma=8mm ; c: ';' does not start a comment"));
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --config c6.ini -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("c6.ini: key 'sigma' given twice (lines 1 and 2)"));
  CHECK(bash(d, "$B/addnoise -q -i one.pcd --config c3.ini -o a.pcd", &err) == 2);
  CHECK_THAT(err, Catch::Contains("c3.ini: line 1: [addnoise]: sections are not used"));
  CHECK_FALSE(fs::exists(d / "a.pcd"));
  CHECK_FALSE(fs::exists(d / "dx"));
}
