// gmatch matching logic on hand-built graphs with known answers.
#include <catch2/catch.hpp>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "gmatch/gmatch.h"
#include "fixtures/gmatch_graphs.h"

using namespace gmatch_test;
namespace gm = canopy::gmatch;
using canopy::documents::ModelScore;

namespace {

ModelScore match(const SegmentGraph& object, const SegmentGraph& model, const gm::Params& p = {},
                 gm::SearchStats* stats = nullptr) {
  return gm::match_model(object, gm::Model{"m", model}, p, stats);
}

int model_of(const ModelScore& ms, int object_segment) {
  for (const auto& pr : ms.pairs) {
    if (pr.object_segment == object_segment) return pr.model_segment;
  }
  return -2;  // not considered
}

void require_same(const ModelScore& a, const ModelScore& b) {
  REQUIRE(a.score == b.score);
  REQUIRE(a.error_total == b.error_total);
  REQUIRE(a.pairs.size() == b.pairs.size());
  for (size_t i = 0; i < a.pairs.size(); ++i) {
    REQUIRE(a.pairs[i].object_segment == b.pairs[i].object_segment);
    REQUIRE(a.pairs[i].model_segment == b.pairs[i].model_segment);
    REQUIRE(a.pairs[i].unary_error == b.pairs[i].unary_error);
  }
}

// Two segments: a square A (id 0, 4 m^2) and an elongated B (id 1, 3 m^2) that cannot match
// each other (E_U > 0.6), identical unary attributes in object and model, so that only the
// pairwise relation decides whether B can match.
SegmentGraph pair_graph(double distance, double angle_b) {
  SegmentGraph g;
  g.segments.push_back(face(0, {0, 0, 1}, {0, 0, 1}, 2.0, 2.0));
  g.segments.push_back(face(1, {distance, 0, 1}, {std::sin(angle_b), 0, std::cos(angle_b)}, 4.0, 0.75));
  return g;
}

}  // namespace

TEST_CASE("a graph matched against itself scores 1 and ranks first", "[gmatch]") {
  const auto sedan = vehicle();
  const auto truck = vehicle(6.5, 2.4, 1.2, 1.6, 1.0, 2.0, 0.5);
  const auto blob = random_graph(7, 11);
  const auto self = match(sedan, sedan);
  REQUIRE(self.score == Approx(1.0).margin(1e-12));
  REQUIRE(self.error_coverage == Approx(0.0).margin(1e-12));
  for (const auto& pr : self.pairs) REQUIRE(pr.model_segment >= 0);

  const std::vector<gm::Model> models{{"blob", blob}, {"sedan", sedan}, {"truck", truck}};
  const auto out = gm::run(gm::Params{}, {&sedan, &models});
  REQUIRE(out.result.models.front().model == "sedan");
  REQUIRE(out.result.models.front().rank == 1);
  REQUIRE(out.result.models[1].score < 1.0);

  // A larger graph than X: the X largest segments are matched, still a perfect score.
  const auto big = random_graph(11, 40);
  REQUIRE(match(big, big).score == Approx(1.0).margin(1e-12));
}

TEST_CASE("shuffling segment order changes nothing", "[gmatch]") {
  const auto model = random_graph(3, 30);
  const auto object = perturbed(model, 4);
  const auto ref = match(object, model);
  REQUIRE(ref.score > 0.5);
  for (std::uint64_t seed : {1, 2, 3}) {
    require_same(match(shuffled(object, seed), model), ref);
    require_same(match(object, shuffled(model, seed + 10)), ref);
  }
}

TEST_CASE("rotating and translating the object changes nothing in the default mode", "[gmatch]") {
  const auto sedan = vehicle();
  const auto object = perturbed(sedan, 5);
  const auto ref = match(object, sedan);
  for (double heading : {0.3, 1.2740903, 2.9, -2.0}) {
    const auto moved = transformed(object, heading, 0.2, {12.5, -3.0, 0.4});
    const auto got = match(moved, sedan);
    REQUIRE(got.score == Approx(ref.score).margin(1e-9));
    for (size_t i = 0; i < ref.pairs.size(); ++i) {
      REQUIRE(got.pairs[i].model_segment == ref.pairs[i].model_segment);
    }
  }
  // The printed Eq. 6.7 depends on the heading: a vehicle turned by 90 degrees loses matches.
  gm::Params thesis;
  thesis.orientation = gm::OrientationForm::kThesis;
  const double aligned = match(object, sedan, thesis).score;
  const double turned = match(transformed(object, canopy::common::kPi / 2, 0, {0, 0, 0}), sedan, thesis).score;
  REQUIRE(aligned > 0.8);
  REQUIRE(turned < aligned - 0.1);
}

TEST_CASE("dropping segments lowers the score monotonically", "[gmatch]") {
  SECTION("hand-built vehicle") {
    const auto sedan = vehicle();
    std::vector<int> dropped;
    double last = match(sedan, sedan).score;
    for (int id : {9, 3, 0, 6, 2, 7}) {
      dropped.push_back(id);
      const double s = match(without(sedan, dropped), sedan).score;
      REQUIRE(s < last);
      last = s;
    }
  }
  SECTION("random graph larger than X") {
    const auto g = random_graph(21, 40);
    std::vector<int> dropped;
    double last = match(g, g).score;
    for (int id : {0, 5, 10, 15, 20, 25}) {
      dropped.push_back(id);
      const double s = match(without(g, dropped), g).score;
      REQUIRE(s <= last);
      last = s;
    }
    REQUIRE(last < 0.95);
  }
}

TEST_CASE("an unrelated graph scores lower than the true one", "[gmatch]") {
  const auto sedan = vehicle();
  const auto truck = vehicle(6.5, 2.4, 1.2, 1.6, 1.0, 2.0, 0.5);
  const auto object = perturbed(sedan, 9);
  const double truth = match(object, sedan).score;
  REQUIRE(match(object, truck).score < truth);
  for (std::uint64_t seed = 100; seed < 105; ++seed) {
    REQUIRE(match(object, random_graph(seed, 11)).score < truth);
  }
}

TEST_CASE("the unary threshold prunes pairs with E_U above it", "[gmatch]") {
  // Same shape, area ratio r: d_a = -log2 r, E_U = 1 - exp(-d_a^2); E_U = 0.6 at r = 0.5153.
  auto one = [](double area) {
    SegmentGraph g;
    g.segments.push_back(face(0, {0, 0, 1}, {0, 0, 1}, area, 1.0));
    g.segments[0].elongation = 0.5;  // only the area differs
    return g;
  };
  const auto model = one(1.0);
  const auto kept = match(one(0.53), model);
  REQUIRE(model_of(kept, 0) == 0);
  const double da = -std::log2(0.53);
  REQUIRE(kept.pairs[0].unary_error == Approx(1 - std::exp(-da * da)).epsilon(1e-12));
  REQUIRE(model_of(match(one(0.50), model), 0) == -1);
  gm::Params loose;
  loose.unary_threshold = 0.7;
  REQUIRE(model_of(match(one(0.50), model, loose), 0) == 0);
  // Thickness: w_t |dt| = 0.5 -> E_U = 1 - exp(-0.25) = 0.221.
  auto thin = one(1.0);
  thin.segments[0].thickness += 0.05;
  REQUIRE(match(thin, model).pairs[0].unary_error == Approx(1 - std::exp(-0.25)).epsilon(1e-9));
}

TEST_CASE("the centroid-distance threshold prunes pairs with d_R above it", "[gmatch]") {
  const auto object = pair_graph(1.0, 0.5);
  // d_R = |1 - 1.25| / 1.25 = 0.2 (kept); |1 - 1.5| / 1.5 = 0.333 (pruned).
  const auto near = match(object, pair_graph(1.25, 0.5));
  REQUIRE(model_of(near, 0) == 0);
  REQUIRE(model_of(near, 1) == 1);
  REQUIRE(near.error_distance == Approx(0.2).epsilon(1e-12));
  const auto far = match(object, pair_graph(1.5, 0.5));
  REQUIRE(model_of(far, 0) == 0);
  REQUIRE(model_of(far, 1) == -1);
  gm::Params loose;
  loose.distance_threshold = 0.35;
  REQUIRE(model_of(match(object, pair_graph(1.5, 0.5), loose), 1) == 1);
}

TEST_CASE("the orientation threshold prunes pairs with E_O above it", "[gmatch]") {
  const double deg = canopy::common::kDegree;
  const auto object = pair_graph(1.0, 60 * deg);
  // E_O = (2/pi) |60 deg - phi_m|: 37.5 deg -> 0.25 (kept), 28.5 deg -> 0.35 (pruned).
  const auto kept = match(object, pair_graph(1.0, 37.5 * deg));
  REQUIRE(model_of(kept, 1) == 1);
  REQUIRE(kept.error_orientation == Approx(0.25).epsilon(1e-9));
  REQUIRE(model_of(match(object, pair_graph(1.0, 28.5 * deg)), 1) == -1);
}

TEST_CASE("normal signs: axial mode ignores flipped normals, signed mode does not", "[gmatch]") {
  const auto sedan = vehicle();
  auto flipped = sedan;
  for (int id : {2, 5, 7}) {
    auto& n = flipped.segments[id].normal;
    n = {-n[0], -n[1], -n[2]};
  }
  REQUIRE(match(flipped, sedan).score == Approx(1.0).margin(1e-12));
  gm::Params signed_p;
  signed_p.normals = gm::NormalSign::kSigned;
  REQUIRE(match(sedan, sedan, signed_p).score == Approx(1.0).margin(1e-12));
  REQUIRE(match(flipped, sedan, signed_p).score < 0.9);
}

TEST_CASE("B limits the branches recursed on per node", "[gmatch]") {
  // No pruning, no bound: every node has more than B candidates, so the tree is complete
  // B-ary: sum B^d nodes over d < n, B^n leaves.
  gm::Params p;
  p.unary_threshold = p.orientation_threshold = p.distance_threshold = 1e9;
  p.bound = false;
  const auto object = random_graph(31, 4);
  const auto model = random_graph(32, 12);
  for (int b : {1, 2, 3, 5}) {
    p.branches = b;
    gm::SearchStats st;
    match(object, model, p, &st);
    std::int64_t nodes = 0, level = 1;
    for (int d = 0; d < 4; ++d) {
      nodes += level;
      level *= b;
    }
    REQUIRE(st.nodes == nodes);
    REQUIRE(st.leaves == level);
  }
}

TEST_CASE("B = 1 is greedy and misses what B = 2 finds", "[gmatch]") {
  // Object: A (area 4) and B (area 1) one metre apart. Model: A1 at 1 m from B' (slightly
  // worse unary match for A) and A0 far from B' (slightly better unary match for A).
  SegmentGraph object;
  object.segments.push_back(face(0, {0, 0, 1}, {0, 0, 1}, 2.0, 2.0));
  object.segments.push_back(face(1, {1, 0, 1}, {0, 0, 1}, 1.0, 1.0));
  SegmentGraph model;
  model.segments.push_back(face(0, {5, 0, 1}, {0, 0, 1}, 2.0, 2.0));  // A0: exact, far
  model.segments.push_back(face(1, {0, 0, 1}, {0, 0, 1}, 2.0, 1.9));  // A1: close
  model.segments.push_back(face(2, {1, 0, 1}, {0, 0, 1}, 1.0, 1.0));  // B'
  gm::Params p;
  p.branches = 1;
  const auto greedy = match(object, model, p);
  REQUIRE(model_of(greedy, 0) == 0);
  REQUIRE(model_of(greedy, 1) == -1);
  p.branches = 2;
  const auto wider = match(object, model, p);
  REQUIRE(model_of(wider, 0) == 1);
  REQUIRE(model_of(wider, 1) == 2);
  REQUIRE(wider.score > greedy.score);
}

TEST_CASE("X limits the object segments matched to the largest ones", "[gmatch]") {
  const auto g = random_graph(41, 20);
  gm::Params p;
  p.max_segments = 6;
  const auto ms = match(g, g, p);
  REQUIRE(ms.pairs.size() == 6);
  std::vector<const canopy::documents::Segment*> by_area;
  for (const auto& s : g.segments) by_area.push_back(&s);
  std::sort(by_area.begin(), by_area.end(), [](auto* a, auto* b) { return a->area > b->area; });
  for (size_t i = 0; i < 6; ++i) {
    REQUIRE(ms.pairs[i].object_segment == by_area[i]->segment_id);
    REQUIRE(ms.pairs[i].model_segment == by_area[i]->segment_id);
  }
  REQUIRE(ms.score == Approx(1.0).margin(1e-12));
}

TEST_CASE("branch and bound never changes the result; max-nodes stops the search", "[gmatch]") {
  for (std::uint64_t seed = 50; seed < 56; ++seed) {
    const auto model = random_graph(seed, 16);
    const auto object = perturbed(without(model, {1, 4}), seed + 1000, 0.1, 0.02, 0.05, 0.05);
    gm::Params p;
    p.max_segments = 8;
    gm::SearchStats with, plain;
    const auto a = match(object, model, p, &with);
    p.bound = false;
    const auto b = match(object, model, p, &plain);
    require_same(a, b);
    REQUIRE(with.nodes <= plain.nodes);
  }
  gm::Params p;
  p.max_nodes = 5;
  p.bound = false;
  p.unary_threshold = p.orientation_threshold = p.distance_threshold = 1e9;
  gm::SearchStats st;
  const auto g = random_graph(61, 20);
  const auto ms = match(perturbed(g, 3), g, p, &st);
  REQUIRE(st.truncated);
  REQUIRE(st.nodes == 5);
  REQUIRE(ms.pairs.size() == 15);
}

TEST_CASE("the printed total error is gamed by a one-segment match, the bounded one is not", "[gmatch]") {
  const auto sedan = vehicle();
  // The object shows the sedan's roof plus nine segments that match nothing.
  auto object = random_graph(77, 9);
  for (auto& s : object.segments) s.segment_id += 100;
  object.segments.push_back(sedan.segments[2]);
  gm::Params thesis;
  thesis.error = gm::ErrorForm::kThesis;
  const auto printed = match(object, sedan, thesis);
  REQUIRE(printed.score == Approx(1.0));  // C_O = C_D = 0 with one matched pair
  const auto bounded = match(object, sedan);
  double total = 0;
  for (const auto& s : sedan.segments) total += s.area;
  REQUIRE(model_of(bounded, 2) == 2);
  REQUIRE(bounded.score < 0.3);  // the roof is 18% of the sedan's area
}

TEST_CASE("thesis error form reproduces Eq. 6.12 on a hand-computed match", "[gmatch]") {
  // Two pairs, unary errors e1, e2; distance ratio 0.2; orientation 0.25; C_A from areas.
  const double deg = canopy::common::kDegree;
  const auto object = pair_graph(1.0, 60 * deg);
  const auto model = pair_graph(1.25, 37.5 * deg);
  gm::Params thesis;
  thesis.error = gm::ErrorForm::kThesis;
  const auto ms = match(object, model, thesis);
  REQUIRE(model_of(ms, 1) == 1);
  REQUIRE(ms.error_unary == Approx(0.0).margin(1e-12));
  REQUIRE(ms.error_orientation == Approx(2 * 0.25).epsilon(1e-9));
  REQUIRE(ms.error_distance == Approx(2 * 0.2).epsilon(1e-9));
  REQUIRE(ms.error_total == Approx(0.0).margin(1e-12));  // C_U = 0
  REQUIRE(ms.score == Approx(1.0));
}

TEST_CASE("entropy of the scores (Eq. 6.14-6.15)", "[gmatch]") {
  REQUIRE(gm::entropy({0.8, 0, 0, 0, 0}) == Approx(0.0).margin(1e-15));
  REQUIRE(gm::entropy({0.4, 0.4, 0.4, 0.4, 0.4}) == Approx(std::log2(5.0)).epsilon(1e-12));
  REQUIRE(gm::entropy({0.4, 0.4, 0.4, 0.4, 0.4}) == Approx(2.3219).epsilon(1e-4));
  REQUIRE(gm::entropy({0.75, 0.25}) == Approx(0.8112781244591328).epsilon(1e-12));
  REQUIRE(gm::entropy({0, 0, 0}) == Approx(std::log2(3.0)).epsilon(1e-12));
  REQUIRE(gm::entropy({0.6}) == Approx(0.0).margin(1e-15));
}

TEST_CASE("run ranks by score, ties by model name, independent of threads", "[gmatch]") {
  const auto sedan = vehicle();
  const auto object = perturbed(sedan, 12);
  const std::vector<gm::Model> models{{"c_copy", sedan},
                                      {"a_copy", sedan},
                                      {"truck", vehicle(6.5, 2.4, 1.2, 1.6, 1.0, 2.0, 0.5)},
                                      {"blob", random_graph(5, 25)}};
  gm::Params three_threads;
  three_threads.threads = 3;
  const auto one = gm::run(gm::Params{}, {&object, &models});
  const auto three = gm::run(three_threads, {&object, &models});
  REQUIRE(one.result.models[0].model == "a_copy");
  REQUIRE(one.result.models[1].model == "c_copy");
  REQUIRE(one.result.models[0].score == one.result.models[1].score);
  for (size_t i = 0; i < models.size(); ++i) {
    REQUIRE(one.result.models[i].rank == static_cast<int>(i) + 1);
    REQUIRE(one.result.models[i].model == three.result.models[i].model);
    require_same(one.result.models[i], three.result.models[i]);
  }
  REQUIRE(one.result.entropy == three.result.entropy);
  REQUIRE(one.result.error_form == "bounded");
}

TEST_CASE("invalid graphs and parameters are rejected", "[gmatch]") {
  auto g = vehicle();
  g.segments[3].area = 0;
  REQUIRE_THROWS_AS(gm::validate_graph(g, "x.json"), canopy::common::DataError);
  g = vehicle();
  g.segments[4].segment_id = 3;
  REQUIRE_THROWS_WITH(gm::validate_graph(g, "x.json"), Catch::Contains("duplicate"));
  g = vehicle();
  g.segments[0].normal = {0, 0, 0};
  REQUIRE_THROWS_WITH(gm::validate_graph(g, "x.json"), Catch::Contains("x.json"));
  REQUIRE_THROWS_AS(gm::validate_graph(SegmentGraph{}, "e.json"), canopy::common::DataError);
  gm::Params p;
  p.branches = 0;
  REQUIRE_THROWS_AS(gm::validate(p), canopy::common::UsageError);
}
