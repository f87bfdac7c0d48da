// The prefilter (docs/decisions/gmatch.md §9): heading-invariant summaries, the K best models
// (coarse search or summaries), the true model kept on a hand-built case where one summary
// alone would drop it, and K >= N (or 0) identical to no prefilter.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"
#include "gmatch/gmatch.h"
#include "fixtures/gmatch_graphs.h"
#include "support/cli.h"

namespace fs = std::filesystem;
namespace gm = canopy::gmatch;
using namespace gmatch_test;

namespace {

// A flat grid of roof panels of total area `area` in a square: the footprint of a graph with
// no sides at all.
SegmentGraph roof_panels(double area) {
  SegmentGraph g;
  const double side = std::sqrt(area / 4);
  for (int i = 0; i < 4; ++i) {
    g.segments.push_back(face(i, {(i % 2) * side, (i / 2) * side, 1.5}, {0, 0, 1}, side, side));
  }
  return g;
}

// The object: the sedan with its far side and rear hidden (occlusion), seen at a heading.
SegmentGraph occluded_sedan() {
  return transformed(perturbed(without(vehicle(), {4, 6, 8, 10}), 5), 2.1, 0.0, {12, -7, 0});
}

std::vector<gm::Model> five_models() {
  const SegmentGraph object = occluded_sedan();
  return {{"blob", random_graph(11, 30)},
          {"panels", roof_panels(gm::summarize(object, 15).area)},
          {"sedan", vehicle()},
          {"truck", vehicle(8.0, 2.5, 1.6, 2.0, 1.0, 2.5, 0.6)},
          {"van", vehicle(5.2, 2.0, 1.3, 3.8, 0.6, -0.4, 0.35)}};
}

}  // namespace

TEST_CASE("summaries are invariant to heading, position and segment order", "[gmatch][prefilter]") {
  const SegmentGraph g = perturbed(vehicle(), 3);
  const gm::Summary a = gm::summarize(g, 15);
  const gm::Summary b = gm::summarize(shuffled(transformed(g, 1.3, 0.0, {40, -3, 0}), 9), 15);
  REQUIRE(a.segments == 11);
  CHECK(b.area == Approx(a.area).epsilon(1e-12));
  for (int i = 0; i < 3; ++i) {
    CHECK(b.spread[i] == Approx(a.spread[i]).epsilon(1e-9));
    CHECK(b.tilt[i] == Approx(a.tilt[i]).margin(1e-12));
  }
  CHECK(gm::summary_distance(a, b) == Approx(0).margin(1e-9));
  // The sedan: 3 roof faces of 4.5 x 1.8 m footprint, the rest vertical faces.
  const gm::Summary s = gm::summarize(vehicle(), 15);
  CHECK(s.tilt[1] == 0);
  CHECK(s.tilt[0] + s.tilt[2] == Approx(1));
  CHECK(s.spread[0] > s.spread[1]);  // longer than wide
  // Only the X largest segments count.
  CHECK(gm::summarize(vehicle(), 3).segments == 3);
  CHECK(gm::summarize(vehicle(), 3).area < s.area);
}

TEST_CASE("summary distance: symmetric, zero on itself, grows with a scaling", "[gmatch][prefilter]") {
  const gm::Summary a = gm::summarize(vehicle(), 15);
  const gm::Summary b = gm::summarize(vehicle(8.0, 2.5, 1.6, 2.0, 1.0, 2.5, 0.6), 15);
  const gm::Summary c = gm::summarize(vehicle(5.0, 2.0, 0.8, 2.4, 0.5, 0.1, 0.3), 15);
  CHECK(gm::summary_distance(a, a) == 0);
  CHECK(gm::summary_distance(a, b) == Approx(gm::summary_distance(b, a)));
  CHECK(gm::summary_distance(a, c) > 0);
  CHECK(gm::summary_distance(a, c) < gm::summary_distance(a, b));
}

TEST_CASE("the prefilter keeps the true model that one summary alone would drop", "[gmatch][prefilter]") {
  const SegmentGraph object = occluded_sedan();
  const auto models = five_models();
  const gm::Summary o = gm::summarize(object, 15);
  const auto d = [&](int i) { return gm::summary_distance(o, gm::summarize(models[i].graph, 15)); };
  // By total area the flat panels are the nearest model (equal area by construction) and the
  // sedan, whose hidden faces the object lacks, is not ...
  const auto area_gap = [&](int i) {
    return std::fabs(std::log(o.area / gm::summarize(models[i].graph, 15).area));
  };
  REQUIRE(area_gap(1) < 1e-9);
  REQUIRE(area_gap(2) > 0.2);
  // ... but the whole summary puts the sedan nearest, and K = 2 keeps it.
  for (int i : {0, 1, 3, 4}) CHECK(d(2) < d(i));
  for (const auto by : {gm::PrefilterBy::kSummary, gm::PrefilterBy::kCoarse}) {
    INFO(gm::to_string(by));
    gm::Params p;
    p.prefilter = 2;
    p.prefilter_by = by;
    for (int threads : {1, 2}) {
      p.threads = threads;
      const std::vector<int> kept = gm::prefilter(object, models, p);
      REQUIRE(kept.size() == 2);
      REQUIRE(std::find(kept.begin(), kept.end(), 2) != kept.end());
      REQUIRE(std::is_sorted(kept.begin(), kept.end()));
    }
  }

  gm::Params on;
  on.prefilter = 2;
  const gm::Outputs with = gm::run(on, {&object, &models});
  const gm::Outputs off = gm::run(gm::Params{}, {&object, &models});
  REQUIRE(with.searched == 2);
  REQUIRE(with.result.models.size() == 2);
  REQUIRE(off.result.models.front().model == "sedan");
  REQUIRE(with.result.models.front().model == "sedan");
  CHECK(with.result.models.front().score == off.result.models.front().score);
  // Models not searched have no statistics.
  int searched = 0;
  for (const auto& s : with.stats) searched += s.nodes > 0 ? 1 : 0;
  CHECK(searched == 2);
}

TEST_CASE("prefilter K >= N or 0 is identical to no prefilter", "[gmatch][prefilter]") {
  const SegmentGraph object = occluded_sedan();
  const auto models = five_models();
  const std::string off =
      canopy::documents::serialize_match_result(gm::run(gm::Params{}, {&object, &models}).result);
  for (int k : {0, 5, 6, 1000}) {
    gm::Params p;
    p.prefilter = k;
    p.prefilter_by = k == 6 ? gm::PrefilterBy::kSummary : gm::PrefilterBy::kCoarse;
    p.threads = 2;
    const gm::Outputs out = gm::run(p, {&object, &models});
    CHECK(out.searched == 5);
    CHECK(canopy::documents::serialize_match_result(out.result) == off);
  }
  gm::Params bad;
  bad.prefilter = -1;
  CHECK_THROWS_AS(gm::validate(bad), canopy::common::UsageError);
  bad.prefilter = 2;
  bad.coarse_segments = 0;
  CHECK_THROWS_AS(gm::validate(bad), canopy::common::UsageError);
  bad.coarse_segments = 5;
  bad.threads = 0;
  CHECK_THROWS_WITH(gm::validate(bad), Catch::Contains("--threads"));
}

TEST_CASE("prefilter ties go to modelbase order", "[gmatch][prefilter]") {
  // Five identical models: every distance is equal, the first K are kept.
  std::vector<gm::Model> same;
  for (int i = 0; i < 5; ++i) same.push_back({"m" + std::to_string(i), vehicle()});
  for (const auto by : {gm::PrefilterBy::kSummary, gm::PrefilterBy::kCoarse}) {
    gm::Params p;
    p.prefilter = 3;
    p.prefilter_by = by;
    p.threads = 2;
    CHECK(gm::prefilter(occluded_sedan(), same, p) == std::vector<int>{0, 1, 2});
  }
}

TEST_CASE("gmatch --prefilter: recorded only when it acts, otherwise byte-identical",
          "[gmatch][prefilter][cli]") {
  const fs::path dir = canopy::test::fresh_dir("gmatch", "prefilter");
  const fs::path mb = dir / "modelbase";
  fs::create_directories(mb);
  for (const auto& m : five_models()) {
    canopy::documents::write_segment_graph(m.graph, (mb / (m.name + ".json")).string());
  }
  const fs::path object = dir / "segments.json";
  canopy::documents::write_segment_graph(occluded_sedan(), object.string());
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/gmatch";
  const std::string base = bin + " -i " + object.string() + " --modelbase " + mb.string();
  std::string err;
  for (const char* k : {"0", "5", "default"}) {  // (0 and 5 with --prefilter-by summary too)
    const std::string opt =
        std::string(k) == "default" ? "" : std::string(" --prefilter-by summary --prefilter ") + k;
    REQUIRE(canopy::test::sh(base + opt + " -o " + (dir / (std::string(k) + ".json")).string(), dir / "err",
                             &err) == 0);
  }
  const std::string off = canopy::common::read_file((dir / "0.json").string());
  CHECK(off == canopy::common::read_file((dir / "5.json").string()));
  CHECK(off == canopy::common::read_file((dir / "default.json").string()));
  CHECK(off.find("\"prefilter\":") == std::string::npos);  // not among the parameters

  REQUIRE(canopy::test::sh(base + " --prefilter 2 -o " + (dir / "2.json").string(), dir / "err", &err) == 0);
  CHECK(err.find("2 of 5 models (prefilter)") != std::string::npos);
  const std::string two = canopy::common::read_file((dir / "2.json").string());
  CHECK(two.find("\"prefilter-by\": \"coarse\"") != std::string::npos);
  const auto r = canopy::documents::read_match_result((dir / "2.json").string());
  REQUIRE(r.models.size() == 2);
  CHECK(r.models.front().model == "sedan");
  bool recorded = false;
  for (const auto& [key, v] : r.provenance.parameters) recorded |= key == "prefilter" && v == "2";
  CHECK(recorded);
  CHECK(canopy::test::sh(base + " --prefilter -3 -o " + (dir / "x.json").string(), dir / "err", &err) == 2);
  CHECK_FALSE(fs::exists(dir / "x.json"));
}
