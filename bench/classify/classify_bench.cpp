// classify benchmark: wall time of classify::run per candidate (the reading of the file is not
// timed) on synthetic car candidates (a 4.6 x 1.8 m car with its roof plateau and 0.5 m of
// ground around it, sampled uniformly from above) at 10, 25, 100, 400 and 1000 points/m², and
// on any candidate PCDs given.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "canopy/common/rng.h"
#include "canopy/formats/points_io.h"
#include "classify/classify.h"

using namespace canopy;

namespace {

double car_top(double x, double y) {
  if (std::abs(x) > 2.3 || std::abs(y) > 0.9) return -1;
  if (std::abs(y) < 0.7 && x >= -1.1 && x <= 0.9) return 1.45;
  return 0.95;
}

formats::PointCloud car(double density, std::uint64_t seed) {
  common::Rng rng(seed);
  const double mx = 2.8, my = 1.4;
  const auto n = static_cast<std::size_t>(density * 4 * mx * my);
  formats::PointCloud c;
  c.resize(n);
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = rng.uniform(-mx, mx);
    y[i] = rng.uniform(-my, my);
    const double h = car_top(x[i], y[i]);
    z[i] = (h > 0 ? h : 0) + 0.01 * rng.normal();
  }
  return c;
}

double seconds_per_run(const formats::PointCloud& cloud, int repeats, std::string* answer) {
  const classify::Params p;
  const auto t0 = std::chrono::steady_clock::now();
  classify::Answer a;
  for (int r = 0; r < repeats; ++r) a = classify::run(p, {cloud, "bench", {}});
  const auto t1 = std::chrono::steady_clock::now();
  *answer = a.cls.empty() ? a.reason : a.cls;
  return std::chrono::duration<double>(t1 - t0).count() / repeats;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  std::printf("%-28s %10s %12s  %s\n", "candidate", "points", "ms / run", "answer");
  for (double density : {10.0, 25.0, 100.0, 400.0, 1000.0}) {
    const formats::PointCloud c = car(density, 7);
    std::string answer;
    const double s = seconds_per_run(c, repeats, &answer);
    char name[64];
    std::snprintf(name, sizeof name, "synthetic car %.0f pts/m2", density);
    std::printf("%-28s %10zu %12.3f  %s\n", name, c.size(), 1e3 * s, answer.c_str());
  }
  for (int i = 2; i < argc; ++i) {
    const formats::PointCloud c = formats::read_points(argv[i], "classify_bench");
    std::string answer;
    const double s = seconds_per_run(c, repeats, &answer);
    std::printf("%-28s %10zu %12.3f  %s\n", argv[i], c.size(), 1e3 * s, answer.c_str());
  }
  return 0;
}
