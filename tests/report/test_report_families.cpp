// The report's "Vehicle families" section (tools/report/families_section.h): per-class and
// overall class accuracy, the confusion matrix and nearest-instance accuracy from hand-written
// famscore tables, and errors on malformed or inconsistent tables.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"
#include "family_tables.h"
#include "one_trial.h"
#include "report/families_section.h"
#include "support/cli.h"

using namespace canopy;

namespace {

const char* const kConfusion = test::kFamilyConfusion;
const char* const kAccuracy = test::kFamilyAccuracy;

}  // namespace

TEST_CASE("families section: class accuracy per class and overall, levels, nearest instance") {
  const auto s = report::summarize_families(kConfusion, "c.csv", kAccuracy, "a.csv");
  REQUIRE(s.classes.size() == 3);
  CHECK(s.answers == std::vector<std::string>{"sedan", "suv", "tank", "none"});
  CHECK(s.classes[0].name == "sedan");
  CHECK(s.classes[0].trials == 4);
  CHECK(s.classes[0].right == 3);
  CHECK(s.classes[1].right == 2);
  CHECK(s.classes[1].answered == std::vector<int>{1, 2, 0, 1});
  CHECK(s.classes[2].right == 4);
  CHECK(s.trials == 12);
  CHECK(s.right == 9);
  REQUIRE(s.levels.size() == 2);
  CHECK(s.levels[1].cover == "dense");
  CHECK(s.levels[1].noise == "32");
  CHECK(s.levels[1].class_right == 4);
  CHECK(s.levels[1].failed == 1);
  CHECK(s.all.nearest_right == 4);
  CHECK(s.all.accepted == 8);
  CHECK(s.all.accepted_right == 7);

  const std::string md = report::families_markdown(s);
  CHECK(md.find("## Vehicle families") != std::string::npos);
  CHECK(md.find("**Class accuracy: 9/12 = 75.0% [46.8, 91.1]**") != std::string::npos);
  CHECK(md.find("nearest in size): 4/12 = 33.3% [13.8, 60.9]") != std::string::npos);
  CHECK(md.find("| sedan | 4 | 3/4 = 75.0% [30.1, 95.4] |") != std::string::npos);
  CHECK(md.find("| suv | 4 | 2/4 = 50.0% [15.0, 85.0] |") != std::string::npos);
  CHECK(md.find("| tank | 4 | 4/4 = 100.0% [51.0, 100.0] |") != std::string::npos);
  CHECK(md.find("| **all** | 12 | **9/12 = 75.0% [46.8, 91.1]** |") != std::string::npos);
  CHECK(md.find("| dense | 32 | 6 | 4/6 = 66.7% [30.0, 90.3] | 3 (3) | 1/6 = 16.7% [3.0, 56.4] | 1 |") !=
        std::string::npos);
  CHECK(md.find("| **all** |  | 12 | 9/12 = 75.0% [46.8, 91.1] | 8 (7) | 4/12 = 33.3% [13.8, 60.9] | 1 |") !=
        std::string::npos);
  // The confusion matrix as a table, right answers in bold.
  CHECK(md.find("| true \\ answered | sedan | suv | tank | none |") != std::string::npos);
  CHECK(md.find("| suv | 1 | **2** | 0 | 1 |") != std::string::npos);
  CHECK(md.find("| tank | 0 | 0 | **4** | 0 |") != std::string::npos);
}

TEST_CASE("families section: a true class never answered has no right answers") {
  const auto s = report::summarize_families("true_class,sedan,none\nsedan,1,0\nbus,1,1\n", "c.csv",
                                            "cover,noise,trials,class_right,accepted,accepted_right,"
                                            "nearest_right,failed\nall,all,3,1,0,0,0,0\n",
                                            "a.csv");
  CHECK(s.classes[1].name == "bus");
  CHECK(s.classes[1].right == 0);
  CHECK(s.classes[1].trials == 2);
  CHECK(s.right == 1);
  CHECK(s.levels.empty());
}

TEST_CASE("families section: malformed or inconsistent tables are DataErrors naming the file") {
  auto fails = [](const std::string& c, const std::string& a, const std::string& file, const std::string& what) {
    try {
      report::summarize_families(c, "c.csv", a, "a.csv");
      FAIL("no error");
    } catch (const common::DataError& e) {
      const std::string m = e.what();
      INFO(m);
      CHECK(m.find(file) != std::string::npos);
      CHECK(m.find(what) != std::string::npos);
    }
  };
  fails("", kAccuracy, "c.csv", "empty");
  fails("class,sedan\nsedan,1\n", kAccuracy, "c.csv", "true_class");
  fails("true_class,sedan,suv,tank,none\nsedan,3,1,0\n", kAccuracy, "c.csv", "line 2");
  fails("true_class,sedan,suv,tank,none\nsedan,3,x,0,0\n", kAccuracy, "c.csv", "'x' is not a count");
  fails("true_class,sedan,suv,tank,none\nsedan,3,-1,0,0\n", kAccuracy, "c.csv", "not a count");
  fails(kConfusion, "cover,noise,trials\nall,all,12\n", "a.csv", "no column 'class_right'");
  fails(kConfusion,
        "cover,noise,trials,class_right,accepted,accepted_right,nearest_right,failed\n"
        "light,0,6,5,5,4,3,0\n",
        "a.csv", "no 'all,all' row");
  fails(kConfusion,
        "cover,noise,trials,class_right,accepted,accepted_right,nearest_right,failed\n"
        "all,all,12,10,8,7,4,1\n",
        "a.csv", "disagree");
  fails(kConfusion,
        "cover,noise,trials,class_right,accepted,accepted_right,nearest_right,failed\n"
        "all,all,12,9,8,9,4,1\n",
        "a.csv", "exceeds");
}

TEST_CASE("report --families adds the section; without it the report has none; a missing table is exit 1") {
  namespace fs = std::filesystem;
  const fs::path dir = test::fresh_dir("report", "families-cli");
  documents::ExperimentManifest manifest = report::testing::one_trial_manifest(dir);
  fs::create_directories(dir / "families");
  for (const char* d : {"with", "without", "missing"}) fs::create_directories(dir / d);
  std::ofstream(dir / "families" / "confusion.csv") << kConfusion;
  std::ofstream(dir / "families" / "accuracy.csv") << kAccuracy;
  manifest.figures = {"figures/grid-circle.png", "figures/scores.png", "pictures/sedan.png"};
  std::ofstream(dir / "experiment.txt") << documents::write_experiment_manifest(manifest);
  const std::string report =
      std::string(CANOPY_BIN_DIR) + "/report --manifest " + (dir / "experiment.txt").string() + " --results ";
  std::string err;
  REQUIRE(test::sh(report + (dir / "with").string() + " --families " + (dir / "families").string(),
                   dir / "err1.txt", &err) == 0);
  const std::string with = test::read_text(dir / "with" / "report.md");
  CHECK(with.find("**Class accuracy: 9/12 = 75.0% [46.8, 91.1]**") != std::string::npos);
  CHECK(with.find("| suv | 1 | **2** | 0 | 1 |") != std::string::npos);
  // The report links the manifest's figures, and no other.
  CHECK(with.find("pictures/sedan.png") != std::string::npos);
  CHECK(with.find("tank-circle") == std::string::npos);
  REQUIRE(test::sh(report + (dir / "without").string(), dir / "err2.txt", &err) == 0);
  const std::string without = test::read_text(dir / "without" / "report.md");
  CHECK(without.find("Vehicle families") == std::string::npos);
  // The report without the section is the report with it, up to the section.
  CHECK(with.substr(0, without.size()) == without);
  fs::remove(dir / "families" / "accuracy.csv");
  CHECK(test::sh(report + (dir / "missing").string() + " --families " + (dir / "families").string(),
                 dir / "err3.txt", &err) == 1);
  CHECK(err.find("accuracy.csv: missing") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "missing" / "report.md"));
}

TEST_CASE("families section: rows pooling noise copies of one render get Wilson at the renders") {
  auto s = report::summarize_families(kConfusion, "c.csv", kAccuracy, "a.csv");
  // One cover level at two noise levels: each test render is run twice, so a row pooling the
  // noise levels has trials / 2 independent units (9/12 at 6 -> [36.5, 94.0]; a class's 3/4 at 2
  // -> [19.8, 97.3]); a row of one cover and noise level keeps its trials (4/6 -> [30.0, 90.3]).
  s.levels[1].cover = "light";
  const std::string md = report::families_markdown(s);
  INFO(md);
  CHECK(md.find("**Class accuracy: 9/12 = 75.0% [36.5, 94.0]**") != std::string::npos);
  CHECK(md.find("| sedan | 4 | 3/4 = 75.0% [19.8, 97.3] |") != std::string::npos);
  CHECK(md.find("| light | 32 | 6 | 4/6 = 66.7% [30.0, 90.3] |") != std::string::npos);
  CHECK(md.find("| **all** |  | 12 | 9/12 = 75.0% [36.5, 94.0] |") != std::string::npos);
}
