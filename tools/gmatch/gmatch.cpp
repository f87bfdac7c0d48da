#include "gmatch/gmatch.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/parallel.h"

namespace canopy::gmatch {
namespace {

std::string fmt3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4f", v);
  return b;
}

using documents::Segment;
using documents::SegmentGraph;
using documents::Vec3;

constexpr double kTwoOverPi = 2.0 / common::kPi;
// Scores closer than this are ties (broken by segment id / search order): keeps the result
// independent of rounding noise, e.g. after rotating the object.
constexpr double kTieQuantum = 1e-10;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
double distance(const Vec3& a, const Vec3& b) {
  const Vec3 d{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return norm(d);
}

Vec3 unit(const Vec3& a) {
  const double n = norm(a);
  return {a[0] / n, a[1] / n, a[2] / n};
}

// Angle between two unit normals: [0, pi] signed, [0, pi/2] axial.
double normal_angle(const Vec3& a, const Vec3& b, NormalSign sign) {
  double c = dot(a, b);
  if (sign == NormalSign::kAxial) c = std::fabs(c);
  return std::acos(std::clamp(c, -1.0, 1.0));
}

// Eq. 6.9.
double relative_difference(double a, double b) {
  const double m = std::max(a, b);
  return m > 0 ? std::fabs(a - b) / m : 0.0;
}

// x^e, exact for the common e = 1.
double power(double x, double e) {
  if (e == 1.0) return x;
  if (e == 0.0) return 1.0;
  return std::pow(x, e);
}

// Clamped so that extreme printed-form errors (large exponents) cannot overflow int64.
std::int64_t quantize(double merit) { return std::llround(std::clamp(merit, -1e8, 1e8) / kTieQuantum); }

// Eq. 6.1, 6.3-6.6.
double unary_error(const Segment& s, const Segment& m, const Params& p) {
  const double ratio = std::min(s.area, m.area) / std::max(s.area, m.area);
  const double da = -std::log(ratio) / std::log1p(p.area_factor);
  const double dt = p.thickness_weight * std::fabs(s.thickness - m.thickness);
  const double de_arg = 1.0 - std::fabs(s.elongation - m.elongation);
  const double de =
      de_arg > 0 ? -p.elongation_weight * std::log(de_arg) : std::numeric_limits<double>::infinity();
  const double du2 = da * da + dt * dt + de * de;
  return 1.0 - std::exp(-du2);
}

// The pairwise tables of one side (object or model), n x n row-major: the angle between the
// unit normals of segments a and b, and the distance between their centroids.
void pair_tables(const std::vector<const Segment*>& segments, const std::vector<Vec3>& normals,
                 NormalSign sign, std::vector<double>* angle, std::vector<double>* dist) {
  const int n = static_cast<int>(segments.size());
  angle->assign(static_cast<size_t>(n) * n, 0);
  dist->assign(static_cast<size_t>(n) * n, 0);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      (*angle)[a * n + b] = normal_angle(normals[a], normals[b], sign);
      (*dist)[a * n + b] = distance(segments[a]->centroid, segments[b]->centroid);
    }
  }
}

struct Child {
  int model = -1;                          // model segment index, -1 = NULL
  double unary = 0, sum_o = 0, sum_d = 0;  // this pair's E_U and its pairwise sums
  double merit = 0;                        // larger is better
  std::int64_t key = 0;                    // quantized merit
};

// One object-to-model search (thesis §6.2): depth-first over the object's segments in area
// order, each level assigning a model segment or NULL, recursing on the B best children.
class Matcher {
 public:
  Matcher(const SegmentGraph& object, const SegmentGraph& model, const Params& p) : p_(p) {
    // Object segments by area (largest first), ties by id; at most X.
    std::vector<const Segment*> obj;
    for (const auto& s : object.segments) obj.push_back(&s);
    std::sort(obj.begin(), obj.end(), [](const Segment* a, const Segment* b) {
      if (a->area != b->area) return a->area > b->area;
      return a->segment_id < b->segment_id;
    });
    if (static_cast<int>(obj.size()) > p.max_segments) obj.resize(p.max_segments);
    obj_ = obj;
    // Model segments by id: the tie-break order of branches.
    for (const auto& s : model.segments) mod_.push_back(&s);
    std::sort(mod_.begin(), mod_.end(),
              [](const Segment* a, const Segment* b) { return a->segment_id < b->segment_id; });
    x_ = static_cast<int>(obj_.size());
    m_ = static_cast<int>(mod_.size());

    std::vector<Vec3> on(x_), mn(m_);
    for (int k = 0; k < x_; ++k) on[k] = unit(obj_[k]->normal);
    for (int j = 0; j < m_; ++j) mn[j] = unit(mod_[j]->normal);

    unary_.assign(static_cast<size_t>(x_) * m_, 0);
    alpha_.assign(static_cast<size_t>(x_) * m_, 0);
    for (int k = 0; k < x_; ++k) {
      for (int j = 0; j < m_; ++j) {
        unary_[k * m_ + j] = unary_error(*obj_[k], *mod_[j], p);
        alpha_[k * m_ + j] = normal_angle(on[k], mn[j], p.normals);
      }
    }
    pair_tables(obj_, on, p.normals, &ang_s_, &dist_s_);
    pair_tables(mod_, mn, p.normals, &ang_m_, &dist_m_);
    // Coverage references: all model area (thesis C_A) and the area of the model's X
    // largest segments (bounded form: a self-match covers it exactly).
    by_area_.resize(m_);
    std::iota(by_area_.begin(), by_area_.end(), 0);
    std::stable_sort(by_area_.begin(), by_area_.end(),
                     [&](int a, int b) { return mod_[a]->area > mod_[b]->area; });
    for (int j = 0; j < m_; ++j) area_total_ += mod_[j]->area;
    for (int i = 0; i < std::min(m_, p.max_segments); ++i) area_ref_ += mod_[by_area_[i]]->area;
    // Object side (coverage both): the area of the X object segments considered, and the
    // suffix sums that bound what the remaining levels can still add.
    obj_rest_.assign(x_ + 1, 0);
    for (int k = x_ - 1; k >= 0; --k) obj_rest_[k] = obj_rest_[k + 1] + obj_[k]->area;
    obj_ref_ = obj_rest_[0];

    used_.assign(m_, 0);
    assign_.assign(x_, -1);
    children_.resize(x_);
    for (auto& c : children_) c.reserve(m_ + 1);
  }

  documents::ModelScore solve(SearchStats* stats) {
    // The all-NULL match is the fallback when no leaf is reached (max_nodes); it is not a
    // starting incumbent because the printed thesis form would score it perfectly.
    best_assign_.assign(x_, -1);
    best_key_ = std::numeric_limits<std::int64_t>::min();
    if (x_ > 0) {
      top_key_ = p_.error == ErrorForm::kBounded ? quantize(1.0) : quantize(0.0);
      descend(0, 0, 0, 0, 0, 0, 0);
    }
    if (stats) {
      stats->nodes = nodes_;
      stats->leaves = leaves_;
      stats->truncated = truncated_;
    }
    return report();
  }

 private:
  double eo_pair(int k, int j, int k2, int j2) const {
    if (p_.orientation == OrientationForm::kRelative) {
      return kTwoOverPi * std::fabs(ang_s_[k * x_ + k2] - ang_m_[j * m_ + j2]);
    }
    return kTwoOverPi * std::fabs(alpha_[k * m_ + j] - alpha_[k2 * m_ + j2]);
  }
  double ed_pair(int k, int j, int k2, int j2) const {
    return relative_difference(dist_s_[k * x_ + k2], dist_m_[j * m_ + j2]);
  }
  // In the bounded form each pairwise term enters its mean clipped to [0, 1].
  double clip(double e) const { return p_.error == ErrorForm::kBounded ? std::min(1.0, e) : e; }

  // Merit of a (partial) match: the score S (bounded) or -E (thesis); larger is better.
  // depth = object segments assigned so far (x of Eq. 6.12), nm = non-NULL pairs among them.
  // area = matched model area, area_o = matched object area.
  double merit(double sum_u, double sum_o, double sum_d, int nm, int depth, double area, double area_o) const {
    if (p_.error == ErrorForm::kBounded) {
      const double pairs = 0.5 * nm * (nm - 1);
      const double eu = nm > 0 ? sum_u / nm : 0;
      const double eo = pairs > 0 ? sum_o / pairs : 0;
      const double ed = pairs > 0 ? sum_d / pairs : 0;
      const double cov = coverage(area, area_o);
      return power(1 - eu, p_.exp_unary) * power(1 - eo, p_.exp_orientation) *
             power(1 - ed, p_.exp_distance) * power(cov, p_.exp_area);
    }
    return -thesis_error(sum_u, sum_o, sum_d, depth, area);
  }

  // Eq. 6.12 with Eq. 6.2, 6.8, 6.10 (double sums over ordered pairs) and Eq. 6.11 on model
  // areas (a NULL match contributes model area 0).
  double thesis_error(double sum_u, double sum_o, double sum_d, int depth, double area) const {
    if (depth == 0) return 0;
    const double ca = std::min(1.0, std::fabs(1.0 - area / area_total_));
    return power(sum_u, p_.exp_unary) * power(2 * sum_o, p_.exp_orientation) *
           power(2 * sum_d, p_.exp_distance) * power(ca, p_.exp_area) / depth;
  }

  // Bounded-form coverage: the model side (matched model area over the model's X largest
  // segments) and, with Coverage::kBoth, the geometric mean with the object side (matched
  // object area over the X object segments considered): a small model covering part of a big
  // object is then short of object area.
  double coverage(double area, double area_o) const {
    const double cm = area_ref_ > 0 ? std::min(1.0, area / area_ref_) : 0;
    if (p_.coverage == Coverage::kModel) return cm;
    const double co = obj_ref_ > 0 ? std::min(1.0, area_o / obj_ref_) : 0;
    return std::sqrt(cm * co);
  }

  // Upper bound of the score of any completion of a partial match (bounded form): future
  // pairs only add non-negative error terms, and at most `remaining` more model segments,
  // at best the largest unused ones, can be covered.
  double upper_bound(double sum_u, double sum_o, double sum_d, int nm, int remaining, double area,
                     double area_o) const {
    const int n = nm + remaining;
    const double pairs = 0.5 * n * (n - 1);
    const double eu = n > 0 ? sum_u / n : 0;
    const double eo = pairs > 0 ? sum_o / pairs : 0;
    const double ed = pairs > 0 ? sum_d / pairs : 0;
    double extra = 0;
    int taken = 0;
    for (int i = 0; i < m_ && taken < remaining; ++i) {
      if (!used_[by_area_[i]]) {
        extra += mod_[by_area_[i]]->area;
        ++taken;
      }
    }
    // The remaining object levels are the last `remaining` object segments.
    const double cov = coverage(area + extra, area_o + obj_rest_[x_ - remaining]);
    return power(1 - eu, p_.exp_unary) * power(1 - eo, p_.exp_orientation) * power(1 - ed, p_.exp_distance) *
           power(cov, p_.exp_area);
  }

  void descend(int depth, double sum_u, double sum_o, double sum_d, int nm, double area, double area_o) {
    if (best_key_ >= top_key_) return;  // nothing can beat a perfect match
    if (depth == x_) {
      ++leaves_;
      const std::int64_t key = quantize(merit(sum_u, sum_o, sum_d, nm, depth, area, area_o));
      if (key > best_key_) {
        best_key_ = key;
        best_assign_ = assign_;
      }
      return;
    }
    if (p_.max_nodes > 0 && nodes_ >= p_.max_nodes) {
      truncated_ = true;
      return;
    }
    ++nodes_;

    // Evaluate every child: each unused model segment that survives pruning, and NULL.
    auto& kids = children_[depth];
    kids.clear();
    const int k = depth;
    for (int j = 0; j < m_; ++j) {
      if (used_[j]) continue;
      const double eu = unary_[k * m_ + j];
      if (eu > p_.unary_threshold) continue;
      double so = 0, sd = 0;
      bool ok = true;
      for (int i = 0; i < nm && ok; ++i) {
        const int k2 = matched_k_[i], j2 = assign_[k2];
        const double eo = eo_pair(k, j, k2, j2);
        const double ed = ed_pair(k, j, k2, j2);
        if (eo > p_.orientation_threshold || ed > p_.distance_threshold) ok = false;
        so += clip(eo);
        sd += clip(ed);
      }
      if (!ok) continue;
      Child c;
      c.model = j;
      c.unary = eu;
      c.sum_o = so;
      c.sum_d = sd;
      c.merit = merit(sum_u + eu, sum_o + so, sum_d + sd, nm + 1, depth + 1, area + mod_[j]->area,
                      area_o + obj_[k]->area);
      c.key = quantize(c.merit);
      kids.push_back(c);
    }
    Child null_child;
    null_child.merit = merit(sum_u, sum_o, sum_d, nm, depth + 1, area, area_o);
    null_child.key = quantize(null_child.merit);
    kids.push_back(null_child);
    // Best first; ties by model segment id, NULL last among equals.
    std::stable_sort(kids.begin(), kids.end(), [](const Child& a, const Child& b) {
      if (a.key != b.key) return a.key > b.key;
      if ((a.model < 0) != (b.model < 0)) return b.model < 0;
      return a.model < b.model;
    });
    if (static_cast<int>(kids.size()) > p_.branches) kids.resize(p_.branches);

    const int remaining = x_ - depth - 1;
    // Iterate over a copy index: deeper levels use their own child buffers.
    for (size_t c = 0; c < kids.size(); ++c) {
      const Child kid = kids[c];
      const bool real = kid.model >= 0;
      const double su = sum_u + kid.unary, so = sum_o + kid.sum_o, sd = sum_d + kid.sum_d;
      const int nm2 = nm + (real ? 1 : 0);
      const double area2 = area + (real ? mod_[kid.model]->area : 0);
      const double area_o2 = area_o + (real ? obj_[k]->area : 0);
      if (real) used_[kid.model] = 1;
      bool skip = false;
      if (p_.bound && p_.error == ErrorForm::kBounded) {
        const double ub = upper_bound(su, so, sd, nm2, remaining, area2, area_o2);
        skip = quantize(ub) <= best_key_;
      }
      if (!skip) {
        assign_[k] = kid.model;
        if (real) matched_k_.push_back(k);
        descend(depth + 1, su, so, sd, nm2, area2, area_o2);
        if (real) matched_k_.pop_back();
        assign_[k] = -1;
      }
      if (real) used_[kid.model] = 0;
      if (best_key_ >= top_key_ || truncated_) return;
    }
  }

  documents::ModelScore report() const {
    documents::ModelScore ms;
    double sum_u = 0, sum_o = 0, sum_d = 0, area = 0, area_o = 0;
    int nm = 0;
    for (int k = 0; k < x_; ++k) {
      documents::SegmentPair pair;
      pair.object_segment = obj_[k]->segment_id;
      const int j = best_assign_[k];
      if (j >= 0) {
        pair.model_segment = mod_[j]->segment_id;
        pair.unary_error = unary_[k * m_ + j];
        sum_u += pair.unary_error;
        area += mod_[j]->area;
        area_o += obj_[k]->area;
        for (int k2 = 0; k2 < k; ++k2) {
          const int j2 = best_assign_[k2];
          if (j2 < 0) continue;
          sum_o += clip(eo_pair(k, j, k2, j2));
          sum_d += clip(ed_pair(k, j, k2, j2));
        }
        ++nm;
      }
      ms.pairs.push_back(pair);
    }
    if (p_.error == ErrorForm::kBounded) {
      const double pairs = 0.5 * nm * (nm - 1);
      ms.error_unary = nm > 0 ? sum_u / nm : 0;
      ms.error_orientation = pairs > 0 ? sum_o / pairs : 0;
      ms.error_distance = pairs > 0 ? sum_d / pairs : 0;
      ms.error_coverage = 1 - coverage(area, area_o);
      ms.score = merit(sum_u, sum_o, sum_d, nm, x_, area, area_o);
      ms.error_total = 1 - ms.score;
    } else {
      ms.error_unary = sum_u;
      ms.error_orientation = 2 * sum_o;
      ms.error_distance = 2 * sum_d;
      ms.error_coverage = std::min(1.0, std::fabs(1.0 - area / area_total_));
      ms.error_total = thesis_error(sum_u, sum_o, sum_d, x_, area);
      ms.score = std::clamp(1 - ms.error_total, 0.0, 1.0);
    }
    return ms;
  }

  const Params& p_;
  std::vector<const Segment*> obj_, mod_;
  int x_ = 0, m_ = 0;
  std::vector<double> unary_, alpha_, ang_s_, dist_s_, ang_m_, dist_m_;
  std::vector<int> by_area_;
  double area_total_ = 0, area_ref_ = 0, obj_ref_ = 0;
  std::vector<double> obj_rest_;  // obj_rest_[k] = area of object segments k..x_-1

  std::vector<char> used_;
  std::vector<int> assign_, matched_k_, best_assign_;
  std::vector<std::vector<Child>> children_;
  std::int64_t best_key_ = 0, top_key_ = 0;
  std::int64_t nodes_ = 0, leaves_ = 0;
  bool truncated_ = false;
};

bool finite3(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

void validate(const Params& p) {
  using common::UsageError;
  if (p.max_segments < 1) throw UsageError("--max-segments must be >= 1");
  if (p.branches < 1) throw UsageError("--branches must be >= 1");
  if (!(p.area_factor > 0)) throw UsageError("--area-factor must be > 0");
  if (!(p.thickness_weight >= 0)) throw UsageError("--thickness-weight must be >= 0");
  if (!(p.elongation_weight >= 0)) throw UsageError("--elongation-weight must be >= 0");
  if (!(p.unary_threshold >= 0)) throw UsageError("--unary-threshold must be >= 0");
  if (!(p.orientation_threshold >= 0)) throw UsageError("--orientation-threshold must be >= 0");
  if (!(p.distance_threshold >= 0)) throw UsageError("--distance-threshold must be >= 0");
  for (double e : {p.exp_unary, p.exp_orientation, p.exp_distance, p.exp_area}) {
    if (!(e >= 0) || !std::isfinite(e)) throw UsageError("error exponents must be finite and >= 0");
  }
  if (p.max_nodes < 0) throw UsageError("--max-nodes must be >= 0 (0 = unlimited)");
  if (p.prefilter < 0) throw UsageError("--prefilter must be >= 0 (0 = off)");
  if (p.coarse_segments < 1) throw UsageError("--coarse-segments must be >= 1");
  if (p.threads < 1) throw UsageError("--threads must be >= 1");
}

void validate_graph(const SegmentGraph& g, const std::string& name) {
  using common::DataError;
  if (g.segments.empty()) throw DataError(name, "segment graph has no segments");
  std::set<int> ids;
  for (const auto& s : g.segments) {
    const std::string who = "segment " + std::to_string(s.segment_id) + ": ";
    if (!ids.insert(s.segment_id).second) throw DataError(name, who + "duplicate segment_id");
    if (!std::isfinite(s.area) || s.area <= 0) throw DataError(name, who + "area must be > 0");
    if (!(s.thickness >= 0 && s.thickness <= 1)) {
      throw DataError(name, who + "thickness must be in [0, 1]");
    }
    if (!(s.elongation >= 0 && s.elongation <= 1)) {
      throw DataError(name, who + "elongation must be in [0, 1]");
    }
    if (!finite3(s.centroid)) throw DataError(name, who + "centroid is not finite");
    if (!finite3(s.normal) || !(norm(s.normal) > 1e-9)) {
      throw DataError(name, who + "normal is zero or not finite");
    }
  }
}

documents::ModelScore match_model(const SegmentGraph& object, const Model& model, const Params& params,
                                  SearchStats* stats) {
  Matcher matcher(object, model.graph, params);
  documents::ModelScore ms = matcher.solve(stats);
  ms.model = model.name;
  return ms;
}

double entropy(const std::vector<double>& scores) { return documents::match_entropy(scores); }

Outputs run(const Params& params, const Inputs& in) {
  validate(params);
  const auto& models = *in.models;
  Outputs out;
  out.result.error_form = to_string(params.error);
  const std::vector<int> kept = prefilter(*in.object, models, params);
  std::vector<documents::ModelScore> scores(kept.size());
  out.stats.resize(models.size());
  out.searched = static_cast<int>(kept.size());
  const int n = static_cast<int>(kept.size());
  common::parallel_for(n, params.threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      scores[i] = match_model(*in.object, models[kept[i]], params, &out.stats[kept[i]]);
    }
  });
  std::stable_sort(scores.begin(), scores.end(),
                   [](const documents::ModelScore& a, const documents::ModelScore& b) {
                     if (a.score != b.score) return a.score > b.score;
                     return a.model < b.model;
                   });
  std::vector<double> s;
  for (size_t i = 0; i < scores.size(); ++i) {
    scores[i].rank = static_cast<int>(i) + 1;
    s.push_back(scores[i].score);
  }
  out.result.entropy = entropy(s);
  out.result.models = std::move(scores);
  return out;
}

const char* to_string(OrientationForm form) {
  return form == OrientationForm::kRelative ? "relative" : "thesis";
}
const char* to_string(NormalSign sign) { return sign == NormalSign::kAxial ? "axial" : "signed"; }
const char* to_string(ErrorForm form) { return form == ErrorForm::kBounded ? "bounded" : "thesis"; }
const char* to_string(Coverage coverage) { return coverage == Coverage::kBoth ? "both" : "model"; }
const char* to_string(PrefilterBy by) { return by == PrefilterBy::kCoarse ? "coarse" : "summary"; }

std::string object_name(const std::string& path) {
  namespace fs = std::filesystem;
  if (path == "-" || path.empty()) return "<stdin>";
  const fs::path p(path);
  const std::string stem = p.stem().string();
  // The experiment's generic artifact names say nothing: name the object by its directory.
  if ((stem == "segments" || stem == "match") && p.has_parent_path()) {
    return p.parent_path().lexically_normal().string();
  }
  return stem;
}

std::string format_table(const documents::MatchResult& r, const std::string& object) {
  std::string out = "# object " + object + ", entropy " + fmt3(r.entropy) + " bits, " +
                    std::to_string(r.models.size()) + " models, error form " + r.error_form + "\n";
  out +=
      "# rank model score margin error_unary error_orientation error_distance error_coverage "
      "matched considered\n";
  for (std::size_t i = 0; i < r.models.size(); ++i) {
    const auto& m = r.models[i];
    const double next = i + 1 < r.models.size() ? r.models[i + 1].score : 0.0;
    int matched = 0;
    for (const auto& pr : m.pairs) matched += pr.model_segment >= 0 ? 1 : 0;
    out += std::to_string(m.rank) + " " + m.model + " " + fmt3(m.score) + " " + fmt3(m.score - next) + " " +
           fmt3(m.error_unary) + " " + fmt3(m.error_orientation) + " " + fmt3(m.error_distance) + " " +
           fmt3(m.error_coverage) + " " + std::to_string(matched) + " " + std::to_string(m.pairs.size()) +
           "\n";
  }
  return out;
}

}  // namespace canopy::gmatch
