// gmatch's two-sided coverage (issue 15): a small model that matches part of a big object is
// short of object area; the model-side form (--coverage model) kept for the ablation lets it
// tie. Plus the table output and the object name.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "gmatch/gmatch.h"
#include "fixtures/gmatch_graphs.h"

using namespace gmatch_test;
namespace gm = canopy::gmatch;

namespace {

// The truck's three largest segments, as a model of its own ("a small car").
SegmentGraph part_of(const SegmentGraph& g, int keep) {
  SegmentGraph part = g;
  std::sort(part.segments.begin(), part.segments.end(),
            [](const auto& a, const auto& b) { return a.area > b.area; });
  part.segments.resize(keep);
  return part;
}

}  // namespace

TEST_CASE("two-sided coverage: a small model covering part of a big object loses", "[gmatch]") {
  const auto truck = vehicle(6.5, 2.4, 1.2, 1.6, 1.0, 2.0, 0.5);
  const auto small = part_of(truck, 3);
  const auto object = transformed(truck, 0.8, 0.0, {2, -1, 0});
  double total = 0, kept = 0;
  for (const auto& s : truck.segments) total += s.area;
  for (const auto& s : small.segments) kept += s.area;

  gm::Params model_side;
  model_side.coverage = gm::Coverage::kModel;
  const auto t1 = gm::match_model(object, {"truck", truck}, model_side);
  const auto s1 = gm::match_model(object, {"small", small}, model_side);
  // Model side only: the small model is fully covered, as well as the truck.
  REQUIRE(t1.score == Approx(1.0));
  REQUIRE(s1.score == Approx(1.0));

  const gm::Params both;  // the default
  REQUIRE(both.coverage == gm::Coverage::kBoth);
  const auto t2 = gm::match_model(object, {"truck", truck}, both);
  const auto s2 = gm::match_model(object, {"small", small}, both);
  REQUIRE(t2.score == Approx(1.0));
  // Object side = the three segments' share of the object's area; geometric mean with 1.
  REQUIRE(s2.score == Approx(std::sqrt(kept / total)).epsilon(1e-9));
  REQUIRE(s2.error_coverage == Approx(1 - std::sqrt(kept / total)).epsilon(1e-9));

  std::vector<gm::Model> models{{"small", small}, {"truck", truck}};
  const auto ranked = gm::run(both, {&object, &models});
  REQUIRE(ranked.result.models[0].model == "truck");
  REQUIRE(ranked.result.models[0].score > ranked.result.models[1].score + 0.2);
}

TEST_CASE("branch and bound is exact with both coverage forms", "[gmatch]") {
  for (auto cov : {gm::Coverage::kBoth, gm::Coverage::kModel}) {
    for (std::uint64_t seed = 70; seed < 74; ++seed) {
      const auto model = random_graph(seed, 14);
      const auto object = perturbed(without(model, {0, 3}), seed + 7, 0.1, 0.02, 0.05, 0.05);
      gm::Params p;
      p.coverage = cov;
      p.max_segments = 8;
      const auto a = gm::match_model(object, {"m", model}, p);
      p.bound = false;
      const auto b = gm::match_model(object, {"m", model}, p);
      REQUIRE(a.score == b.score);
      REQUIRE(a.pairs.size() == b.pairs.size());
      for (std::size_t i = 0; i < a.pairs.size(); ++i) {
        REQUIRE(a.pairs[i].model_segment == b.pairs[i].model_segment);
      }
    }
  }
}

TEST_CASE("table output and object names", "[gmatch]") {
  REQUIRE(gm::object_name("out/sedan/circle/noise-8/segments.json") == "out/sedan/circle/noise-8");
  REQUIRE(gm::object_name("scans/tank-east.json") == "tank-east");
  REQUIRE(gm::object_name("-") == "<stdin>");
  const auto truck = vehicle(6.5, 2.4, 1.2, 1.6, 1.0, 2.0, 0.5);
  std::vector<gm::Model> models{{"sedan", vehicle()}, {"truck", truck}};
  const auto r = gm::run(gm::Params{}, {&truck, &models}).result;
  const std::string t = gm::format_table(r, "truck-scan");
  // Two header lines, then one line per model in rank order.
  REQUIRE(t.rfind("# object truck-scan, entropy ", 0) == 0);
  const auto l1 = t.find("\n1 truck 1.0000 ");
  const auto l2 = t.find("\n2 sedan ");
  REQUIRE(l1 != std::string::npos);
  REQUIRE(l2 != std::string::npos);
  REQUIRE(l1 < l2);
  REQUIRE(std::count(t.begin(), t.end(), '\n') == 4);
}
