#include "detect/truth.h"

#include <cstdint>
#include <map>
#include <utility>

#include "canopy/formats/labels.h"

namespace canopy::detect {
namespace {

// Ground truth of the tile: a point's vehicle instance (0 = none: no instance field, or a
// label field that says not a vehicle) and every vehicle's number of points.
struct TileTruth {
  const formats::PointCloud& tile;
  const Params& params;
  bool has_instance = false, has_label = false;
  std::map<std::uint32_t, std::size_t> instance_points;

  TileTruth(const formats::PointCloud& t, const Params& p)
      : tile(t), params(p), has_instance(t.has(p.instance_field)), has_label(t.has(p.label_field)) {
    if (!has_instance) return;
    for (std::size_t i = 0; i < tile.size(); ++i) {
      if (const std::uint32_t id = (*this)(i)) ++instance_points[id];
    }
  }
  std::uint32_t operator()(std::size_t i) const {
    if (!has_instance) return 0;
    if (has_label && std::uint32_t(tile.col(params.label_field)[i]) != formats::kLabelTarget) return 0;
    return std::uint32_t(tile.col(params.instance_field)[i]);
  }
};

// The candidate's truth: the vehicle with the most points in the object (not merely in the
// crop around it), its points in the crop (`rows`), coverage and purity.
Truth candidate_truth(const TileTruth& truth, const Object& o, const std::vector<std::size_t>& rows) {
  Truth t;
  std::map<std::uint32_t, std::size_t> in_object;
  for (std::uint32_t q : o.points) {
    if (const std::uint32_t id = truth(q)) ++in_object[id];
  }
  std::size_t best = 0;
  for (const auto& [id, cnt] : in_object) {
    if (cnt > best) {
      best = cnt;
      t.instance = id;
    }
  }
  if (t.instance != 0) {
    for (std::size_t q : rows) t.points += truth(q) == t.instance;
    t.coverage = double(t.points) / double(truth.instance_points.at(t.instance));
    t.purity = double(best) / double(o.points.size());
  }
  return t;
}

// Every labelled vehicle of the tile with the candidates whose truth it is.
std::vector<InstanceTruth> instances_of(const TileTruth& truth, const std::vector<Candidate>& candidates,
                                        const std::vector<Truth>& truths) {
  std::vector<InstanceTruth> out;
  for (const auto& [id, cnt] : truth.instance_points) {
    InstanceTruth it;
    it.instance = id;
    it.points = cnt;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (truths[k].instance == id) it.candidates.push_back(candidates[k].id);
    }
    out.push_back(std::move(it));
  }
  return out;
}

}  // namespace

TileTruthStats truth_of(const formats::PointCloud& tile, const Params& params,
                        const std::vector<Object>& objects, const Placed& placed) {
  TileTruthStats out;
  const TileTruth truth(tile, params);
  out.has_truth = truth.has_instance;
  if (!truth.has_instance) return out;
  for (std::size_t k = 0; k < placed.candidates.size(); ++k) {
    out.candidates.push_back(candidate_truth(truth, objects[placed.object[k]], placed.rows[k]));
  }
  out.instances = instances_of(truth, placed.candidates, out.candidates);
  return out;
}

}  // namespace canopy::detect
