#include "candtruth/candtruth.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/labels.h"

namespace canopy::candtruth {
namespace {

// The tile's points bucketed on a square grid of the xy plane (cell `cell` m), so that a
// candidate visits the points near its footprint only.
class Grid {
 public:
  Grid(const std::vector<double>& x, const std::vector<double>& y, double cell) : cell_(cell) {
    for (std::size_t i = 0; i < x.size(); ++i) cells_[key(ix(x[i]), ix(y[i]))].push_back(i);
  }
  // Calls f(i) for every point in the cells that the square [cx - r, cx + r] x [cy - r, cy + r] touches.
  template <typename F>
  void near(double cx, double cy, double r, F&& f) const {
    for (std::int64_t j = ix(cy - r); j <= ix(cy + r); ++j)
      for (std::int64_t i = ix(cx - r); i <= ix(cx + r); ++i) {
        const auto it = cells_.find(key(i, j));
        if (it == cells_.end()) continue;
        for (std::size_t q : it->second) f(q);
      }
  }

 private:
  std::int64_t ix(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  static std::uint64_t key(std::int64_t i, std::int64_t j) {
    return (static_cast<std::uint64_t>(i) << 32) ^ (static_cast<std::uint64_t>(j) & 0xffffffffULL);
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

// A field's values as ids: integers in [0, 2^32).
std::vector<std::uint32_t> ids_of(const formats::PointCloud& tile, const std::string& field,
                                  const std::string& name) {
  const std::vector<double>& v = tile.col(field);
  std::vector<std::uint32_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!(v[i] >= 0 && v[i] < 4294967296.0) || v[i] != std::floor(v[i])) {
      throw common::DataError(
          name, "point " + std::to_string(i) + ": field '" + field + "' is not an integer in [0, 2^32)");
    }
    out[i] = static_cast<std::uint32_t>(v[i]);
  }
  return out;
}

}  // namespace

void validate(const Params& params) {
  if (params.margin && !(std::isfinite(*params.margin) && *params.margin >= 0)) {
    throw common::UsageError("--margin must be a finite length >= 0");
  }
  if (params.instance_field.empty()) throw common::UsageError("--instance-field must name a field");
  if (params.label_field.empty()) throw common::UsageError("--label-field must name a field");
}

Outputs run(const Params& params, const Inputs& inputs) {
  const formats::PointCloud& tile = *inputs.tile;
  const documents::Candidates& index = inputs.index;
  tile.require({"x", "y", "z"}, inputs.tile_name);
  if (!tile.has(params.instance_field)) {
    throw common::DataError(inputs.tile_name, "has no '" + params.instance_field +
                                                  "' field: no ground truth to compare the candidates with");
  }
  if (!params.margin && !index.margin) {
    throw common::DataError(inputs.index_name, "gives no crop margin (a version 1 index): give --margin");
  }
  const double margin = params.margin ? *params.margin : *index.margin;
  if (index.tile_points && static_cast<std::size_t>(*index.tile_points) != tile.size()) {
    throw common::DataError(
        inputs.index_name, "was made from a tile of " + std::to_string(*index.tile_points) + " points, not " +
                               inputs.tile_name + " (" + std::to_string(tile.size()) + " points)");
  }

  // A point's vehicle (0 = none) and whether it is ground.
  std::vector<std::uint32_t> vehicle = ids_of(tile, params.instance_field, inputs.tile_name);
  std::vector<bool> ground(tile.size(), false);
  if (tile.has(params.label_field)) {
    const std::vector<std::uint32_t> label = ids_of(tile, params.label_field, inputs.tile_name);
    for (std::size_t i = 0; i < tile.size(); ++i) {
      if (label[i] != formats::kLabelTarget) vehicle[i] = 0;
      ground[i] = label[i] == formats::kLabelGround;
    }
  }
  std::map<std::uint32_t, std::int64_t> tile_points;
  for (std::uint32_t v : vehicle) {
    if (v != 0) ++tile_points[v];
  }

  const std::vector<double>& x = tile.col("x");
  const std::vector<double>& y = tile.col("y");
  const std::vector<double>& z = tile.col("z");
  const Grid grid(x, y, 2.0);

  Outputs out;
  out.tile = inputs.tile_name;
  out.index = inputs.index_name;
  for (const documents::Candidate& c : index.candidates) {
    if (!c.height) throw common::DataError(inputs.index_name, "candidate " + c.id + " has no height");
    const auto& m = c.transform;  // row-major local -> tile, rigid (the reader checks it)
    const double hx = 0.5 * c.length + margin, hy = 0.5 * c.width + margin;
    const double bottom = -margin, top = *c.height + margin;
    // Horizontal reach of the box from its centre: the footprint's half-diagonal plus how far a
    // tilted frame's z axis (the transform's third column: m[2], m[6]) leans out over its height.
    const double reach = std::hypot(hx, hy) + std::hypot(m[2], m[6]) * std::max(-bottom, top);
    std::map<std::uint32_t, std::int64_t> in_crop;
    documents::CandidateTruthRow row;
    row.id = c.id;
    std::int64_t not_ground = 0;
    grid.near(m[3], m[7], reach, [&](std::size_t q) {
      const double dx = x[q] - m[3], dy = y[q] - m[7], dz = z[q] - m[11];
      // R^T (p - t): the frame's axes are the transform's columns.
      const double lx = m[0] * dx + m[4] * dy + m[8] * dz;
      const double ly = m[1] * dx + m[5] * dy + m[9] * dz;
      const double lz = m[2] * dx + m[6] * dy + m[10] * dz;
      if (std::abs(lx) > hx || std::abs(ly) > hy || lz < bottom || lz > top) return;
      ++row.crop_points;
      not_ground += !ground[q];
      if (vehicle[q] != 0) ++in_crop[vehicle[q]];
    });
    for (const auto& [v, n] : in_crop) {
      if (n > row.points) {
        row.instance = v;
        row.points = n;
      }
    }
    if (row.instance != 0) {
      row.coverage = static_cast<double>(row.points) / static_cast<double>(tile_points.at(row.instance));
      row.purity = static_cast<double>(row.points) / static_cast<double>(not_ground);
    }
    out.candidates.push_back(std::move(row));
  }
  for (const auto& [v, n] : tile_points) {
    documents::InstanceTruthRow it;
    it.instance = v;
    it.points = n;
    for (const auto& c : out.candidates) {
      if (c.instance == v) it.candidates.push_back(c.id);
    }
    out.instances.push_back(std::move(it));
  }
  return out;
}

}  // namespace canopy::candtruth
