// documents/stage_time.h: the .time files tools/stagerun writes (GNU time's "%e %M %U %S"),
// and the older two-column files; a malformed file is an error naming it (issue 25: a negative
// time was summed and "abc def" / "nan inf" silently dropped).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/documents/stage_time.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

fs::path dir() {
  const fs::path d = fs::path(CANOPY_TEST_TMP) / "stage-time";
  fs::create_directories(d);
  return d;
}

// Writes <artifact>.time with `text` and returns the artifact's path.
std::string with_time(const std::string& name, const std::string& text) {
  const fs::path a = dir() / name;
  std::ofstream(a.string() + ".time", std::ios::binary) << text;
  return a.string();
}

// The message read_stage_time throws for `text`, "" when it does not.
std::string error_of(const std::string& text) {
  const std::string a = with_time("bad", text);
  try {
    documents::read_stage_time(a);
  } catch (const common::DataError& e) {
    CHECK(e.file() == a + ".time");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("stage time: four columns give wall, peak memory, user and system CPU") {
  const auto t = documents::read_stage_time(with_time("four", "1.52 48128 1.40 0.08\n"));
  CHECK(t.present);
  CHECK(t.has_cpu);
  CHECK(t.seconds == Approx(1.52));
  CHECK(t.peak_mb == Approx(47.0));  // 48128 KiB
  CHECK(t.user_seconds == Approx(1.40));
  CHECK(t.system_seconds == Approx(0.08));
  CHECK(t.cpu_seconds() == Approx(1.48));
}

TEST_CASE("stage time: an older two-column file is read, without CPU") {
  const auto t = documents::read_stage_time(with_time("two", "0.25 2048\n"));
  CHECK(t.present);
  CHECK_FALSE(t.has_cpu);
  CHECK(t.seconds == Approx(0.25));
  CHECK(t.peak_mb == Approx(2.0));
  CHECK(t.cpu_seconds() == 0);
}

TEST_CASE("stage time: no file is a stage that did not run") {
  const auto t = documents::read_stage_time((dir() / "never-ran").string());
  CHECK_FALSE(t.present);
}

TEST_CASE("stage time: a malformed file is an error naming it") {
  CHECK_THAT(error_of("-5 100\n"), Catch::Contains("bad.time") && Catch::Contains("'-5'"));
  CHECK_THAT(error_of("abc def\n"), Catch::Contains("'abc'"));
  CHECK_THAT(error_of("nan inf\n"), Catch::Contains("'nan'"));
  CHECK_THAT(error_of("1 inf\n"), Catch::Contains("'inf'"));
  CHECK_THAT(error_of("1 100 -0.5 0\n"), Catch::Contains("user CPU"));
  CHECK_THAT(error_of("1 100 0.5 x\n"), Catch::Contains("system CPU"));
  CHECK_THAT(error_of("1.5s 100\n"), Catch::Contains("'1.5s'"));
  CHECK_THAT(error_of("1e999 100\n"), Catch::Contains("'1e999'"));
  CHECK_THAT(error_of(""), Catch::Contains("0 words"));
  CHECK_THAT(error_of("1\n"), Catch::Contains("1 words"));
  CHECK_THAT(error_of("1 2 3\n"), Catch::Contains("3 words"));
  CHECK_THAT(error_of("1 2 3 4 5\n"), Catch::Contains("5 words"));
  CHECK_THAT(error_of("Command exited with non-zero status 1\n1 2\n"), Catch::Contains("words"));
  CHECK_THAT(error_of(std::string(5000, '1')), Catch::Contains("longer than 4096 bytes"));
}
