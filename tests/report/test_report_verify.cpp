#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "report/report.h"

using namespace canopy;

namespace {

// A trial of `object` in `scene` whose gmatch rank-1 model is `gmatch_first`.
report::Case make_trial(const std::string& object, const std::string& scene, int noise,
                        const std::string& gmatch_first) {
  report::Case c;
  c.object = object;
  c.scene = scene;
  c.noise_mm = noise;
  const std::string second = gmatch_first == object ? "other" : object;
  c.match.models = {{gmatch_first, 0.9, 1, 0, 0, 0, 0, 0, {}, {}}, {second, 0.4, 2, 0, 0, 0, 0, 0, {}, {}}};
  return c;
}

// verify answered `model` ("" = none) with `confidence`; the chosen hypothesis is posed by a
// heading of `heading_deg` about z and the translation (x, y, z).
void answer(report::Case& c, const std::string& model, double confidence, double heading_deg = 0,
            double x = 0, double y = 0, double z = 0) {
  c.verdict_status = report::VerdictStatus::read;
  c.verdict.model = model;
  c.verdict.confidence = confidence;
  if (model.empty()) return;
  documents::Hypothesis h;
  h.model = model;
  const double a = heading_deg * M_PI / 180.0, co = std::cos(a), si = std::sin(a);
  h.pose.rotation = {co, -si, 0, si, co, 0, 0, 0, 1};
  h.pose.translation = {x, y, z};
  c.verdict.hypotheses = {h};
  c.verdict.chosen = 0;
}

// Eight hand-built trials (sedan, tank x circle, flyby x 0, 32 mm), one of each kind:
//  1 sedan/circle/0   right, conf 0.95, 5 mm (3-4-5), heading 1      gmatch right
//  2 sedan/flyby/0    right, conf 1.00, 50 mm (30-40-50), heading -3 gmatch wrong
//  3 sedan/circle/32  sedan posed at heading 179: flipped, conf 0.85  gmatch right
//  4 sedan/flyby/32   empty verdict.json: failed                     gmatch wrong
//  5 tank/circle/0    wrong model (sedan), conf 0.75                 gmatch right
//  6 tank/flyby/0     none, conf 0.5                                 gmatch wrong
//  7 tank/circle/32   no verdict.json: verify not run                gmatch right
//  8 tank/flyby/32    right, conf 0.3, 100 mm up, heading 359 (= -1) gmatch wrong
report::Inputs hand_built() {
  report::Inputs in;
  in.objects = {"sedan", "tank"};
  in.scenes = {"circle", "flyby"};
  in.noises = {0, 32};
  auto t1 = make_trial("sedan", "circle", 0, "sedan");
  answer(t1, "sedan", 0.95, 1, 0.003, 0.004, 0);
  auto t2 = make_trial("sedan", "flyby", 0, "other");
  answer(t2, "sedan", 1.0, -3, 0.03, -0.04, 0);
  auto t3 = make_trial("sedan", "circle", 32, "sedan");
  answer(t3, "sedan", 0.85, 179, 0.01, 0, 0);
  auto t4 = make_trial("sedan", "flyby", 32, "other");
  t4.verdict_status = report::VerdictStatus::failed;
  auto t5 = make_trial("tank", "circle", 0, "tank");
  answer(t5, "sedan", 0.75);
  auto t6 = make_trial("tank", "flyby", 0, "other");
  answer(t6, "", 0.5);
  auto t7 = make_trial("tank", "circle", 32, "tank");
  auto t8 = make_trial("tank", "flyby", 32, "other");
  answer(t8, "tank", 0.3, 359, 0, 0, 0.1);
  in.cases = {t1, t3, t2, t4, t5, t7, t6, t8};  // objects x scenes x noises order
  return in;
}

}  // namespace

TEST_CASE("verify summary: right, flipped, wrong model, none, failed and not run on hand-built trials") {
  const auto v = report::summarize_verify(hand_built());
  CHECK(v.not_run == 1);
  CHECK(v.all.trials == 7);
  CHECK(v.all.right == 3);
  CHECK(v.all.flipped == 1);
  CHECK(v.all.wrong_model == 1);
  CHECK(v.all.none == 1);
  CHECK(v.all.failed == 1);
  CHECK(v.all.gmatch_right == 3);  // trials 1, 3, 5 (7 was not verified: left out)

  const auto& sedan = v.per_object.at("sedan");
  CHECK(sedan.trials == 4);
  CHECK(sedan.right == 2);
  CHECK(sedan.flipped == 1);
  CHECK(sedan.failed == 1);
  CHECK(sedan.wrong_model + sedan.none == 0);
  CHECK(sedan.gmatch_right == 2);
  const auto& tank = v.per_object.at("tank");
  CHECK(tank.trials == 3);
  CHECK(tank.right == 1);
  CHECK(tank.wrong_model == 1);
  CHECK(tank.none == 1);
  CHECK(tank.failed + tank.flipped == 0);
  CHECK(tank.gmatch_right == 1);

  const auto& n0 = v.per_noise.at(0);
  CHECK(n0.trials == 4);
  CHECK(n0.right == 2);
  CHECK(n0.wrong_model == 1);
  CHECK(n0.none == 1);
  CHECK(n0.gmatch_right == 2);
  const auto& n32 = v.per_noise.at(32);
  CHECK(n32.trials == 3);
  CHECK(n32.right == 1);
  CHECK(n32.flipped == 1);
  CHECK(n32.failed == 1);
  CHECK(n32.gmatch_right == 1);

  // Judgements in case order: the flip is detected from the pose, the heading wraps at 360.
  REQUIRE(v.judgements.size() == 8);
  CHECK(v.judgements[1].outcome == report::Outcome::flipped);
  CHECK(v.judgements[1].heading_error == Approx(179));
  CHECK(v.judgements[3].outcome == report::Outcome::failed);
  CHECK(v.judgements[5].outcome == report::Outcome::not_run);
  CHECK(v.judgements[6].answer == "none");
  CHECK(v.judgements[7].heading_error == Approx(1));
  CHECK(v.judgements[0].position_error == Approx(0.005));
}

TEST_CASE("verify reliability bins and pose error percentiles on hand-built trials") {
  const auto v = report::summarize_verify(hand_built());
  REQUIRE(v.reliability.size() == 5);
  const int answers[] = {1, 1, 1, 1, 2};  // 0.3 | 0.5 (lower edge) | 0.75 | 0.85 | 0.95, 1.0 (last bin has 1)
  const int right[] = {1, 0, 0, 0, 2};    // the 0.85 answer is the flipped one: wrong
  const double lo[] = {0, 0.5, 0.7, 0.8, 0.9};
  for (int b = 0; b < 5; ++b) {
    CAPTURE(b);
    CHECK(v.reliability[b].lo == Approx(lo[b]));
    CHECK(v.reliability[b].answers == answers[b]);
    CHECK(v.reliability[b].right == right[b]);
  }
  // Right answers: positions 0.005, 0.05, 0.1 m; headings 1, 3, 1 degrees.
  CHECK(v.posed == 3);
  CHECK(v.position_median == Approx(0.05));
  CHECK(v.position_p90 == Approx(0.05 + 0.8 * 0.05));  // rank 1.8 of 0..2
  CHECK(v.heading_median == Approx(1));
  CHECK(v.heading_p90 == Approx(1 + 0.8 * 2));
  CHECK(report::percentile({}, 0.5) == 0);
  CHECK(report::percentile({4, 1, 2, 3}, 0.5) == Approx(2.5));
}

TEST_CASE("verify section and verdicts.csv in the report") {
  const auto out = report::run(report::Params{}, hand_built());
  CHECK_THAT(out.markdown, Catch::Contains("## Verification (`verify`)"));
  CHECK_THAT(out.markdown, Catch::Contains("verify was not run on 1 trials"));
  // all trials: 3/7 right, 1 wrong model, 1 flipped, 1 none, 1 failed; gmatch 3/7.
  // Wilson 95% at the distinct renders: a row pooling the 2 noise levels has trials / 2 units
  // (all: 3/7 at 3.5 -> [10.6, 82.6]; sedan 2/4 at 2 -> [9.5, 90.5]), a noise level's row its
  // trials (32 mm: 1/3 at 3 -> [6.1, 79.2]); reliability bins answers / 2 (2/2 at 1 -> [20.7, 100]).
  CHECK_THAT(out.markdown,
             Catch::Contains("| **all trials** | 7 | 3/7 = 42.9% [10.6, 82.6] | 1 | 1 | 1 | 1 | "
                             "3/7 = 42.9% [10.6, 82.6] |"));
  CHECK_THAT(
      out.markdown,
      Catch::Contains("| sedan | 4 | 2/4 = 50.0% [9.5, 90.5] | 0 | 1 | 0 | 1 | 2/4 = 50.0% [9.5, 90.5] |"));
  CHECK_THAT(
      out.markdown,
      Catch::Contains("| 32 mm | 3 | 1/3 = 33.3% [6.1, 79.2] | 0 | 1 | 0 | 1 | 1/3 = 33.3% [6.1, 79.2] |"));
  CHECK_THAT(out.markdown, Catch::Contains("| 0.9–1.0 | 2 | 2/2 = 100.0% [20.7, 100.0] |"));
  CHECK_THAT(out.markdown, Catch::Contains("position median 0.050 m, 90th percentile 0.090 m"));

  std::istringstream csv(out.verdicts_csv);
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  REQUIRE(lines.size() == 9);  // header + one row per trial
  CHECK(lines[0].rfind("object,scene,noise_mm,answer,confidence,correct,gmatch_rank1,", 0) == 0);
  CHECK(lines[1] == "sedan,circle,0,sedan,0.9500,1,sedan,right,0.0050,1.000");
  CHECK(lines[2] == "sedan,circle,32,sedan,0.8500,0,sedan,flipped,0.0100,179.000");
  CHECK(lines[4] == "sedan,flyby,32,,,0,other,failed,,");
  CHECK(lines[5] == "tank,circle,0,sedan,0.7500,0,tank,wrong_model,,");
  CHECK(lines[6] == "tank,circle,32,,,,tank,not_run,,");
  CHECK(lines[7] == "tank,flyby,0,none,0.5000,0,other,none,,");
}

TEST_CASE("no verdict.json anywhere: the section says verify was not run") {
  report::Inputs in = hand_built();
  for (auto& c : in.cases) c.verdict_status = report::VerdictStatus::missing;
  const auto v = report::summarize_verify(in);
  CHECK(v.all.trials == 0);
  CHECK(v.not_run == 8);
  const auto out = report::run(report::Params{}, in);
  CHECK_THAT(out.markdown, Catch::Contains("`verify` was not run on these trials"));
  CHECK_THAT(out.markdown, !Catch::Contains("| confidence | answers | right |"));
}

TEST_CASE("recognition by scene: verify's columns over trials and renders") {
  const std::string md = report::run(report::Params{}, hand_built()).markdown;
  INFO(md);
  // circle: gmatch right on all 4; verify right on trial 1 only, trial 7 not run; no render
  // right at both noise levels (sedan flipped at 32 mm, tank wrong at 0 mm).
  CHECK(md.find("| circle | 2 | 4 | 4/4 = 100.0% [51.0, 100.0] | 2/2 = 100.0% [34.2, 100.0] | "
                "1/4 = 25.0% [4.6, 69.9] (verify not run on some) | 0/2 = 0.0% [0.0, 65.8] |\n") !=
        std::string::npos);
  // flyby: gmatch right on none; verify on trials 2 and 8, never both of one render.
  CHECK(md.find(
            "| flyby | 2 | 4 | 0/4 = 0.0% [0.0, 49.0] | 0/2 = 0.0% [0.0, 65.8] | 2/4 = 50.0% [15.0, 85.0] | "
            "0/2 = 0.0% [0.0, 65.8] |\n") != std::string::npos);
  CHECK(md.find("occluded (all but unoccluded)") == std::string::npos);  // no unoccluded scene
}
