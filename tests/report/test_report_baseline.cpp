// The baseline section of the report (tools/report/baseline_section.h): rank-1 counts per
// object and noise of gmatch, verify and the two baseline methods from hand-written trials.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/verdict.h"
#include "report/baseline_section.h"
#include "support/cli.h"

namespace fs = std::filesystem;

namespace {

// The manifest of a grid of trials in OUT/<object>/<scene>/noise-<mm> (make's layout, here the
// test's own).
canopy::documents::ExperimentManifest grid(const fs::path& out, const std::vector<std::string>& objects,
                                           const std::vector<std::string>& scenes,
                                           const std::vector<int>& noises) {
  canopy::documents::ExperimentManifest m;
  m.objects = objects;
  m.scenes = scenes;
  m.noises = noises;
  for (const auto& o : objects)
    for (const auto& s : scenes)
      for (int n : noises)
        m.trials.push_back({o, s, n, (out / o / s / ("noise-" + std::to_string(n))).string()});
  return m;
}

void trial(const fs::path& out, const std::string& object, int noise, const std::string& gmatch,
           const std::string& vfh, const std::string& fpfh, const std::string& verify) {
  const fs::path dir = out / object / "circle" / ("noise-" + std::to_string(noise));
  fs::create_directories(dir);
  canopy::documents::MatchResult m;
  m.error_form = "bounded";
  for (const std::string& name : {gmatch, std::string("other")}) {
    canopy::documents::ModelScore s;
    s.model = name;
    s.rank = static_cast<int>(m.models.size()) + 1;
    s.score = 0.9 - 0.1 * s.rank;
    m.models.push_back(s);
  }
  canopy::documents::write_match_result(m, (dir / "match.json").string());
  std::ofstream(dir / "baseline.json")
      << R"({"format": "canopy.baseline", "version": 1, "methods": [)"
      << R"({"method": "vfh", "models": [{"rank": 1, "model": ")" << vfh << R"("}]},)"
      << R"({"method": "fpfh", "models": [{"rank": 1, "model": ")" << fpfh << R"("}]}]})";
  std::ofstream(dir / "baseline.json.time") << "0.50 40960\n";
  if (!verify.empty()) {
    // verify's answer: one hypothesis, chosen (documents/verdict.h writes the whole verdict).
    canopy::documents::Verdict v;
    v.provenance = {"verify", "test", {}, {}};
    v.candidate = (dir / "samples.pcd").string();
    v.confidence = 0.9;
    canopy::documents::Hypothesis h;
    h.model = verify;
    h.gmatch_rank = 1;
    v.hypotheses = {h};
    v.chosen = 0;
    v.model = verify;
    canopy::documents::write_verdict(v, (dir / "verdict.json").string());
  }
}

}  // namespace

TEST_CASE("baseline section: rank-1 of canopy and both baseline methods per object and noise",
          "[report][baseline]") {
  const fs::path out = canopy::test::fresh_dir("report", "baseline") / "out";
  trial(out, "sedan", 0, "sedan", "tank", "sedan", "sedan");
  trial(out, "sedan", 8, "tank", "sedan", "sedan", "");
  trial(out, "tank", 0, "tank", "tank", "sedan", "tank");
  // tank at 8 mm has no baseline.json: left out. The sedan trials' .time files have CPU columns
  // (0.45 s user + 0.05 s system each), tank's is an older two-column file.
  for (int n : {0, 8}) {
    std::ofstream(out / "sedan" / "circle" / ("noise-" + std::to_string(n)) / "baseline.json.time")
        << "0.50 40960 0.45 0.05\n";
  }
  const auto b = canopy::report::baseline_section(grid(out, {"sedan", "tank"}, {"circle"}, {0, 8}));
  INFO(b.markdown);
  // Wilson 95% at the distinct renders: the 2 noise levels copy one render, so the object and
  // all rows have trials / 2 units (sedan 1/2 at 1: [5.5, 94.5]; tank 1/1 at 0.5: [11.5, 100];
  // all 2/3 at 1.5: [12.9, 96.4]); a noise level's row its trials (0/1 at 1: [0, 79.3]).
  CHECK(b.markdown.find("| sedan | 2 | 1/2 = 50.0% [5.5, 94.5] | 1/2 = 50.0% [5.5, 94.5] | "
                        "1/2 = 50.0% [5.5, 94.5] | 2/2 = 100.0% [20.7, 100.0] |") != std::string::npos);
  CHECK(b.markdown.find("| tank | 1 | 1/1 = 100.0% [11.5, 100.0] | 1/1 = 100.0% [11.5, 100.0] | "
                        "1/1 = 100.0% [11.5, 100.0] | 0/1 = 0.0% [0.0, 88.5] |") != std::string::npos);
  CHECK(b.markdown.find("| all | 3 | 2/3 = 66.7% [12.9, 96.4] | 2/3 = 66.7% [12.9, 96.4] | "
                        "2/3 = 66.7% [12.9, 96.4] | 2/3 = 66.7% [12.9, 96.4] |") != std::string::npos);
  CHECK(b.markdown.find(
            "| 8 | 1 | 0/1 = 0.0% [0.0, 79.3] | 0/1 = 0.0% [0.0, 79.3] | 1/1 = 100.0% [20.7, 100.0] | "
            "1/1 = 100.0% [20.7, 100.0] |") != std::string::npos);
  CHECK(b.markdown.find("1 trials have no baseline.json") != std::string::npos);
  CHECK(b.markdown.find("verify was not run on 1 of them") != std::string::npos);
  CHECK(b.markdown.find("mean 0.50 s") != std::string::npos);
  CHECK(b.markdown.find("total 1.5 s wall, CPU 1.0 s (2 of 3 runs), peak 40 MB.") != std::string::npos);
  CHECK(b.csv.find(",baseline_s,baseline_peak_mb,baseline_cpu_s\n") != std::string::npos);
  CHECK(b.csv.find("sedan,circle,8,tank,0,,0,sedan,1,sedan,1,0.500,40.0,0.500\n") != std::string::npos);
  CHECK(b.csv.find("tank,circle,0,tank,1,tank,1,tank,1,sedan,0,0.500,40.0,\n") != std::string::npos);
  CHECK(std::count(b.csv.begin(), b.csv.end(), '\n') == 4);  // header + 3 trials

  // No baseline.json anywhere: no section, no CSV.
  const fs::path none = canopy::test::fresh_dir("report", "baseline-none") / "out";
  fs::create_directories(none);
  CHECK(canopy::report::baseline_section(grid(none, {"sedan"}, {"circle"}, {0})).markdown.empty());
}
