// Measurements behind docs/decisions/gmatch.md: recognition on synthetic scenes with each
// orientation form, normal-sign convention and total-error form.
#include <cstdio>
#include <string>
#include <vector>

#include "gmatch/gmatch.h"
#include "synth.h"

namespace gm = canopy::gmatch;
using namespace gmatch_bench;

namespace {

std::vector<gm::Model> modelbase() {
  std::vector<gm::Model> models;
  const int sizes[5] = {20, 30, 40, 50, 60};
  for (int k = 0; k < 5; ++k) {
    models.push_back({"model" + std::to_string(k), synthetic_vehicle(100 + k, sizes[k])});
  }
  return models;
}

void row(const char* scenes, const char* config, const std::vector<gm::Model>& models, const SceneSpec& spec,
         const gm::Params& p, int per_model = 10) {
  int n = 0, correct = 0;
  double true_score = 0, best_wrong = 0, entropy = 0;
  for (size_t k = 0; k < models.size(); ++k) {
    for (int i = 0; i < per_model; ++i) {
      const auto scene = synthetic_scene(models[k].graph, 5000 + 100 * k + i, spec);
      const auto out = gm::run(p, {&scene, &models}).result;
      ++n;
      double wrong = 0;
      for (const auto& m : out.models) {
        if (m.model == models[k].name) {
          true_score += m.score;
          if (m.rank == 1) ++correct;
        } else {
          wrong = std::max(wrong, m.score);
        }
      }
      best_wrong += wrong;
      entropy += out.entropy;
    }
  }
  std::printf("%-34s %-30s %6.0f%% %8.3f %8.3f %8.3f\n", scenes, config, 100.0 * correct / n, true_score / n,
              best_wrong / n, entropy / n);
}

gm::Params with(gm::OrientationForm o, gm::NormalSign s, gm::ErrorForm e) {
  gm::Params p;
  p.orientation = o;
  p.normals = s;
  p.error = e;
  return p;
}

}  // namespace

int main() {
  const auto models = modelbase();
  using O = gm::OrientationForm;
  using N = gm::NormalSign;
  using E = gm::ErrorForm;
  std::printf(
      "5 synthetic models (20-60 segments), 10 scenes each: 20%% occlusion, 2 splits, "
      "5 clutter segments, noise\n");
  std::printf("%-34s %-30s %7s %8s %8s %8s\n", "scenes", "configuration", "rank-1", "S true", "S wrong",
              "H bits");
  SceneSpec aligned;
  aligned.random_heading = false;
  SceneSpec rotated;
  SceneSpec flipped;
  flipped.flip = 0.2;
  SceneSpec clean;
  clean.drop = 0;
  clean.clutter = 0;
  clean.splits = 0;

  // (1) orientation form: heading dependence.
  for (const auto* sc : {&aligned, &rotated}) {
    const char* name = sc == &aligned ? "heading as model" : "random heading";
    row(name, "orientation relative", models, *sc, with(O::kRelative, N::kAxial, E::kBounded));
    row(name, "orientation thesis", models, *sc, with(O::kThesis, N::kAxial, E::kBounded));
  }
  // (2) normal signs: 20% of the scene's normals flipped (thin parts, inconsistent orientation).
  for (const auto* sc : {&rotated, &flipped}) {
    const char* name = sc == &rotated ? "random heading" : "random heading, 20% flipped";
    row(name, "normals axial", models, *sc, with(O::kRelative, N::kAxial, E::kBounded));
    row(name, "normals signed", models, *sc, with(O::kRelative, N::kSigned, E::kBounded));
  }
  // (3) total error form.
  for (const auto* sc : {&clean, &aligned, &rotated}) {
    const char* name = sc == &clean     ? "noise only, heading as model"
                       : sc == &aligned ? "heading as model"
                                        : "random heading";
    row(name, "error bounded", models, *sc, with(O::kRelative, N::kAxial, E::kBounded));
    row(name, "error thesis", models, *sc, with(O::kRelative, N::kAxial, E::kThesis));
    row(name, "error thesis, orientation thesis", models, *sc, with(O::kThesis, N::kAxial, E::kThesis));
  }
  // (4) one-segment gaming: the object is one model segment plus clutter.
  std::printf("\none model segment (the largest) + 9 clutter segments, matched to its model:\n");
  for (auto e : {E::kBounded, E::kThesis}) {
    double s = 0;
    for (const auto& m : models) {
      auto obj = random_graph(999, 9);
      for (auto& seg : obj.segments) seg.segment_id += 1000;
      const gm::Model& model = m;
      const auto* largest = &model.graph.segments[0];
      for (const auto& seg : model.graph.segments) {
        if (seg.area > largest->area) largest = &seg;
      }
      obj.segments.push_back(*largest);
      s += gm::match_model(obj, model, with(O::kRelative, N::kAxial, e)).score;
    }
    std::printf("  error %-8s mean score %.3f\n", gm::to_string(e), s / models.size());
  }
  return 0;
}
