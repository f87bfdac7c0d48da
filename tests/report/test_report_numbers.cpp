// report::compute: the numbers of the report from hand-built trials with known answers (the
// Markdown only renders these; test_report.cpp checks a few rendered rows).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "report/report.h"
#include "support/cli.h"
#include "trials.h"

using namespace canopy;
using report::testing::seg;
using report::testing::trial;

namespace {

// A stage run from an older two-column .time file (no CPU), and one with CPU columns.
report::StageTime took(double seconds, double peak_mb) {
  report::StageTime t;
  t.seconds = seconds;
  t.peak_mb = peak_mb;
  t.present = true;
  return t;
}
report::StageTime took(double seconds, double peak_mb, double user, double system) {
  report::StageTime t = took(seconds, peak_mb);
  t.user_seconds = user;
  t.system_seconds = system;
  t.has_cpu = true;
  return t;
}

// sedan: 2 of 2 at rank 1; tank: 1 of 3 (one failure over-segmented, one missing area); obj9:
// a model the thesis never printed and the modelbase lacks, 0 of 1 (no cause found).
report::Inputs hand_built() {
  report::Inputs in;
  in.objects = {"sedan", "tank", "obj9"};
  in.scenes = {"circle", "flyby"};
  in.noises = {0, 8};
  documents::SegmentGraph tank_model;
  tank_model.segments = {seg(0, 5, 1), seg(1, 5, 1)};  // 2 segments, 10 m²
  in.models["tank"] = tank_model;
  report::Case over = trial("tank", "circle", 8, 2);  // 4 target segments > 1.5 x 2; 9 m² >= 0.6 x 10
  over.segments.segments = {seg(0, 3, 1), seg(1, 2, 1), seg(2, 2, 1), seg(3, 2, 1)};
  in.cases = {trial("sedan", "circle", 0, 1), trial("sedan", "flyby", 8, 1),
              trial("tank", "circle", 0, 1),  over,
              trial("tank", "flyby", 0, 2),   trial("obj9", "circle", 0, 2)};
  in.cases[0].times = {
      {"addnoise", took(1.5, 10, 1.0, 0.25)}, {"fitvox", took(4, 300, 3.5, 0.25)}, {"verify", took(100, 50)}};
  in.cases[1].times = {{"addnoise", took(2.5, 30)}, {"fitvox", report::StageTime{}}};
  in.cases[2].times = {{"gmatch", took(0.25, 5, 0.25, 0)}};
  // The thesis table lists two trials: sedan/circle/0 at rank 1, tank/circle/0 at rank 2.
  in.thesis = {{"sedan/circle/0", {0.6, 1, 1.5}}, {"tank/circle/0", {0.5, 2, 2.0}}};
  in.render_times = {
      {"sedan/circle", took(10, 700, 9, 1)}, {"tank/circle", took(20, 900, 18, 1)}, {"tank/flyby", {}}};
  in.render_views = {{"circle", 3}, {"flyby", 5}};
  return in;
}

}  // namespace

TEST_CASE("numbers: rank-1 rates per object and overall, beside the thesis table's") {
  const auto n = report::compute(hand_built(), report::Params{});
  CHECK(n.per_object.at("sedan").right == 2);
  CHECK(n.per_object.at("sedan").trials == 2);
  CHECK(n.per_object.at("tank").right == 1);
  CHECK(n.per_object.at("tank").trials == 3);
  CHECK(n.per_object.at("obj9").right == 0);
  CHECK(n.all.right == 3);
  CHECK(n.all.trials == 6);
  CHECK(n.thesis_per_object.at("sedan").right == 1);
  CHECK(n.thesis_per_object.at("tank").right == 0);
  CHECK(n.thesis_per_object.at("tank").trials == 1);
  CHECK(n.thesis_per_object.at("obj9").trials == 0);
  CHECK(n.thesis_all.right == 1);
  CHECK(n.thesis_all.trials == 2);
  // Mean of the rates 100%, 33.3% and 0% over the three objects; the thesis's over the two it
  // printed (sedan 100%, tank 50%); its five objects are not all here.
  CHECK(n.mean_rate == Approx((100.0 + 100.0 / 3 + 0) / 3));
  CHECK(n.thesis_mean == Approx(75.0));
  CHECK(n.thesis_printed == 2);
  CHECK_FALSE(n.thesis_objects);
}

TEST_CASE("numbers: failures and their diagnosed causes") {
  const auto n = report::compute(hand_built(), report::Params{});
  REQUIRE(n.diagnoses.size() == 6);
  CHECK(n.diagnoses[3].correct_rank == 2);
  CHECK(n.diagnoses[3].target_segments == 4);
  CHECK(n.diagnoses[3].model_segments == 2);
  CHECK(n.by_key.at("tank/circle/8").target_area == Approx(9.0));
  CHECK(n.failed == 3);
  CHECK(n.over_segmented == 1);
  CHECK(n.missing_area == 1);  // tank/flyby/0: no target segment, 0 m² < 0.6 x 10 m²
  CHECK(n.spurious == 0);
  CHECK(n.unexplained == 1);  // obj9: no segments and no model to compare with
  report::Params strict;
  strict.missing_area_ratio = 1.0;  // tank/circle/8 too: 9 m² < 1 x 10 m²
  CHECK(report::compute(hand_built(), strict).missing_area == 2);
}

TEST_CASE("numbers: stage times summed over runs, renderings beside them, verify outside the total") {
  const auto n = report::compute(hand_built(), report::Params{});
  const auto& addnoise = n.stages.at("addnoise");
  CHECK(addnoise.runs == 2);
  CHECK(addnoise.seconds == Approx(4.0));
  CHECK(addnoise.peak_mb == Approx(30.0));
  CHECK(n.stages.at("fitvox").runs == 1);  // the second fitvox has no .time file
  CHECK(n.stages.at("cocone").runs == 0);  // present, empty
  CHECK(n.stages.at("verify").seconds == Approx(100.0));
  const auto& render = n.stages.at("rangetrace");
  CHECK(render.runs == 2);
  CHECK(render.seconds == Approx(30.0));
  CHECK(render.peak_mb == Approx(900.0));
  CHECK(n.render_images == 6);                          // two circle renderings of 3 views
  CHECK(n.total_seconds == Approx(30 + 4 + 4 + 0.25));  // rangetrace, addnoise, fitvox, gmatch
  // CPU beside wall: addnoise's second run is an older two-column file (no CPU).
  CHECK(addnoise.cpu_runs == 1);
  CHECK(addnoise.cpu_seconds == Approx(1.25));
  CHECK(render.cpu_runs == 2);
  CHECK(render.cpu_seconds == Approx(29));
  CHECK(n.stages.at("verify").cpu_runs == 0);
  CHECK(n.total_cpu_seconds == Approx(29 + 1.25 + 3.75 + 0.25));
  CHECK(n.total_runs == 6);
  CHECK(n.total_cpu_runs == 5);
  const auto out = report::render(hand_built(), report::Params{}, n);
  CHECK(out.times_csv.find("stage,runs,total_s,mean_s,peak_mb,cpu_s,cpu_runs\n") == 0);
  CHECK(out.times_csv.find("rangetrace,2,30.000,15.000,900,29.000,2\n") != std::string::npos);
  CHECK(out.times_csv.find("addnoise,2,4.000,2.000,30,1.250,1\n") != std::string::npos);
  CHECK(out.times_csv.find("verify,1,100.000,100.000,50,0.000,0\n") != std::string::npos);
  // The time table: CPU beside wall; partial CPU says of how many runs; none is a dash.
  CHECK(out.markdown.find(
            "| Range image generation | `rangetrace` | 2 (6 images) | 0:00:30 | 0:00:29 | 15.00 | 900 | "
            "780 | 7:34 |\n") != std::string::npos);
  CHECK(out.markdown.find(
            "| Noise | `addnoise` | 2 | 0:00:04 | 0:00:01 (1 of 2 runs) | 2.00 | 30 | – | – |\n") !=
        std::string::npos);
  CHECK(
      out.markdown.find("| Surface reconstruction | `cocone` | 0 | 0:00:00 | – | 0.00 | 0 | 90 | 2:14 |\n") !=
      std::string::npos);
  CHECK(
      out.markdown.find("| **all stages** | | | **0:00:38** | **0:00:34 (5 of 6 runs)** | | | | 11:54 |\n") !=
      std::string::npos);
}

TEST_CASE("numbers: an ablation's rates per object and over its trials") {
  report::Inputs in = hand_built();
  report::Ablation a;
  a.name = "variant";
  a.correct_rank = {{"sedan/circle/0", 1}, {"sedan/flyby/8", 2}, {"tank/circle/0", 1}, {"tank/circle/8", 0}};
  a.failed = 1;
  in.ablations = {a};
  const auto n = report::compute(in, report::Params{});
  REQUIRE(n.ablations.size() == 1);
  const auto& r = n.ablations[0];
  REQUIRE(r.per_object.size() == 3);
  CHECK(r.per_object[0].right == 1);
  CHECK(r.per_object[0].trials == 2);
  CHECK(r.per_object[1].right == 1);
  CHECK(r.per_object[1].trials == 2);
  CHECK(r.per_object[2].trials == 0);
  CHECK(r.all.right == 2);
  CHECK(r.all.trials == 4);
  CHECK(r.failed == 1);
}

TEST_CASE("numbers: the thesis's overall rate applies to its five objects only") {
  report::Inputs in;
  in.objects = {"earthmover", "obj1", "sedan", "semi", "tank"};
  in.scenes = {"circle"};
  in.noises = {0};
  for (const auto& o : in.objects) in.cases.push_back(trial(o, "circle", 0, 1));
  const auto n = report::compute(in, report::Params{});
  CHECK(n.thesis_objects);
  CHECK(n.thesis_printed == 5);
  CHECK(n.thesis_mean == Approx((100 + 64 + 100 + 83 + 50) / 5.0));
  CHECK(n.mean_rate == Approx(100.0));
}

TEST_CASE("report parameters out of range name their option") {
  report::Params p;
  CHECK_NOTHROW(report::validate(p));
  p.max_segments = 0;
  CHECK_THROWS_WITH(report::validate(p), Catch::Contains("--max-segments"));
  p = {};
  p.overseg_ratio = 0;
  CHECK_THROWS_AS(report::validate(p), common::UsageError);
  p = {};
  p.missing_area_ratio = -1;
  CHECK_THROWS_WITH(report::validate(p), Catch::Contains("--missing-area-ratio"));
  p = {};
  p.spurious_share = 1.5;
  CHECK_THROWS_WITH(report::validate(p), Catch::Contains("--spurious-share"));
}

TEST_CASE("numbers: a rendering's images from its scan, or from its stage log once the scan is gone") {
  const auto dir = test::fresh_dir("report", "render_views");
  const std::string scan = (dir / "scan.pcd").string();
  // No scan, no log: nothing says how many.
  CHECK(report::render_views(scan) == 0);
  // The scan: 1 + its largest view_idx (views 0..11 of a 12-view circle, in any order).
  formats::PointCloud c;
  c.resize(30);
  for (const char* f : {"x", "y", "z"}) c.add(f, formats::kFloat32);
  auto& view = c.add("view_idx", formats::kInt32);
  for (std::size_t i = 0; i < c.size(); ++i) view[i] = static_cast<double>((7 * i) % 12);
  formats::write_pcd(c, scan);
  std::ofstream(scan + ".log") << "rangetrace: render: 3 views x 2 passes\n"
                                  "rangetrace: wrote 30 points (tank, circle, 3 views) to "
                               << scan << "\n";
  CHECK(report::render_views(scan) == 12);  // the scan wins while it is there
  // The scan deleted after its last reader (KEEP=0): the count rangetrace wrote in its log.
  std::filesystem::remove(scan);
  CHECK(report::render_views(scan) == 3);
  // A log without the line (an older or a failed render): 0, as without a log.
  std::ofstream(scan + ".log") << "rangetrace: render: 12 views x 2 passes, 512x512 pixels\n";
  CHECK(report::render_views(scan) == 0);
  // A scan without view_idx: 0.
  formats::PointCloud plain;
  plain.resize(3);
  for (const char* f : {"x", "y", "z"}) plain.add(f, formats::kFloat32);
  formats::write_pcd(plain, scan);
  CHECK(report::render_views(scan) == 0);
}
