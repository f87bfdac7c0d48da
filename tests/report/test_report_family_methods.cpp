// The report's "Vehicle families" section, canopy beside the PCL baseline
// (tools/report/families_section.h, add_family_methods): hand-written famscore tables
// (methods.csv, methods-confusion.csv) with known counts and times, their cross-checks, and
// their discovery beside accuracy.csv.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "canopy/common/error.h"
#include "family_tables.h"
#include "report/families_section.h"

using namespace canopy;

namespace {

const char* const kConfusion = test::kFamilyConfusion;
const char* const kAccuracy = test::kFamilyAccuracy;
const std::string kHead =
    "method,class,cover,noise,trials,class_right,class_accuracy,nearest_right,nearest_accuracy,failed,timed,"
    "seconds_mean\n";
// gmatch 8/12 (sedan 3, suv 1, tank 4), verify 9/12 (3, 2, 4), FPFH 6/12 (2, 0, 4), untimed.
const std::string kMethods = kHead +
                             "gmatch,all,all,all,12,8,0.6667,3,0.2500,1,12,1.500\n"
                             "gmatch,sedan,all,all,4,3,0.7500,1,0.2500,0,4,1.000\n"
                             "gmatch,suv,all,all,4,1,0.2500,0,0.0000,1,4,2.000\n"
                             "gmatch,tank,all,all,4,4,1.0000,2,0.5000,0,4,1.500\n"
                             "gmatch,all,light,all,6,5,0.8333,2,0.3333,0,6,1.400\n"
                             "gmatch,all,dense,all,6,3,0.5000,1,0.1667,1,6,1.600\n"
                             "gmatch,all,all,0,6,5,0.8333,2,0.3333,0,6,1.400\n"
                             "gmatch,all,all,32,6,3,0.5000,1,0.1667,1,6,1.600\n"
                             "verify,all,all,all,12,9,0.7500,4,0.3333,1,10,2.750\n"
                             "verify,sedan,all,all,4,3,0.7500,2,0.5000,0,4,2.000\n"
                             "verify,suv,all,all,4,2,0.5000,0,0.0000,1,2,4.000\n"
                             "verify,tank,all,all,4,4,1.0000,2,0.5000,0,4,2.750\n"
                             "verify,all,light,all,6,5,0.8333,3,0.5000,0,5,2.000\n"
                             "verify,all,dense,all,6,4,0.6667,1,0.1667,1,5,3.500\n"
                             "verify,all,all,0,6,5,0.8333,3,0.5000,0,5,2.000\n"
                             "verify,all,all,32,6,4,0.6667,1,0.1667,1,5,3.500\n"
                             "fpfh,all,all,all,12,6,0.5000,2,0.1667,0,0,\n"
                             "fpfh,sedan,all,all,4,2,0.5000,1,0.2500,0,0,\n"
                             "fpfh,suv,all,all,4,0,0.0000,0,0.0000,0,0,\n"
                             "fpfh,tank,all,all,4,4,1.0000,1,0.2500,0,0,\n"
                             "fpfh,all,light,all,6,4,0.6667,1,0.1667,0,0,\n"
                             "fpfh,all,dense,all,6,2,0.3333,1,0.1667,0,0,\n"
                             "fpfh,all,all,0,6,4,0.6667,1,0.1667,0,0,\n"
                             "fpfh,all,all,32,6,2,0.3333,1,0.1667,0,0,\n";
const char* kMethodsConfusion =
    "method,true_class,sedan,suv,tank,none\n"
    "gmatch,sedan,3,1,0,0\n"
    "gmatch,suv,2,1,0,1\n"
    "gmatch,tank,0,0,4,0\n"
    "verify,sedan,3,1,0,0\n"
    "verify,suv,1,2,0,1\n"
    "verify,tank,0,0,4,0\n"
    "fpfh,sedan,2,2,0,0\n"
    "fpfh,suv,4,0,0,0\n"
    "fpfh,tank,0,0,4,0\n";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("families section: canopy beside the baseline, per method, class, cover and noise, with time") {
  auto s = report::summarize_families(kConfusion, "c.csv", kAccuracy, "a.csv");
  CHECK(s.methods.empty());
  report::add_family_methods(s, kMethods, "m.csv", kMethodsConfusion, "mc.csv");
  CHECK(s.methods == std::vector<std::string>{"gmatch", "verify", "fpfh"});
  REQUIRE(s.method_rows.size() == 24);
  CHECK(s.method_rows[8].class_right == 9);
  CHECK(s.method_rows[8].timed == 10);
  CHECK(s.method_rows[8].seconds_mean == Approx(2.75));
  REQUIRE(s.method_confusion.size() == 3);
  CHECK(s.method_confusion[2].classes[1].answered == std::vector<int>{4, 0, 0, 0});
  CHECK(s.method_confusion[2].classes[1].right == 0);

  const std::string md = report::families_markdown(s);
  CHECK(md.find("### canopy beside the PCL baseline") != std::string::npos);
  CHECK(md.find(
            "| canopy (gmatch rank-1) | 8/12 = 66.7% [39.1, 86.2] | 3/12 = 25.0% [8.9, 53.2] | 1 | 1.50 |") !=
        std::string::npos);
  CHECK(md.find("| canopy (verify) | 9/12 = 75.0% [46.8, 91.1] | 4/12 = 33.3% [13.8, 60.9] | 1 | 2.75 (10 "
                "timed) |") != std::string::npos);
  CHECK(md.find("| FPFH | 6/12 = 50.0% [25.4, 74.6] | 2/12 = 16.7% [4.7, 44.8] | 0 | – |") != std::string::npos);
  CHECK(md.find("| class | trials | canopy (gmatch rank-1) | canopy (verify) | FPFH |") != std::string::npos);
  CHECK(
      md.find("| suv | 4 | 1/4 = 25.0% [4.6, 69.9] | 2/4 = 50.0% [15.0, 85.0] | 0/4 = 0.0% [0.0, 49.0] |") !=
      std::string::npos);
  CHECK(
      md.find(
          "| dense | 6 | 3/6 = 50.0% [18.8, 81.2] | 4/6 = 66.7% [30.0, 90.3] | 2/6 = 33.3% [9.7, 70.0] |") !=
      std::string::npos);
  CHECK(
      md.find("| 32 | 6 | 3/6 = 50.0% [18.8, 81.2] | 4/6 = 66.7% [30.0, 90.3] | 2/6 = 33.3% [9.7, 70.0] |") !=
      std::string::npos);
  CHECK(md.find("Confusion matrix of FPFH") != std::string::npos);
  CHECK(md.find("| suv | 4 | 0 | 0 | 0 |") != std::string::npos);
  CHECK(md.find("Confusion matrix of canopy (verify)") == std::string::npos);  // shown above
  // Without the methods tables the section is as before.
  const std::string plain =
      report::families_markdown(report::summarize_families(kConfusion, "c.csv", kAccuracy, "a.csv"));
  CHECK(plain.find("PCL baseline") == std::string::npos);
}

TEST_CASE("families section: the methods tables are checked against each other and the confusion matrix") {
  auto fresh = [] { return report::summarize_families(kConfusion, "c.csv", kAccuracy, "a.csv"); };
  auto fails = [&](const std::string& methods, const std::string& confusion, const char* needle) {
    auto s = fresh();
    try {
      report::add_family_methods(s, methods, "m.csv", confusion, "mc.csv");
      FAIL("no error");
    } catch (const common::DataError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  };
  // verify's right answers must be the confusion matrix's.
  fails(replaced(kMethods, "verify,all,all,all,12,9", "verify,all,all,all,12,8"), kMethodsConfusion, "verify");
  // every method covers the same trials.
  fails(replaced(kMethods, "fpfh,all,all,all,12,6", "fpfh,all,all,all,11,6"), kMethodsConfusion, "11 trials");
  // a per-method matrix that disagrees with its rows.
  fails(kMethods, replaced(kMethodsConfusion, "fpfh,suv,4,0", "fpfh,suv,3,1"), "class suv");
  // malformed cells and rows.
  fails(replaced(kMethods, "gmatch,all,all,all,12,8", "gmatch,all,all,all,12,x"), kMethodsConfusion, "line 2");
  fails(replaced(kMethods, "fpfh,suv,all,all,4,0,0.0000,0,0.0000,0,0,",
                 "fpfh,suv,all,all,4,0,0.0000,0,0.0000,0,0,7"),
        kMethodsConfusion, "without timed");
  fails(kHead, kMethodsConfusion, "no method");
  fails(kMethods, "true_class,sedan\n", "expected the header");
}

TEST_CASE("families section: methods tables are read beside accuracy.csv, both or neither") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(CANOPY_TEST_TMP) / "report-family-methods";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto put = [&](const char* name, const std::string& text) { std::ofstream(dir / name) << text; };
  put("confusion.csv", kConfusion);
  put("accuracy.csv", kAccuracy);
  const std::string c = (dir / "confusion.csv").string(), a = (dir / "accuracy.csv").string();
  CHECK(report::summarize_families(kConfusion, c, kAccuracy, a).methods.empty());
  put("methods.csv", kMethods);
  CHECK_THROWS_AS(report::summarize_families(kConfusion, c, kAccuracy, a), common::DataError);
  put("methods-confusion.csv", kMethodsConfusion);
  CHECK(report::summarize_families(kConfusion, c, kAccuracy, a).methods.size() == 3);
}
