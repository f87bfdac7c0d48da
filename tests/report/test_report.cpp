#include <catch2/catch.hpp>

#include "canopy/common/error.h"
#include "report/report.h"
#include "trials.h"

using namespace canopy;

using report::testing::seg;

namespace {

// A trial in the scene "circle".
report::Case make_case(const std::string& object, int noise, int rank) {
  return report::testing::trial(object, "circle", noise, rank);
}

}  // namespace

TEST_CASE("diagnosis counts target segments, area and spurious share against the model") {
  documents::SegmentGraph model;
  model.segments = {seg(0, 4.0, 1), seg(1, 2.0, 1), seg(2, 2.0, 1)};  // 3 segments, 8 m^2
  report::Case c = make_case("sedan", 0, 2);
  // 5 target segments with 4 m^2 (over-segmented, half the area) and one 1 m^2 foliage segment.
  c.segments.segments = {seg(0, 1.0, 1), seg(1, 1.0, 2), seg(2, 1.0, 1),
                         seg(3, 0.5, 1), seg(4, 0.5, 1), seg(5, 1.0, 1)};
  report::Params p;
  const auto d = report::diagnose(c, &model, p);
  CHECK(d.target_segments == 5);
  CHECK(d.model_segments == 3);
  CHECK(d.target_area == Approx(4.0));
  CHECK(d.model_area == Approx(8.0));
  CHECK(d.spurious_segments == 1);
  CHECK(d.spurious_area_share == Approx(1.0 / 5.0));
  CHECK(d.over_segmented);  // 5 > 1.5 x 3
  CHECK(d.missing_area);    // 4 < 0.6 x 8
  CHECK_FALSE(d.spurious);  // 0.2 is not above 0.2
  CHECK(d.correct_rank == 2);
  CHECK(d.best_model == "other");
  p.max_segments = 1;  // only the largest segment (a target one, first of the 1 m^2 ties) examined
  CHECK(report::diagnose(c, &model, p).spurious_segments == 0);
}

TEST_CASE("recognition rates per object and overall, with the thesis beside them") {
  report::Inputs in;
  in.objects = {"sedan", "tank"};
  in.scenes = {"circle"};
  in.noises = {0, 8};
  in.cases = {make_case("sedan", 0, 1), make_case("sedan", 8, 1), make_case("tank", 0, 1),
              make_case("tank", 8, 3)};
  in.thesis = report::parse_thesis_csv(
      "object,scene,noise_mm,score,rank,entropy\nsedan,circle,0,0.641,1,1.64\ntank,circle,0,0.603,2,2.26\n",
      "t.csv");
  const auto out = report::run(report::Params{}, in);
  // Intervals at the distinct renders: two noise levels of one render per object are one unit
  // (Wilson at n = 1: 1 -> [20.7, 100], 0.5 -> [5.5, 94.5]); all trials: 2 units, 0.75 -> [19.8, 97.3].
  CHECK(out.markdown.find("| sedan | 100% (2/2) | 2/2 = 100.0% [20.7, 100.0] | 100% | 100% (1/1) |") !=
        std::string::npos);
  CHECK(out.markdown.find("| tank | 50% (1/2) | 1/2 = 50.0% [5.5, 94.5] | 50% | 0% (0/1) |") !=
        std::string::npos);
  CHECK(out.markdown.find("**75%** (3/4)") != std::string::npos);
  // Two of the thesis's objects: its means are over them, its overall rate (five objects) is not shown.
  CHECK(out.markdown.find("| **all trials** | **75%** (3/4) | 3/4 = 75.0% [19.8, 97.3] | – | 50% (1/2) |") !=
        std::string::npos);
  CHECK(out.markdown.find("| mean per object | 75% | | 75% | |") != std::string::npos);
  CHECK(out.markdown.find("obj1") == std::string::npos);
  CHECK(out.markdown.find("1 trials did not rank the correct model first") != std::string::npos);
  // scores.csv: one line per trial with the correct model's score and rank.
  CHECK(out.scores_csv ==
        "object,scene,noise_mm,score,rank,entropy\n"
        "sedan,circle,0,0.9000,1,0.5000\nsedan,circle,8,0.9000,1,0.5000\n"
        "tank,circle,0,0.9000,1,0.5000\ntank,circle,8,0.4000,3,0.5000\n");
}

TEST_CASE(
    "models the thesis never printed (family instances) show no thesis value and leave its mean alone") {
  report::Inputs in;
  in.objects = {"sedan", "suv-1000"};
  in.scenes = {"circle"};
  in.noises = {0};
  in.cases = {make_case("sedan", 0, 1), make_case("suv-1000", 0, 2)};
  const auto out = report::run(report::Params{}, in);
  INFO(out.markdown);
  CHECK(out.markdown.find("| suv-1000 | 0% (0/1) | 0/1 = 0.0% [0.0, 79.3] | – | – (0/0) |") !=
        std::string::npos);
  // canopy's mean over both objects (100% and 0%); the thesis's over the one it printed (sedan 100%).
  CHECK(out.markdown.find("| mean per object | 50% | | 100% | |") != std::string::npos);
  CHECK(out.markdown.find("| **all trials** | **50%** (1/2) | 1/2 = 50.0% [9.5, 90.5] | – |") !=
        std::string::npos);
  CHECK(out.markdown.find("### suv-1000 — 0% (thesis –)") != std::string::npos);
}

TEST_CASE("a malformed thesis table names the file") {
  CHECK_THROWS_AS(report::parse_thesis_csv("h\na,b,c\n", "bad.csv"), common::DataError);
  CHECK_THROWS_WITH(report::parse_thesis_csv("h\na,b,1,x,1,2\n", "bad.csv"), Catch::Contains("bad.csv"));
}

TEST_CASE("ablation rows give each variant's rank-1 rate per object and overall") {
  report::Inputs in;
  in.objects = {"sedan", "tank"};
  in.scenes = {"circle"};
  in.noises = {0};
  in.cases = {make_case("sedan", 0, 1), make_case("tank", 0, 1)};
  report::Ablation a;
  a.name = "ncut-squared";
  a.change = "ncut --exponent squared";
  a.correct_rank = {{"sedan/circle/0", 1}, {"tank/circle/0", 2}};
  in.ablations.push_back(a);
  const auto out = report::run(report::Params{}, in);
  // (one noise level: every trial its own render; all trials with Wilson at 2)
  CHECK(out.markdown.find("| **canopy defaults** | | 100% | 100% | **2/2 = 100.0% [34.2, 100.0]** |") !=
        std::string::npos);
  CHECK(out.markdown.find(
            "| ncut-squared | `ncut --exponent squared` | 100% | 0% | 1/2 = 50.0% [9.5, 90.5] |") !=
        std::string::npos);
}

TEST_CASE("area table: ratios of sums per noise level and matched area relative to 0 mm") {
  report::Inputs in;
  in.objects = {"sedan", "tank"};
  in.scenes = {"circle"};
  in.noises = {0, 32};
  auto with = [](report::Case c, double vis, double smp, double mesh, double segs, double matched) {
    c.areas = {true, vis, smp, mesh, segs, matched};
    return c;
  };
  // sedan: 10 m² visible; tank: 30 m². tank at 32 mm has no areas.json (left out of its row).
  in.cases = {with(make_case("sedan", 0, 1), 10, 8, 6, 6, 5), with(make_case("tank", 0, 1), 30, 24, 18, 18, 15),
              with(make_case("sedan", 32, 1), 10, 9, 4, 4, 2), make_case("tank", 32, 2)};
  const auto rows = report::summarize_areas(in);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].noise_mm == 0);
  CHECK(rows[0].trials == 2);
  CHECK(rows[0].visible == Approx(40));
  CHECK(rows[0].samples == Approx(32.0 / 40));
  CHECK(rows[0].mesh == Approx(24.0 / 40));
  CHECK(rows[0].segments == Approx(24.0 / 40));
  CHECK(rows[0].matched == Approx(20.0 / 40));
  CHECK(rows[0].matched_vs_0 == Approx(1.0));
  CHECK(rows[1].trials == 1);
  CHECK(rows[1].visible == Approx(10));
  CHECK(rows[1].samples == Approx(0.9));
  CHECK(rows[1].mesh == Approx(0.4));
  CHECK(rows[1].matched == Approx(0.2));
  CHECK(rows[1].matched_vs_0 == Approx(2.0 / 5.0));  // sedan only: tank has no 32 mm areas
  CHECK(rows[1].pairs_vs_0 == 1);
  const auto out = report::run(report::Params{}, in);
  CHECK(out.markdown.find("| 0 | 2 | 20.0 | 80% | 60% | 60% | 50% | 100% |") != std::string::npos);
  CHECK(out.markdown.find("| 32 | 1 | 10.0 | 90% | 40% | 40% | 20% | 40% |") != std::string::npos);
  CHECK(out.markdown.find("matched  32 mm |########## 20%") != std::string::npos);
  CHECK(out.areas_csv.find("mesh,all,32,0.4000,0,0\n") != std::string::npos);
}

TEST_CASE("no areas.json anywhere: no area section") {
  report::Inputs in;
  in.objects = {"sedan"};
  in.scenes = {"circle"};
  in.noises = {0};
  in.cases = {make_case("sedan", 0, 1)};
  CHECK(report::run(report::Params{}, in).markdown.find("Where the target's area goes") == std::string::npos);
  CHECK_FALSE(report::read_areas(std::string(CANOPY_TEST_TMP) + "/no-such-dir/areas.json").present);
}

TEST_CASE("recognition by scene: unoccluded apart, trials and renders with Wilson intervals") {
  report::Inputs in;
  in.objects = {"sedan", "tank"};
  in.scenes = {"circle", "unoccluded"};
  in.noises = {0, 8};
  // gmatch right everywhere but sedan/circle at 8 mm.
  for (const auto& o : in.objects)
    for (const auto& s : in.scenes)
      for (int n : in.noises)
        in.cases.push_back(report::testing::trial(o, s, n, o == "sedan" && s == "circle" && n == 8 ? 2 : 1));
  const std::string md = report::run(report::Params{}, in).markdown;
  INFO(md);
  // circle: 3 of 4 trials; of its 2 renders only tank's is right at both noise levels.
  // Wilson 95%: 3/4 -> [30.1, 95.4], 1/2 -> [9.5, 90.5], 4/4 -> [51.0, 100.0], 2/2 -> [34.2, 100.0].
  CHECK(md.find("| circle | 2 | 4 | 3/4 = 75.0% [30.1, 95.4] | 1/2 = 50.0% [9.5, 90.5] |\n") !=
        std::string::npos);
  CHECK(md.find("| unoccluded (the modelbase's own renders) | 2 | 4 | 4/4 = 100.0% [51.0, 100.0] | "
                "2/2 = 100.0% [34.2, 100.0] |\n") != std::string::npos);
  CHECK(md.find("| **occluded (all but unoccluded)** | 2 | 4 | 3/4 = 75.0% [30.1, 95.4] |") !=
        std::string::npos);
  CHECK(md.find("| all | 4 | 8 | 7/8 = 87.5% [52.9, 97.8] | 3/4 = 75.0% [30.1, 95.4] |\n") != std::string::npos);
  // No verdicts: no verify columns.
  CHECK(md.find("verify right, trials") == std::string::npos);
}
