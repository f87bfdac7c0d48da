// famscore: the runs manifest, the nearest instance by size, and the confusion and accuracy
// tables on hand-made trials with known counts.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/family_runs.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/verdict.h"
#include "famscore/famscore.h"
#include "canopy/sim/families.h"
#include "support/cli.h"

using namespace canopy;
using namespace canopy::famscore;

TEST_CASE("famscore: the runs manifest") {
  const auto runs = documents::parse_family_runs(
      "# header\na/verdict.json pickup 1000 light 0\n\nb.json van 7 dense 32  # c\n", "runs");
  REQUIRE(runs.size() == 2);
  CHECK(runs[0].verdict == "a/verdict.json");
  CHECK(runs[0].vehicle_class == "pickup");
  CHECK(runs[0].instance == 1000);
  CHECK(runs[1].cover == "dense");
  CHECK(runs[1].noise == "32");
  CHECK(runs[1].line == 4);
  CHECK_THROWS_AS(documents::parse_family_runs("a.json van 7 dense\n", "runs"), common::DataError);
  CHECK_THROWS_AS(documents::parse_family_runs("a.json van x7 dense 0\n", "runs"), common::DataError);
  CHECK_THROWS_AS(documents::parse_family_runs("# nothing\n", "runs"), common::DataError);
  try {
    documents::parse_family_runs("ok.json van 1 a 0\nbad\n", "m.txt");
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
    const auto f = sim::make_family_instance(c, n);
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

namespace {

namespace fs = std::filesystem;

void write(const fs::path& p, const std::string& text) { test::write_file(p, text); }

// A stage's <file>.time for each (file, wall seconds), peak 20000 kB.
void write_times(const fs::path& dir, const std::vector<std::pair<std::string, double>>& times) {
  for (const auto& [f, s] : times) write(dir / (f + ".time"), std::to_string(s) + " 20000\n");
}

// A verdict with verify's class answer (the best hypothesis's class and model; accepted or not).
std::string verdict_text(const std::string& cls, const std::string& nearest, bool accepted) {
  documents::Verdict v;
  v.candidate = "samples.pcd";
  v.has_classes = true;
  v.vehicle_class = cls;
  v.nearest_instance = nearest;
  documents::Hypothesis h;
  h.model = nearest;
  h.gmatch_rank = 1;
  h.vehicle_class = cls;
  h.score = 0.7;
  v.hypotheses.push_back(h);
  v.chosen = accepted ? 0 : -1;
  v.model = accepted ? nearest : "";
  return documents::serialize_verdict(v);
}

std::string match_text(const std::string& rank1, const std::string& rank2) {
  documents::MatchResult m;
  m.object = "segments.json";
  m.error_form = "bounded";
  int rank = 1;
  for (const auto& name : {rank1, rank2}) {
    documents::ModelScore s;
    s.model = name;
    s.rank = rank;
    s.score = 0.9 - 0.1 * rank++;
    s.error_total = 1 - s.score;
    m.models.push_back(s);
  }
  return documents::serialize_match_result(m);
}

std::string baseline_text(const std::string& method, const std::string& rank1, double score) {
  return R"({"format": "canopy.baseline", "version": 1, "provenance": {}, "object": "samples.pcd",
  "candidate_points": 100, "methods": [{"method": ")" +
         method + R"(", "models": [{"rank": 1, "model": ")" + rank1 + R"(", "score": )" +
         std::to_string(score) + R"(}, {"rank": 2, "model": "tank-0", "score": 0}]}]})";
}

// methods.csv as method|class|cover|noise -> the numeric columns after them.
std::map<std::string, std::vector<std::string>> rows_of(const std::string& csv) {
  std::map<std::string, std::vector<std::string>> out;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    if (line.back() == ',') cells.emplace_back();
    REQUIRE(cells.size() == 12);
    out[cells[0] + "|" + cells[1] + "|" + cells[2] + "|" + cells[3]] = {cells.begin() + 4, cells.end()};
  }
  return out;
}

}  // namespace

TEST_CASE("famscore: gmatch, verify, VFH and FPFH side by side on hand-built trials") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "famscore" / "methods";
  fs::remove_all(root);
  const fs::path mb = root / "modelbase";
  for (const char* e : {"pickup-0", "pickup-1", "van-0", "van-1", "tank-0"}) {
    const std::string name = e;
    write(mb / (name + ".class"), name.substr(0, name.rfind('-')) + "\n");
  }
  const auto entries = read_entries(mb.string());
  REQUIRE(entries.size() == 5);
  // The size-nearest entry of each test vehicle, and the other entry of its class.
  const std::string n1 = nearest_by_size("pickup", 1000, entries);
  const std::string o1 = n1 == "pickup-0" ? "pickup-1" : "pickup-0";
  const std::string n3 = nearest_by_size("van", 1000, entries);
  const std::string n4 = nearest_by_size("van", 1001, entries);
  const std::string o4 = n4 == "van-0" ? "van-1" : "van-0";
  REQUIRE(!n1.empty());
  REQUIRE(!n3.empty());

  // T1 pickup-1000 light 0: verify right (nearest too); gmatch right class, other instance;
  //    VFH a van; FPFH the nearest instance. Every stage timed.
  const fs::path t1 = root / "t1";
  write(t1 / "verdict.json", verdict_text("pickup", n1, true));
  write(t1 / "match.json", match_text(o1, n1));
  write(t1 / "baseline-vfh.json", baseline_text("vfh", "van-0", 0.6));
  write(t1 / "baseline-fpfh.json", baseline_text("fpfh", n1, 0.8));
  write_times(t1, {{"mesh.ply", 1.0},
                   {"segments.json", 2.0},
                   {"match.json", 0.5},
                   {"verdict.json", 3.0},
                   {"baseline-vfh.json", 0.25},
                   {"baseline-fpfh.json", 4.0}});
  // T2 pickup-1001 dense 32: the chain failed (empty verdict and match), FPFH failed too, VFH a
  //    van; verify's stage has no .time.
  const fs::path t2 = root / "t2";
  write(t2 / "verdict.json", "");
  write(t2 / "match.json", "");
  write(t2 / "baseline-vfh.json", baseline_text("vfh", "van-1", 0.5));
  write(t2 / "baseline-fpfh.json", "");
  write_times(t2, {{"mesh.ply", 1.5},
                   {"segments.json", 1.0},
                   {"match.json", 0.5},
                   {"baseline-vfh.json", 0.75},
                   {"baseline-fpfh.json", 2.0}});
  // T3 van-1000 light 32: verify right, not accepted; gmatch the tank; VFH the nearest van;
  //    FPFH found no pose for any model (score 0: no answer).
  const fs::path t3 = root / "t3";
  write(t3 / "verdict.json", verdict_text("van", n3, false));
  write(t3 / "match.json", match_text("tank-0", n3));
  write(t3 / "baseline-vfh.json", baseline_text("vfh", n3, 0.7));
  write(t3 / "baseline-fpfh.json", baseline_text("fpfh", "van-0", 0.0));
  write_times(t3, {{"mesh.ply", 1.0},
                   {"segments.json", 1.0},
                   {"match.json", 1.0},
                   {"verdict.json", 1.0},
                   {"baseline-vfh.json", 0.5},
                   {"baseline-fpfh.json", 6.0}});
  // T4 van-1001 dense 0: verify a pickup; gmatch and FPFH the nearest van; VFH the other van.
  //    No .time files.
  const fs::path t4 = root / "t4";
  write(t4 / "verdict.json", verdict_text("pickup", "pickup-0", false));
  write(t4 / "match.json", match_text(n4, "tank-0"));
  write(t4 / "baseline-vfh.json", baseline_text("vfh", o4, 0.7));
  write(t4 / "baseline-fpfh.json", baseline_text("fpfh", n4, 0.9));

  const std::string manifest = (t1 / "verdict.json").string() + " pickup 1000 light 0\n" +
                               (t2 / "verdict.json").string() + " pickup 1001 dense 32\n" +
                               (t3 / "verdict.json").string() + " van 1000 light 32\n" +
                               (t4 / "verdict.json").string() + " van 1001 dense 0\n";
  std::vector<Trial> trials;
  for (const auto& r : documents::parse_family_runs(manifest, "runs"))
    trials.push_back(read_trial(r, entries, true));
  REQUIRE(trials.size() == 4);
  REQUIRE(trials[0].answers.size() == 4);
  CHECK(trials[0].answers[0].seconds == Approx(3.5));  // gmatch: cocone + ncut + gmatch
  CHECK(trials[0].answers[1].seconds == Approx(6.5));  // verify: + verify
  CHECK_FALSE(trials[1].answers[1].timed);             // no verdict.json.time
  CHECK(trials[1].answers[3].failed);

  const auto m = rows_of(methods_csv(trials));
  // trials, class_right, class_accuracy, nearest_right, nearest_accuracy, failed, timed, seconds_mean
  auto check = [&](const std::string& key, int n, int right, int nearest, int failed, int timed, double mean) {
    INFO(key);
    REQUIRE(m.count(key) == 1);
    const auto& r = m.at(key);
    CHECK(std::stoi(r[0]) == n);
    CHECK(std::stoi(r[1]) == right);
    CHECK(std::stod(r[2]) == Approx(static_cast<double>(right) / n).margin(1e-4));
    CHECK(std::stoi(r[3]) == nearest);
    CHECK(std::stoi(r[5]) == failed);
    CHECK(std::stoi(r[6]) == timed);
    if (timed > 0) {
      CHECK(std::stod(r[7]) == Approx(mean).margin(1e-3));
    } else {
      CHECK(r[7].empty());
    }
  };
  check("gmatch|all|all|all", 4, 2, 1, 1, 3, 9.5 / 3);
  check("verify|all|all|all", 4, 2, 2, 1, 2, 5.25);
  check("vfh|all|all|all", 4, 2, 1, 0, 3, 0.5);
  check("fpfh|all|all|all", 4, 2, 2, 1, 3, 4.0);
  check("gmatch|pickup|all|all", 2, 1, 0, 1, 2, 3.25);
  check("gmatch|van|all|all", 2, 1, 1, 0, 1, 3.0);
  check("verify|van|all|all", 2, 1, 1, 0, 1, 4.0);
  check("vfh|pickup|all|all", 2, 0, 0, 0, 2, 0.5);
  check("fpfh|all|light|all", 2, 1, 1, 0, 2, 5.0);
  check("fpfh|all|dense|all", 2, 1, 1, 1, 1, 2.0);
  check("vfh|all|all|32", 2, 1, 1, 0, 2, 0.625);
  check("verify|all|all|0", 2, 1, 1, 0, 1, 6.5);
  CHECK(m.size() == 4 * (1 + 2 + 2 + 2));

  // One confusion matrix per method: rows pickup, van; columns pickup, van, tank, none.
  CHECK(methods_confusion_csv(trials, entries) ==
        "method,true_class,pickup,van,tank,none\n"
        "gmatch,pickup,1,0,0,1\n"
        "gmatch,van,0,1,1,0\n"
        "verify,pickup,1,0,0,1\n"
        "verify,van,1,1,0,0\n"
        "vfh,pickup,0,2,0,0\n"
        "vfh,van,0,2,0,0\n"
        "fpfh,pickup,1,0,0,1\n"
        "fpfh,van,0,1,0,1\n");
  // verify's column of the side-by-side table is the confusion matrix of confusion.csv.
  CHECK(confusion_csv(trials, entries) == "true_class,pickup,van,tank,none\npickup,1,0,0,1\nvan,1,1,0,0\n");

  // The stage: run() reads the same manifest and modelbase and renders the same tables; without
  // the methods it renders only the two class tables.
  Params p;
  p.with_methods = true;
  const Outputs out = run(p, {manifest, "runs", mb.string()});
  CHECK(out.trials == 4);
  CHECK(out.entries == 5);
  CHECK(out.confusion == confusion_csv(trials, entries));
  CHECK(out.accuracy == accuracy_csv(trials));
  CHECK(out.methods == methods_csv(trials));
  CHECK(out.methods_confusion == methods_confusion_csv(trials, entries));
  const Outputs plain = run(Params{}, {manifest, "runs", mb.string()});
  CHECK(plain.confusion == out.confusion);
  CHECK(plain.accuracy == out.accuracy);
  CHECK(plain.methods.empty());
  CHECK(plain.methods_confusion.empty());

  // A missing method file is an error naming it; a malformed baseline document too.
  fs::remove(t4 / "baseline-fpfh.json");
  try {
    read_trial(documents::parse_family_runs((t4 / "verdict.json").string() + " van 1001 dense 0\n", "runs")[0],
               entries, true);
    FAIL("no error");
  } catch (const common::DataError& e) {
    CHECK(std::string(e.what()).find("baseline-fpfh.json") != std::string::npos);
  }
  CHECK_NOTHROW(read_trial(
      documents::parse_family_runs((t4 / "verdict.json").string() + " van 1001 dense 0\n", "runs")[0],
      entries, false));
  write(t4 / "baseline-fpfh.json", "{\"format\": \"canopy.match_result\"}");
  CHECK_THROWS_AS(read_trial(documents::parse_family_runs(
                                 (t4 / "verdict.json").string() + " van 1001 dense 0\n", "runs")[0],
                             entries, true),
                  common::DataError);
  CHECK_THROWS_AS(read_entries((root / "no-such").string()), common::DataError);
}
