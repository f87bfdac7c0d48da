// The prefilter (docs/decisions/gmatch.md §9): rank every model cheaply (a coarse search on the
// object's few largest segments, or graph summaries) and keep the K best; the full search then
// runs on those K only.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "canopy/common/parallel.h"
#include "gmatch/gmatch.h"

namespace canopy::gmatch {
namespace {

// Spreads below this (a flat or one-segment graph) are all alike: log ratios stay bounded.
constexpr double kSpreadFloor = 0.05;  // m
// Tilt bins by |n_z|: sides (within ~22 deg of vertical faces), slopes, roofs (within ~23 deg
// of horizontal).
constexpr double kSideMax = 0.38, kSlopeMax = 0.92;

}  // namespace

Summary summarize(const documents::SegmentGraph& graph, int max_segments) {
  // The X largest segments, as the search takes them (area, then id).
  std::vector<const documents::Segment*> seg;
  seg.reserve(graph.segments.size());
  for (const auto& s : graph.segments) seg.push_back(&s);
  const auto by_area = [](const documents::Segment* a, const documents::Segment* b) {
    if (a->area != b->area) return a->area > b->area;
    return a->segment_id < b->segment_id;
  };
  const std::size_t x = std::min<std::size_t>(seg.size(), std::max(0, max_segments));
  std::partial_sort(seg.begin(), seg.begin() + static_cast<std::ptrdiff_t>(x), seg.end(), by_area);
  seg.resize(x);

  Summary out;
  out.segments = static_cast<int>(x);
  for (const auto* s : seg) out.area += s->area;
  if (!(out.area > 0)) return out;
  double mx = 0, my = 0, mz = 0;
  for (const auto* s : seg) {
    const double w = s->area / out.area;
    mx += w * s->centroid[0];
    my += w * s->centroid[1];
    mz += w * s->centroid[2];
  }
  double cxx = 0, cxy = 0, cyy = 0, czz = 0;
  for (const auto* s : seg) {
    const double w = s->area / out.area;
    const double dx = s->centroid[0] - mx, dy = s->centroid[1] - my, dz = s->centroid[2] - mz;
    cxx += w * dx * dx;
    cxy += w * dx * dy;
    cyy += w * dy * dy;
    czz += w * dz * dz;
    const double n =
        std::sqrt(s->normal[0] * s->normal[0] + s->normal[1] * s->normal[1] + s->normal[2] * s->normal[2]);
    const double nz = n > 0 ? std::fabs(s->normal[2]) / n : 0;
    out.tilt[nz < kSideMax ? 0 : nz < kSlopeMax ? 1 : 2] += w;
  }
  // Eigenvalues of the horizontal 2x2 covariance: invariant to the heading.
  const double half_trace = 0.5 * (cxx + cyy);
  const double root = std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
  out.spread = {std::sqrt(std::max(0.0, half_trace + root)), std::sqrt(std::max(0.0, half_trace - root)),
                std::sqrt(std::max(0.0, czz))};
  return out;
}

double summary_distance(const Summary& a, const Summary& b) {
  const auto log_ratio = [](double u, double v, double floor) {
    return std::fabs(std::log(std::max(u, floor) / std::max(v, floor)));
  };
  double d = log_ratio(a.area, b.area, 1e-6);
  for (int i = 0; i < 3; ++i) d += log_ratio(a.spread[i], b.spread[i], kSpreadFloor);
  for (int i = 0; i < 3; ++i) d += std::fabs(a.tilt[i] - b.tilt[i]);
  return d;
}

std::vector<int> prefilter(const documents::SegmentGraph& object, const std::vector<Model>& models,
                           const Params& params) {
  const int n = static_cast<int>(models.size());
  const int k = params.prefilter;
  std::vector<int> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  if (k <= 0 || k >= n) return idx;
  // (merit, index): larger merit first, then smaller index.
  std::vector<std::pair<double, int>> merit(n);
  if (params.prefilter_by == PrefilterBy::kSummary) {
    const Summary o = summarize(object, params.max_segments);
    for (int i = 0; i < n; ++i) {
      merit[i] = {-summary_distance(o, summarize(models[i].graph, params.max_segments)), i};
    }
  } else {
    Params coarse = params;
    coarse.max_segments = std::min(params.coarse_segments, params.max_segments);
    coarse.prefilter = 0;
    common::parallel_for(n, params.threads, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        merit[i] = {match_model(object, models[i], coarse).score, static_cast<int>(i)};
      }
    });
  }
  const auto better = [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
    if (a.first != b.first) return a.first > b.first;
    return a.second < b.second;
  };
  std::nth_element(merit.begin(), merit.begin() + k, merit.end(), better);
  idx.resize(k);
  for (int i = 0; i < k; ++i) idx[i] = merit[i].second;
  std::sort(idx.begin(), idx.end());
  return idx;
}

}  // namespace canopy::gmatch
