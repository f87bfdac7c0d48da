#include "report/report.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include <sys/stat.h>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/stats.h"
#include "canopy/documents/areas.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/pcd.h"

namespace canopy::report {
namespace {

std::string key(const std::string& o, const std::string& s, int n) {
  return o + "/" + s + "/" + std::to_string(n);
}

const documents::ModelScore* find_model(const documents::MatchResult& m, const std::string& name) {
  for (const auto& s : m.models) {
    if (s.model == name) return &s;
  }
  return nullptr;
}

}  // namespace

const std::map<std::string, int> kThesisPrinted = {
    {"earthmover", 100}, {"obj1", 64}, {"sedan", 100}, {"semi", 83}, {"tank", 50}};

void validate(const Params& p) {
  if (p.max_segments < 1) throw common::UsageError("--max-segments must be at least 1");
  if (!(p.overseg_ratio > 0 && std::isfinite(p.overseg_ratio)))
    throw common::UsageError("--overseg-ratio must be a finite number > 0");
  if (!(p.missing_area_ratio >= 0 && std::isfinite(p.missing_area_ratio)))
    throw common::UsageError("--missing-area-ratio must be a finite number >= 0");
  if (!(p.spurious_share >= 0 && p.spurious_share <= 1))
    throw common::UsageError("--spurious-share must be in [0, 1]");
}

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::not_run: return "not_run";
    case Outcome::failed: return "failed";
    case Outcome::right: return "right";
    case Outcome::flipped: return "flipped";
    case Outcome::wrong_model: return "wrong_model";
    case Outcome::none: return "none";
  }
  return "";
}

Judgement judge_verdict(const Case& c) {
  Judgement j;
  if (!c.match.models.empty()) j.gmatch_model = c.match.models.front().model;
  j.gmatch_right = j.gmatch_model == c.object;
  if (c.verdict_status == VerdictStatus::missing) return j;
  if (c.verdict_status == VerdictStatus::failed) {
    j.outcome = Outcome::failed;
    return j;
  }
  const documents::Verdict& v = c.verdict;
  j.confidence = v.confidence;
  if (v.model.empty()) {
    j.outcome = Outcome::none;
    j.answer = "none";
    return j;
  }
  j.answer = v.model;
  if (v.model != c.object) {
    j.outcome = Outcome::wrong_model;
    return j;
  }
  j.outcome = Outcome::right;
  if (v.chosen >= 0 && v.chosen < static_cast<int>(v.hypotheses.size())) {
    const formats::Pose& pose = v.hypotheses[static_cast<std::size_t>(v.chosen)].pose;
    j.posed = true;
    const auto& t = pose.translation;
    j.position_error = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    const double h = std::remainder(formats::euler_degrees(pose)[0], 360.0);  // in [-180, 180]
    j.heading_error = std::fabs(h);
    if (j.heading_error > 90) j.outcome = Outcome::flipped;
  }
  return j;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return common::sorted_quantile(values, std::clamp(q, 0.0, 1.0));
}

VerifySummary summarize_verify(const Inputs& in) {
  VerifySummary s;
  const double edges[] = {0, 0.5, 0.7, 0.8, 0.9, 1.0};
  for (std::size_t b = 0; b + 1 < std::size(edges); ++b)
    s.reliability.push_back({edges[b], edges[b + 1], 0, 0});
  std::vector<double> position, heading;
  for (const auto& c : in.cases) {
    const Judgement j = judge_verdict(c);
    s.judgements.push_back(j);
    if (j.outcome == Outcome::not_run) {
      ++s.not_run;
      continue;
    }
    for (VerifyTally* t : {&s.all, &s.per_object[c.object], &s.per_noise[c.noise_mm]}) {
      ++t->trials;
      t->right += j.outcome == Outcome::right;
      t->flipped += j.outcome == Outcome::flipped;
      t->wrong_model += j.outcome == Outcome::wrong_model;
      t->none += j.outcome == Outcome::none;
      t->failed += j.outcome == Outcome::failed;
      t->gmatch_right += j.gmatch_right;
    }
    if (j.outcome != Outcome::failed) {
      for (std::size_t b = 0; b < s.reliability.size(); ++b) {
        auto& bin = s.reliability[b];
        const bool last = b + 1 == s.reliability.size();
        if (j.confidence >= bin.lo && (j.confidence < bin.hi || (last && j.confidence <= bin.hi))) {
          ++bin.answers;
          bin.right += j.outcome == Outcome::right;
          break;
        }
      }
    }
    if (j.outcome == Outcome::right && j.posed) {
      position.push_back(j.position_error);
      heading.push_back(j.heading_error);
    }
  }
  s.posed = static_cast<int>(position.size());
  s.position_median = percentile(position, 0.5);
  s.position_p90 = percentile(position, 0.9);
  s.heading_median = percentile(heading, 0.5);
  s.heading_p90 = percentile(heading, 0.9);
  return s;
}

Diagnosis diagnose(const Case& c, const documents::SegmentGraph* model, const Params& p) {
  Diagnosis d;
  if (const auto* s = find_model(c.match, c.object)) {
    d.correct_score = s->score;
    d.correct_rank = s->rank;
  }
  d.entropy = c.match.entropy;
  if (!c.match.models.empty()) d.best_model = c.match.models.front().model;
  std::vector<const documents::Segment*> segs;
  for (const auto& s : c.segments.segments) segs.push_back(&s);
  std::stable_sort(segs.begin(), segs.end(), [](auto* a, auto* b) { return a->area > b->area; });
  double top_area = 0, top_spurious = 0;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const bool target = segs[i]->label == formats::kLabelTarget;
    if (target) {
      ++d.target_segments;
      d.target_area += segs[i]->area;
    }
    if (static_cast<int>(i) < p.max_segments) {
      top_area += segs[i]->area;
      if (!target) {
        ++d.spurious_segments;
        top_spurious += segs[i]->area;
      }
    }
  }
  d.spurious_area_share = top_area > 0 ? top_spurious / top_area : 0;
  if (model != nullptr) {
    for (const auto& s : model->segments) {
      if (s.label == formats::kLabelTarget || s.label == formats::kLabelUnknown) {
        ++d.model_segments;
        d.model_area += s.area;
      }
    }
  }
  d.over_segmented = d.model_segments > 0 && d.target_segments > p.overseg_ratio * d.model_segments;
  d.missing_area = d.model_area > 0 && d.target_area < p.missing_area_ratio * d.model_area;
  d.spurious = d.spurious_area_share > p.spurious_share;
  return d;
}

AreaRow read_areas(const std::string& path) {
  AreaRow r;
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return r;
  const documents::Areas a = documents::read_areas_file(path);
  r.present = true;
  r.visible = a.visible;
  r.samples = a.samples;
  r.mesh = a.mesh;
  r.segments = a.segments;
  r.matched = a.matched;
  return r;
}

std::vector<AreaSummary> summarize_areas(const Inputs& in) {
  std::vector<AreaSummary> out;
  std::map<std::string, double> matched0;  // "<object>/<scene>" -> matched area at 0 mm
  for (const auto& c : in.cases) {
    if (c.areas.present && c.noise_mm == 0) matched0[c.object + "/" + c.scene] = c.areas.matched;
  }
  for (int n : in.noises) {
    AreaSummary a;
    a.noise_mm = n;
    double samples = 0, mesh = 0, segments = 0, matched = 0, num = 0, den = 0;
    for (const auto& c : in.cases) {
      if (c.noise_mm != n || !c.areas.present) continue;
      ++a.trials;
      a.visible += c.areas.visible;
      samples += c.areas.samples;
      mesh += c.areas.mesh;
      segments += c.areas.segments;
      matched += c.areas.matched;
      const auto it = matched0.find(c.object + "/" + c.scene);
      if (it != matched0.end()) {
        num += c.areas.matched;
        den += it->second;
        ++a.pairs_vs_0;
      }
    }
    if (a.visible > 0) {
      a.samples = samples / a.visible;
      a.mesh = mesh / a.visible;
      a.segments = segments / a.visible;
      a.matched = matched / a.visible;
    }
    a.matched_vs_0 = den > 0 ? num / den : 0;
    out.push_back(a);
  }
  return out;
}

namespace {

// The trials: diagnoses, rank-1 rates (canopy's and the thesis table's), failure causes and the
// stages' times, in case order.
void count_trials(const Inputs& in, const Params& p, Numbers& n) {
  for (const auto& c : in.cases) {
    const auto mit = in.models.find(c.object);
    const Diagnosis d = diagnose(c, mit == in.models.end() ? nullptr : &mit->second, p);
    const std::string k = key(c.object, c.scene, c.noise_mm);
    n.diagnoses.push_back(d);
    n.by_key[k] = d;
    const bool ok = d.correct_rank == 1;
    n.per_object[c.object].right += ok;
    n.per_object[c.object].trials += 1;
    n.all.right += ok;
    ++n.all.trials;
    const auto th = in.thesis.find(k);
    if (th != in.thesis.end()) {
      n.thesis_per_object[c.object].right += th->second.rank == 1;
      n.thesis_per_object[c.object].trials += 1;
      n.thesis_all.right += th->second.rank == 1;
      ++n.thesis_all.trials;
    }
    if (!ok) {
      ++n.failed;
      n.over_segmented += d.over_segmented;
      n.missing_area += d.missing_area;
      n.spurious += d.spurious;
      n.unexplained += !(d.over_segmented || d.missing_area || d.spurious);
    }
    for (const auto& [stage, t] : c.times) n.stages[stage].add(t);
  }
}

// Mean of the per-object rates; the thesis's mean is over the objects it printed a rate for
// (none for other models).
void count_means(const Inputs& in, Numbers& n) {
  for (const auto& o : in.objects) {
    const Rate& po = n.per_object[o];
    n.thesis_per_object[o];
    n.mean_rate += po.trials ? 100.0 * po.right / po.trials : 0;
    if (kThesisPrinted.count(o)) {
      n.thesis_mean += kThesisPrinted.at(o);
      ++n.thesis_printed;
    }
  }
  if (!in.objects.empty()) n.mean_rate /= static_cast<double>(in.objects.size());
  if (n.thesis_printed > 0) n.thesis_mean /= n.thesis_printed;
  // The thesis's overall rate (≈79%) is over its five objects: it applies only to them.
  n.thesis_objects = n.thesis_printed == static_cast<int>(kThesisPrinted.size()) &&
                     in.objects.size() == kThesisPrinted.size();
}

AblationRates ablation_rates(const Inputs& in, const Ablation& a) {
  AblationRates r;
  r.failed = a.failed;
  for (const auto& o : in.objects) {
    Rate po;
    for (const auto& [k, rank] : a.correct_rank) {
      if (k.compare(0, o.size() + 1, o + "/") != 0) continue;
      po.right += rank == 1;
      ++po.trials;
    }
    r.all.right += po.right;
    r.all.trials += po.trials;
    r.per_object.push_back(po);
  }
  return r;
}

// The renderings (rangetrace) beside the trial stages, and the total over all but verify.
void count_times(const Inputs& in, Numbers& n) {
  StageTotal render;
  for (const auto& [k, t] : in.render_times) {
    if (!t.present) continue;
    render.add(t);
    const auto scene = k.substr(k.find('/') + 1);
    n.render_images += in.render_views.count(scene) ? in.render_views.at(scene) : 0;
  }
  n.stages["rangetrace"] = render;
  for (const char* s : {"addnoise", "fitvox", "cocone", "ncut", "gmatch", "verify"}) n.stages[s];
  for (const auto& [s, t] : n.stages) {
    if (s == "verify") continue;
    n.total_seconds += t.seconds;
    n.total_cpu_seconds += t.cpu_seconds;
    n.total_runs += t.runs;
    n.total_cpu_runs += t.cpu_runs;
  }
}

}  // namespace

void StageTotal::add(const StageTime& t) {
  if (!t.present) return;
  ++runs;
  seconds += t.seconds;
  peak_mb = std::max(peak_mb, t.peak_mb);
  if (t.has_cpu) {
    ++cpu_runs;
    cpu_seconds += t.cpu_seconds();
  }
}

std::string cpu_cell(const std::string& number, int cpu_runs, int runs) {
  if (cpu_runs == 0) return "–";
  if (cpu_runs == runs) return number;
  return number + " (" + std::to_string(cpu_runs) + " of " + std::to_string(runs) + " runs)";
}

Numbers compute(const Inputs& in, const Params& p) {
  Numbers n;
  count_trials(in, p, n);
  count_means(in, n);
  for (const auto& a : in.ablations) n.ablations.push_back(ablation_rates(in, a));
  n.areas = summarize_areas(in);
  n.verify = summarize_verify(in);
  count_times(in, n);
  return n;
}

int render_views(const std::string& scan) {
  struct stat st {};
  if (::stat(scan.c_str(), &st) == 0) {
    const formats::PointCloud c = formats::read_pcd(scan);
    if (!c.has("view_idx")) return 0;
    double m = -1;
    for (double v : c.col("view_idx")) m = std::max(m, v);
    return static_cast<int>(m) + 1;
  }
  const std::string log = scan + ".log";
  if (::stat(log.c_str(), &st) != 0) return 0;
  static const std::regex wrote(R"(rangetrace: wrote \d+ points \([^()]*, (\d+) views\))");
  std::istringstream in(common::read_file(log));
  int views = 0;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, wrote)) views = std::stoi(m[1].str());
  }
  return views;
}

Outputs run(const Params& p, const Inputs& in) { return render(in, p, compute(in, p)); }

}  // namespace canopy::report
