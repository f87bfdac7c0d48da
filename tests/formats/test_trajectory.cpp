// formats/trajectory.h (issue 26): the sensor trajectory text format, its strict reader (errors
// name the file and the line), the writer's round trip, and linear interpolation by GPS time.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/formats/trajectory.h"

using namespace canopy;
using namespace std::string_literals;
namespace fs = std::filesystem;

namespace {

const std::string kHead = "# canopy trajectory 1\ntime x y z roll pitch heading\n";

// The message parse_trajectory throws for `text` (checked to name the file), "" when none.
std::string error_of(const std::string& text) {
  try {
    formats::parse_trajectory(text, "traj.txt");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "traj.txt");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("trajectory: parses samples, comments, blank lines and CRLF") {
  const formats::Trajectory t = formats::parse_trajectory(
      "# canopy trajectory 1\r\n# flight 7\ntime x y z roll pitch heading\n\n# a comment\n"
      "10 100 200 1000 0.5 -1 90\n 10.5\t101  200 1000.25 0 0 -179.5\r\n",
      "traj.txt");
  REQUIRE(t.samples.size() == 2);
  CHECK(t.comments == std::vector<std::string>{"flight 7"});
  CHECK(t.samples[0].time == 10);
  CHECK(t.samples[0].x == 100);
  CHECK(t.samples[0].y == 200);
  CHECK(t.samples[0].z == 1000);
  CHECK(t.samples[0].roll == 0.5);
  CHECK(t.samples[0].pitch == -1);
  CHECK(t.samples[0].heading == 90);
  CHECK(t.samples[1].time == 10.5);
  CHECK(t.samples[1].x == 101);
  CHECK(t.samples[1].z == 1000.25);
  CHECK(t.samples[1].heading == -179.5);
}

TEST_CASE("trajectory: bad files are refused naming the file and the line") {
  CHECK_THAT(error_of(""), Catch::Contains("traj.txt: empty file"));
  CHECK_THAT(error_of("# canopy trajectory 2\ntime x y z roll pitch heading\n1 0 0 0 0 0 0\n"),
             Catch::Contains("traj.txt: line 1:") && Catch::Contains("another version"));
  CHECK_THAT(error_of("ply\nformat ascii 1.0\n"), Catch::Contains("line 1:"));
  CHECK_THAT(error_of("# canopy trajectory 1\ntime x y z heading pitch roll\n1 0 0 0 0 0 0\n"),
             Catch::Contains("line 2:") && Catch::Contains("header line"));
  CHECK_THAT(error_of("# canopy trajectory 1\n"), Catch::Contains("no header line"));
  CHECK_THAT(error_of(kHead), Catch::Contains("traj.txt: no samples"));
  CHECK_THAT(error_of(kHead + "1 0 0 0 0 0 0\n2 0 0 0 0 0\n"),
             Catch::Contains("line 4: 6 values; a sample has 7"));
  CHECK_THAT(error_of(kHead + "1 0 0 0 0 0 0 8\n"), Catch::Contains("line 3: 8 values"));
  CHECK_THAT(error_of(kHead + "1 0 nan 0 0 0 0\n"),
             Catch::Contains("line 3: y 'nan' is not a decimal number"));
  CHECK_THAT(error_of(kHead + "1 0 0 1e999 0 0 0\n"),
             Catch::Contains("line 3: z:") && Catch::Contains("out of range"));
  CHECK_THAT(error_of(kHead + "1 0 0 0 0 0 0x10\n"), Catch::Contains("line 3: heading '0x10'"));
  CHECK_THAT(error_of(kHead + "1 0 0 0 0 0 5deg\n"), Catch::Contains("line 3: heading '5deg'"));
  CHECK_THAT(error_of(kHead + "1 0 0 0 0 0 0\n1 1 0 0 0 0 0\n"),
             Catch::Contains("line 4: time 1 is not after the previous sample's 1"));
  CHECK_THAT(error_of(kHead + "2 0 0 0 0 0 0\n# c\n1 1 0 0 0 0 0\n"), Catch::Contains("line 5: time 1"));
  CHECK_THAT(error_of(kHead + std::string(5000, '1') + "\n"), Catch::Contains("line 3: longer than 4096"));
  CHECK_THAT(error_of(kHead + "1 0 0 0\0 0 0 0\n"s), Catch::Contains("line 3: holds a NUL byte"));
}

TEST_CASE("trajectory: read_trajectory names the file; write round-trips exactly") {
  const fs::path d = fs::path(CANOPY_TEST_TMP) / "trajectory";
  fs::create_directories(d);
  const std::string missing = (d / "missing.txt").string();
  try {
    formats::read_trajectory(missing);
    FAIL("no error");
  } catch (const common::DataError& e) { CHECK(e.file() == missing); }
  try {
    formats::read_trajectory(d.string());
    FAIL("no error");
  } catch (const common::DataError& e) { CHECK_THAT(e.what(), Catch::Contains("is a directory")); }
  const std::string bad = (d / "bad.txt").string();
  std::ofstream(bad) << kHead << "1 0 0 0 0 0 0\n0.5 0 0 0 0 0 0\n";
  try {
    formats::read_trajectory(bad);
    FAIL("no error");
  } catch (const common::DataError& e) {
    CHECK(std::string(e.what()) == bad +
                                       ": line 4: time 0.5 is not after the previous sample's 1 (times must "
                                       "strictly increase)");
  }

  formats::Trajectory t;
  t.comments = {"written by a test"};
  t.samples = {{307843211.123456789, 500012.345678, 4399987.000001, 1180.1, 0.1, -0.2, 90},
               {307843211.2, 500013.5, 4399987.25, 1180, 0, 0, -0.0},
               {307843212.7, 1e-7, -3.25, 0.3, 179.99, -89.5, 1.0 / 3.0}};
  const std::string path = (d / "t.txt").string();
  formats::write_trajectory(t, path);
  const formats::Trajectory back = formats::read_trajectory(path);
  CHECK(back.comments == t.comments);
  REQUIRE(back.samples.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(back.samples[i].time == t.samples[i].time);
    CHECK(back.samples[i].x == t.samples[i].x);
    CHECK(back.samples[i].y == t.samples[i].y);
    CHECK(back.samples[i].z == t.samples[i].z);
    CHECK(back.samples[i].roll == t.samples[i].roll);
    CHECK(back.samples[i].pitch == t.samples[i].pitch);
    CHECK(back.samples[i].heading == t.samples[i].heading);
  }
  // Writing what was read gives the same bytes.
  CHECK(formats::serialize_trajectory(back) == formats::serialize_trajectory(t));
  t.samples[2].time = t.samples[1].time;
  CHECK_THROWS_AS(formats::serialize_trajectory(t), std::invalid_argument);
}

TEST_CASE("trajectory: linear interpolation by time, tolerance at the ends") {
  const formats::Trajectory t = formats::parse_trajectory(
      kHead + "10 0 0 100 0 0 170\n12 20 -4 104 2 0 -170\n13 20 6 104 4 0 -160\n", "t");
  // Exactly at a sample, a quarter into the first segment, half into the second.
  CHECK(formats::trajectory_position(t, 12, 0, "t") == std::array<double, 3>{20, -4, 104});
  CHECK(formats::trajectory_position(t, 10.5, 0, "t") == std::array<double, 3>{5, -1, 101});
  CHECK(formats::trajectory_position(t, 12.5, 0, "t") == std::array<double, 3>{20, 1, 104});
  // Heading interpolates along the shorter arc through 180, not through 0.
  const formats::TrajectorySample s = formats::trajectory_sample(t, 11, 0, "t");
  CHECK(s.x == 10);
  CHECK(s.roll == Approx(1));
  CHECK(std::abs(s.heading) == Approx(180));
  CHECK(formats::trajectory_sample(t, 12.5, 0, "t").heading == Approx(-165));
  // Within the tolerance beyond an end: the end sample's position.
  CHECK(formats::trajectory_position(t, 9.6, 0.5, "t") == std::array<double, 3>{0, 0, 100});
  CHECK(formats::trajectory_position(t, 13.5, 0.5, "t") == std::array<double, 3>{20, 6, 104});
  try {
    formats::trajectory_position(t, 13.6, 0.5, "traj.txt");
    FAIL("no error");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "traj.txt");
    CHECK_THAT(e.what(), Catch::Contains("GPS time 13.6 s is outside the trajectory's span [10, 13]"));
  }
  CHECK_THROWS_AS(formats::trajectory_position(t, 9.4, 0.5, "t"), common::DataError);
}

TEST_CASE("trajectory: a comment ending in several CRs reads and writes back (fuzz_trajectory finding)") {
  const std::string text =
      "# canopy trajectory 1\n# a\rb\r\r\r\r\ntime x y z roll pitch heading\n0 1 2 3 0 0 0\n1 2 3 4 0 0 0\n";
  const formats::Trajectory t = formats::parse_trajectory(text, "crs.txt");
  CHECK(t.comments == std::vector<std::string>{"a\rb"});
  const std::string once = formats::serialize_trajectory(t);
  CHECK(formats::serialize_trajectory(formats::parse_trajectory(once, "back.txt")) == once);
}
