// famscore: the runs manifest, the nearest instance by size, and the confusion and accuracy
// tables on hand-made trials with known counts.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "famscore/famscore.h"
#include "rangetrace/families.h"

using namespace canopy;
using namespace canopy::famscore;

TEST_CASE("famscore: the runs manifest") {
  const auto runs =
      parse_runs("# header\na/verdict.json pickup 1000 light 0\n\nb.json van 7 dense 32  # c\n", "runs");
  REQUIRE(runs.size() == 2);
  CHECK(runs[0].verdict == "a/verdict.json");
  CHECK(runs[0].vehicle_class == "pickup");
  CHECK(runs[0].instance == 1000);
  CHECK(runs[1].cover == "dense");
  CHECK(runs[1].noise == "32");
  CHECK(runs[1].line == 4);
  CHECK_THROWS_AS(parse_runs("a.json van 7 dense\n", "runs"), common::DataError);
  CHECK_THROWS_AS(parse_runs("a.json van x7 dense 0\n", "runs"), common::DataError);
  CHECK_THROWS_AS(parse_runs("# nothing\n", "runs"), common::DataError);
  try {
    parse_runs("ok.json van 1 a 0\nbad\n", "m.txt");
    FAIL("no error");
  } catch (const common::DataError& e) { CHECK(std::string(e.what()).find("line 2") != std::string::npos); }
}

TEST_CASE("famscore: the nearest instance is the same-class entry nearest in size") {
  const std::vector<Entry> entries = {{"pickup-0", "pickup"},
                                      {"pickup-1", "pickup"},
                                      {"pickup-2", "pickup"},
                                      {"van-0", "van"},
                                      {"sedan", "pickup"}};
  auto size = [](const char* c, int n) {
    const auto f = rangetrace::make_family_instance(c, n);
    return Eigen::Vector3d(f.hi - f.lo);
  };
  const Eigen::Vector3d t = size("pickup", 1000);
  std::string want;
  double best = 1e9;
  for (int n : {0, 1, 2}) {
    const double d = (size("pickup", n) - t).norm();
    if (d < best) best = d, want = "pickup-" + std::to_string(n);
  }
  CHECK(nearest_by_size("pickup", 1000, entries) == want);
  CHECK(nearest_by_size("van", 5, entries) == "van-0");
  CHECK(nearest_by_size("tank", 5, entries).empty());  // no entry of the class
}

TEST_CASE("famscore: confusion and accuracy tables count the trials") {
  auto trial = [](const char* truth, const char* got, const char* cover, bool accepted, const char* nearest,
                  const char* expected, bool failed = false) {
    Trial t;
    t.run.vehicle_class = truth;
    t.run.cover = cover;
    t.run.noise = "0";
    t.answered_class = got;
    t.accepted = accepted;
    t.nearest = nearest;
    t.expected_nearest = expected;
    t.failed = failed;
    return t;
  };
  const std::vector<Trial> trials = {
      trial("van", "van", "light", true, "van-1", "van-1"),
      trial("van", "pickup", "light", false, "pickup-0", "van-0"),
      trial("pickup", "pickup", "dense", false, "pickup-0", "pickup-1"),
      trial("pickup", "none", "dense", false, "", "pickup-1", true),
      trial("tank", "tank", "dense", true, "tank-3", "tank-3"),
  };
  const std::vector<Entry> entries = {
      {"pickup-0", "pickup"}, {"van-0", "van"}, {"tank-3", "tank"}, {"zz-1", "zz"}};
  // Rows and columns in the families' order, other classes after them, none last.
  CHECK(confusion_csv(trials, entries) ==
        "true_class,pickup,van,tank,zz,none\n"
        "pickup,1,0,0,0,1\n"
        "van,1,1,0,0,0\n"
        "tank,0,0,1,0,0\n");
  CHECK(accuracy_csv(trials) ==
        "cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,nearest_"
        "accuracy,failed\n"
        "light,0,2,1,0.5000,1,1,1,0.5000,0\n"
        "dense,0,3,2,0.6667,1,1,1,0.3333,1\n"
        "all,all,5,3,0.6000,2,2,2,0.4000,1\n");
}
