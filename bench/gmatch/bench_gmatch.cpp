// Time to match one scene against the modelbase, and how it grows with the number of models,
// X and B. Synthetic vehicle-like graphs of 20-60 segments (bench/gmatch/synth.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "gmatch/gmatch.h"
#include "synth.h"

namespace gm = canopy::gmatch;
using namespace gmatch_bench;

namespace {

struct Setup {
  std::vector<gm::Model> base;
  std::vector<std::pair<int, SegmentGraph>> scenes;  // (true model index, scene)
};

Setup make_setup(int scenes_per_model) {
  Setup s;
  const int sizes[5] = {20, 30, 40, 50, 60};
  for (int k = 0; k < 5; ++k) {
    s.base.push_back({"model" + std::to_string(k), synthetic_vehicle(100 + k, sizes[k])});
  }
  for (int k = 0; k < 5; ++k) {
    for (int i = 0; i < scenes_per_model; ++i) {
      s.scenes.emplace_back(k, synthetic_scene(s.base[k].graph, 1000 * k + i));
    }
  }
  return s;
}

void measure(const char* label, const Setup& s, const std::vector<gm::Model>& models, const gm::Params& p) {
  double total = 0, worst = 0;
  std::int64_t nodes = 0, truncated = 0;
  int correct = 0;
  for (const auto& [truth, scene] : s.scenes) {
    // Best of three runs: the machine is shared, the minimum is the least disturbed.
    double ms = 1e300;
    gm::Outputs out;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      out = gm::run(p, {&scene, &models});
      ms = std::min(ms,
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    total += ms;
    worst = std::max(worst, ms);
    for (const auto& st : out.stats) {
      nodes += st.nodes;
      truncated += st.truncated;
    }
    if (out.result.models.front().model.rfind(s.base[truth].name, 0) == 0) ++correct;
  }
  const double n = static_cast<double>(s.scenes.size());
  std::printf("%-28s %4zu %3d %3d %10.2f %10.2f %12.0f %6lld %6.0f%%\n", label, models.size(), p.max_segments,
              p.branches, total / n, worst, nodes / (n * static_cast<double>(models.size())),
              static_cast<long long>(truncated), 100.0 * correct / n);
}

}  // namespace

int main() {
  const Setup s = make_setup(4);
  std::printf(
      "%zu scenes, best of 3 runs each (4 per model; models of 20/30/40/50/60 segments; occlusion "
      "20%%, 2 "
      "splits, 5 clutter segments, noise, random heading), 1 thread\n",
      s.scenes.size());
  std::printf("%-28s %4s %3s %3s %10s %10s %12s %6s %7s\n", "case", "M", "X", "B", "ms/scene", "max ms",
              "nodes/match", "trunc", "rank-1");
  gm::Params p;
  for (int m : {1, 5, 10, 20, 40}) {
    std::vector<gm::Model> models;
    for (int i = 0; i < m; ++i) {
      models.push_back(s.base[i % 5]);
      models.back().name += "_" + std::to_string(i);
    }
    // rank-1 is only meaningful for M = 5 (copies carry suffixed names)
    measure("models", s, models, p);
  }
  for (int x : {5, 10, 15, 20, 25}) {
    gm::Params q = p;
    q.max_segments = x;
    measure("X", s, s.base, q);
  }
  for (int b : {1, 2, 3, 5, 8}) {
    gm::Params q = p;
    q.branches = b;
    measure("B", s, s.base, q);
  }
  {
    gm::Params q = p;
    q.bound = false;
    q.max_nodes = 2000000;
    measure("no bound (max 2e6 nodes)", s, s.base, q);
    q.max_segments = 10;
    measure("no bound, X=10", s, s.base, q);
  }
  {
    gm::Params q = p;
    q.error = gm::ErrorForm::kThesis;
    measure("error thesis", s, s.base, q);
  }
  return 0;
}
