#include "detect/plan.h"

#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include <Eigen/Core>

namespace canopy::detect {

std::uint64_t column_key(double x, double y, double v) {
  const auto i = std::int64_t(std::floor(x / v)) + (std::int64_t(1) << 30);
  const auto j = std::int64_t(std::floor(y / v)) + (std::int64_t(1) << 30);
  return (std::uint64_t(i) << 32) | std::uint64_t(j);
}

bool touch_in_plan(const std::vector<double>& x, const std::vector<double>& y,
                   const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b, double reach) {
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
  for (std::uint32_t q : b) cells[column_key(x[q], y[q], reach)].push_back(q);
  for (std::uint32_t q : a)
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const auto it = cells.find(column_key(x[q] + di * reach, y[q] + dj * reach, reach));
        if (it == cells.end()) continue;
        for (std::uint32_t r : it->second)
          if (std::hypot(x[q] - x[r], y[q] - y[r]) <= reach) return true;
      }
  return false;
}

bool over_in_plan(const std::vector<double>& x, const std::vector<double>& y,
                  const std::vector<std::uint32_t>& own, const std::vector<std::uint32_t>& other, double cell) {
  std::unordered_set<std::uint64_t> own_cells, other_cells;
  for (std::uint32_t q : own) own_cells.insert(column_key(x[q], y[q], cell));
  for (std::uint32_t q : other) other_cells.insert(column_key(x[q], y[q], cell));
  std::size_t shared = 0;
  for (std::uint64_t k : own_cells) shared += other_cells.count(k);
  return double(shared) > kStackOverlay * double(own_cells.size());
}

Footprint plan_footprint(const std::vector<double>& x, const std::vector<double>& y,
                         const std::vector<std::uint32_t>& pts) {
  std::vector<Eigen::Vector2d> xy(pts.size());
  for (std::size_t n = 0; n < pts.size(); ++n) xy[n] = Eigen::Vector2d(x[pts[n]], y[pts[n]]);
  return min_area_rectangle(xy);
}

}  // namespace canopy::detect
