// The report's Markdown and CSV tables: renders the numbers compute() found (report.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "canopy/common/stats.h"
#include "report/report.h"

namespace canopy::report {
namespace {

// Every number of the report goes through the one formatter (formats::format_number).
std::string fmt(const char* f, double v) { return format_number(f, v); }

std::string pct(int num, int den) { return den == 0 ? "–" : fmt("%.0f%%", 100.0 * num / den); }
std::string pct(const Rate& r) { return pct(r.right, r.trials); }

// A row's units: the trials of a row that pools every noise level are noisy copies of
// trials / noise levels renders.
double pooled_units(const Rate& r, std::size_t noise_levels) {
  return noise_levels > 0 ? static_cast<double>(r.trials) / static_cast<double>(noise_levels) : r.trials;
}

std::string key(const std::string& o, const std::string& s, int n) {
  return o + "/" + s + "/" + std::to_string(n);
}

std::string thesis_printed(const std::string& object) {
  return kThesisPrinted.count(object) ? std::to_string(kThesisPrinted.at(object)) + "%" : "–";
}

// Thesis Table A.1 (2002 hardware): stage -> (runs, total minutes).
struct ThesisTime {
  const char* stage;
  const char* ours;
  int runs;
  int minutes;
};
const ThesisTime kThesisTimes[] = {{"Range image generation", "rangetrace", 780, 454},
                                   {"Local surface fitting", "fitvox", 90, 57},
                                   {"Surface reconstruction", "cocone", 90, 134},
                                   {"Segmentation", "ncut", 90, 67},
                                   {"Recognition", "gmatch", 90, 2}};

std::string hms(double seconds) {
  const long s = std::lround(seconds);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

std::string verify_markdown(const Inputs& in, const VerifySummary& v) {
  std::ostringstream md;
  md << "## Verification (`verify`)\n\n";
  if (v.all.trials == 0) {
    md << "`verify` was not run on these trials (no `verdict.json`; `make -f Makefile.experiments "
          "verdicts`).\n\n";
    return md.str();
  }
  md << "`verify` (docs/decisions/verify.md) checks gmatch's hypotheses against the samples and answers "
        "a model or `none` with a confidence. *right*: the true object; *wrong model*: another model; "
        "*flipped*: the true object posed 180° about the vertical (counted as wrong); *failed*: verify "
        "failed (empty `verdict.json`). \"without verify\" is the ablation: gmatch's rank-1 model on the "
        "same trials.";
  if (v.not_run > 0)
    md << " verify was not run on " << v.not_run << " trials (no `verdict.json`); they are left out.";
  md << " Per trial: `verdicts.csv`.\n\n"
     << "| | trials | right | wrong model | flipped | none | failed | without verify (gmatch rank 1) |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  // (rates with Wilson 95% intervals at the distinct renders: trials / noise levels where a row
  // pools the noise levels, the trials themselves in a row of one noise level)
  const double levels = static_cast<double>(std::max<std::size_t>(1, in.noises.size()));
  auto row = [&](const std::string& label, const VerifyTally& t, bool pooled) {
    const double units = pooled ? t.trials / levels : t.trials;
    md << "| " << label << " | " << t.trials << " | " << rate_ci_units(t.right, t.trials, units) << " | "
       << t.wrong_model << " | " << t.flipped << " | " << t.none << " | " << t.failed << " | "
       << rate_ci_units(t.gmatch_right, t.trials, units) << " |\n";
  };
  for (const auto& o : in.objects) {
    const auto it = v.per_object.find(o);
    if (it != v.per_object.end()) row(o, it->second, true);
  }
  for (int n : in.noises) {
    const auto it = v.per_noise.find(n);
    if (it != v.per_noise.end()) row(std::to_string(n) + " mm", it->second, false);
  }
  row("**all trials**", v.all, true);
  md << "\n";
  md << "Pose of the right answers: every thesis object is rendered at heading 0 at the origin, so the "
        "true pose is the identity; error = |translation| and |heading| of the chosen hypothesis's pose "
        "(model → candidate frame). ";
  if (v.posed == 0) {
    md << "No right answer carries a pose.\n\n";
  } else {
    md << "Over " << v.posed << " right answers: position median " << fmt("%.3f", v.position_median)
       << " m, 90th percentile " << fmt("%.3f", v.position_p90) << " m; heading median "
       << fmt("%.2f", v.heading_median) << "°, 90th percentile " << fmt("%.2f", v.heading_p90) << "°.\n\n";
  }
  md << "Reliability: answers (a model or `none`) by stated confidence, and the share that was right "
        "(`none` is never right here: every trial's object is in the modelbase).\n\n"
     << "| confidence | answers | right (95% interval at answers / noise levels) |\n|---|---|---|\n";
  for (std::size_t b = 0; b < v.reliability.size(); ++b) {
    const auto& bin = v.reliability[b];
    md << "| " << fmt("%.1f", bin.lo) << "–" << fmt("%.1f", bin.hi) << " | " << bin.answers << " | "
       << rate_ci_units(bin.right, bin.answers, bin.answers / levels) << " |\n";
  }
  md << "\n";
  return md.str();
}

std::string verdicts_csv(const Inputs& in, const VerifySummary& v) {
  std::ostringstream csv;
  csv << "object,scene,noise_mm,answer,confidence,correct,gmatch_rank1,outcome,position_error_m,"
         "heading_error_deg\n";
  for (std::size_t i = 0; i < in.cases.size(); ++i) {
    const Case& c = in.cases[i];
    const Judgement& j = v.judgements[i];
    const bool answered = j.outcome != Outcome::not_run && j.outcome != Outcome::failed;
    csv << c.object << ',' << c.scene << ',' << c.noise_mm << ',' << j.answer << ','
        << (answered ? fmt("%.4f", j.confidence) : "") << ','
        << (j.outcome == Outcome::not_run ? ""
            : j.outcome == Outcome::right ? "1"
                                          : "0")
        << ',' << j.gmatch_model << ',' << outcome_name(j.outcome) << ','
        << (j.posed ? fmt("%.4f", j.position_error) : "") << ','
        << (j.posed ? fmt("%.3f", j.heading_error) : "") << '\n';
  }
  return csv.str();
}

std::string cases_csv(const Inputs& in, const Numbers& n) {
  std::ostringstream csv;
  csv << "object,scene,noise_mm,correct_score,correct_rank,entropy,best_model,best_score,"
         "segments,target_segments,model_segments,target_area_m2,model_area_m2,"
         "spurious_segments,spurious_area_share,over_segmented,missing_area,spurious,"
         "thesis_score,thesis_rank,thesis_entropy,"
         "addnoise_s,fitvox_s,cocone_s,ncut_s,gmatch_s,samples_peak_mb\n";
  for (std::size_t i = 0; i < in.cases.size(); ++i) {
    const Case& c = in.cases[i];
    const Diagnosis& d = n.diagnoses[i];
    const auto th = in.thesis.find(key(c.object, c.scene, c.noise_mm));
    auto time_of = [&](const char* s) {
      const auto it = c.times.find(s);
      return it != c.times.end() && it->second.present ? fmt("%.3f", it->second.seconds) : std::string();
    };
    const double best_score = c.match.models.empty() ? 0 : c.match.models.front().score;
    csv << c.object << ',' << c.scene << ',' << c.noise_mm << ',' << fmt("%.4f", d.correct_score) << ','
        << d.correct_rank << ',' << fmt("%.4f", d.entropy) << ',' << d.best_model << ','
        << fmt("%.4f", best_score) << ',' << c.segments.segments.size() << ',' << d.target_segments << ','
        << d.model_segments << ',' << fmt("%.3f", d.target_area) << ',' << fmt("%.3f", d.model_area) << ','
        << d.spurious_segments << ',' << fmt("%.3f", d.spurious_area_share) << ',' << d.over_segmented << ','
        << d.missing_area << ',' << d.spurious << ',';
    if (th != in.thesis.end()) {
      csv << fmt("%.3f", th->second.score) << ',' << th->second.rank << ',' << fmt("%.2f", th->second.entropy);
    } else {
      csv << ",,";
    }
    const auto fit = c.times.find("fitvox");
    csv << ',' << time_of("addnoise") << ',' << time_of("fitvox") << ',' << time_of("cocone") << ','
        << time_of("ncut") << ',' << time_of("gmatch") << ','
        << (fit != c.times.end() && fit->second.present ? fmt("%.0f", fit->second.peak_mb) : "") << '\n';
  }
  return csv.str();
}

std::string scores_csv(const Inputs& in, const Numbers& n) {
  std::ostringstream csv;
  csv << "object,scene,noise_mm,score,rank,entropy\n";
  for (std::size_t i = 0; i < in.cases.size(); ++i) {
    const Case& c = in.cases[i];
    const Diagnosis& d = n.diagnoses[i];
    csv << c.object << ',' << c.scene << ',' << c.noise_mm << ',' << fmt("%.4f", d.correct_score) << ','
        << d.correct_rank << ',' << fmt("%.4f", d.entropy) << '\n';
  }
  return csv.str();
}

// The title paragraph and the recognition rates beside the thesis's.
std::string rates_markdown(const Inputs& in, const Numbers& n) {
  std::ostringstream md;
  md << "# canopy experiment report\n\n"
     << in.objects.size() << " objects × " << in.scenes.size() << " scenes × " << in.noises.size()
     << " noise levels = " << n.all.trials << " trials, each matched against the " << in.models.size()
     << "-model modelbase built from the `unoccluded`, noise-free scans (thesis §6.4). "
        "Generated by `make -f Makefile.experiments all`; every number is also in `cases.csv`.\n\n";
  const std::size_t levels = in.noises.size();
  md << "## Recognition rate\n\n| object | canopy | canopy, 95% interval over renders | thesis (printed) | "
        "thesis (its table) |\n|---|---|---|---|---|\n";
  for (const auto& o : in.objects) {
    const Rate& po = n.per_object.at(o);
    const Rate& to = n.thesis_per_object.at(o);
    md << "| " << o << " | " << pct(po) << " (" << po.right << "/" << po.trials << ") | "
       << rate_ci_units(po.right, po.trials, pooled_units(po, levels)) << " | " << thesis_printed(o) << " | "
       << pct(to) << " (" << to.right << "/" << to.trials << ") |\n";
  }
  md << "| **all trials** | **" << pct(n.all) << "** (" << n.all.right << "/" << n.all.trials << ") | "
     << rate_ci_units(n.all.right, n.all.trials, pooled_units(n.all, levels)) << " | "
     << (n.thesis_objects ? "≈79%" : "–") << " | " << pct(n.thesis_all) << " (" << n.thesis_all.right << "/"
     << n.thesis_all.trials << ") |\n";
  md << "| mean per object | " << fmt("%.0f%%", n.mean_rate) << " | | "
     << (n.thesis_printed > 0 ? fmt("%.0f%%", n.thesis_mean) : "–") << " | |\n\n";
  md << "Intervals (issue 29): Wilson 95% at the number of distinct renders, not of trials: the " << levels
     << " noise levels of an (object, scene) are noisy copies of one render, so a row pooling them "
        "has trials / "
     << levels << " independent units (section \"Recognition by scene\" below splits them).\n\n";
  if (std::find(in.objects.begin(), in.objects.end(), "obj1") != in.objects.end())
    md << "The thesis prints 64% for obj1, but its Table 6.2 has 11 of 18 trials at rank 1 (61%).\n\n";
  return md.str();
}

// "k/n = r% [lo, hi]" with Wilson's 95% interval (common/stats.h), as the real tiles' section
// writes rates; "–" when n = 0.
std::string rate_ci(int k, int n) { return rate_ci_units(k, n, n); }

// The protocol split by scene (issue 29): the unoccluded trials are the modelbase's own renders
// (and noisy copies of them), circle and flyby the occluded test; and every noise level of an
// (object, scene) reuses one render, so the trials are counted beside the distinct renders.
std::string scene_split_markdown(const Inputs& in, const Numbers& n) {
  struct Tally {
    int trials = 0, gmatch = 0, verify = 0, verified = 0;
    std::map<std::string, std::pair<bool, bool>> renders;  // object -> (all gmatch right, all verify right)
    int renders_gmatch() const {
      int k = 0;
      for (const auto& [o, r] : renders) k += r.first;
      return k;
    }
    int renders_verify() const {
      int k = 0;
      for (const auto& [o, r] : renders) k += r.second;
      return k;
    }
  };
  std::map<std::string, Tally> by_scene;
  Tally occluded, all;
  const bool verify = n.verify.all.trials > 0;
  for (std::size_t i = 0; i < in.cases.size(); ++i) {
    const Case& c = in.cases[i];
    const bool g = n.diagnoses[i].correct_rank == 1;
    const bool v = i < n.verify.judgements.size() && n.verify.judgements[i].outcome == Outcome::right;
    const bool ran = i < n.verify.judgements.size() && n.verify.judgements[i].outcome != Outcome::not_run;
    std::vector<Tally*> into{&by_scene[c.scene], &all};
    if (c.scene != "unoccluded") into.push_back(&occluded);
    for (Tally* t : into) {
      ++t->trials;
      t->gmatch += g;
      t->verify += v;
      t->verified += ran;
      // A render is one (object, scene): keyed by both where the tally spans scenes.
      auto it = t->renders.try_emplace(c.object + "/" + c.scene, std::make_pair(true, true)).first;
      it->second.first = it->second.first && g;
      it->second.second = it->second.second && v;
    }
  }
  std::ostringstream md;
  md << "## Recognition by scene, with 95% intervals\n\n"
        "The trials above are not independent samples. Each object is rendered once per scene and "
        "the noise levels are noisy copies of that one render, so the trials of an (object, scene) "
        "share their occlusion and viewpoint; and the `unoccluded` renders are the scans the "
        "modelbase is built from (at 0 mm a trial matches a model against its own source): they "
        "check the chain, they do not test recognition. Here `unoccluded` stands apart from the "
        "occluded scenes, and each rate is given over trials and over distinct renders (a render "
        "counts as right when all its noise levels are). Intervals: Wilson 95% (common/stats.h); "
        "the one over renders is the honest width, the one over trials is too narrow where trials "
        "share a render.\n\n"
     << "| scene | renders | trials | gmatch rank 1, trials | gmatch, renders right at every noise |"
     << (verify ? " verify right, trials | verify, renders right at every noise |" : "")
     << "\n|---|---|---|---|---|" << (verify ? "---|---|" : "") << "\n";
  auto row = [&](const std::string& label, const Tally& t) {
    const int r = static_cast<int>(t.renders.size());
    md << "| " << label << " | " << r << " | " << t.trials << " | " << rate_ci(t.gmatch, t.trials) << " | "
       << rate_ci(t.renders_gmatch(), r) << " |";
    if (verify) {
      md << " " << rate_ci(t.verify, t.trials) << (t.verified < t.trials ? " (verify not run on some)" : "")
         << " | " << rate_ci(t.renders_verify(), r) << " |";
    }
    md << "\n";
  };
  for (const auto& s : in.scenes) {
    if (by_scene.count(s))
      row(s == "unoccluded" ? "unoccluded (the modelbase's own renders)" : s, by_scene.at(s));
  }
  if (occluded.trials > 0 && occluded.trials < all.trials) row("**occluded (all but unoccluded)**", occluded);
  row("all", all);
  md << "\n";
  return md.str();
}

std::string ablations_markdown(const Inputs& in, const Numbers& n) {
  if (in.ablations.empty()) return "";
  std::ostringstream md;
  md << "## Ablations\n\nEach default where canopy departs from the thesis (or from its first "
        "reading), undone one at a time on the same scans; rank-1 rate per object and over all "
        "trials, all trials with its Wilson 95% interval at the distinct renders (trials / noise levels: "
        "the noise levels are copies of one render).\n\n| variant | change |";
  for (const auto& o : in.objects) md << " " << o << " |";
  md << " all |\n|---|---|";
  for (std::size_t i = 0; i <= in.objects.size(); ++i) md << "---|";
  const std::size_t levels = in.noises.size();
  md << "\n| **canopy defaults** | |";
  for (const auto& o : in.objects) { md << " " << pct(n.per_object.at(o)) << " |"; }
  md << " **" << rate_ci_units(n.all.right, n.all.trials, pooled_units(n.all, levels)) << "** |\n";
  for (std::size_t i = 0; i < in.ablations.size(); ++i) {
    const Ablation& a = in.ablations[i];
    const AblationRates& r = n.ablations[i];
    md << "| " << a.name << " | `" << a.change << "` |";
    for (const Rate& po : r.per_object) md << " " << pct(po) << " |";
    md << " " << rate_ci_units(r.all.right, r.all.trials, pooled_units(r.all, levels))
       << (r.failed ? " (" + std::to_string(r.failed) + " failed in a stage)" : "") << " |\n";
  }
  md << "\n";
  return md.str();
}

double stage_share(const AreaSummary& a, const std::string& stage) {
  return stage == "samples"    ? a.samples
         : stage == "mesh"     ? a.mesh
         : stage == "segments" ? a.segments
                               : a.matched;
}

// Area retained per stage and noise level in scores.csv's layout.
std::string areas_csv(const Numbers& n) {
  std::ostringstream csv;
  csv << "object,scene,noise_mm,score,rank,entropy\n";
  for (const char* stage : {"samples", "mesh", "segments", "matched"}) {
    for (const auto& a : n.areas) {
      if (a.trials == 0) continue;
      csv << stage << ",all," << a.noise_mm << ',' << fmt("%.4f", stage_share(a, stage)) << ",0,0\n";
    }
  }
  return csv.str();
}

std::string areas_markdown(const Params& p, const Numbers& n) {
  bool any_areas = false;
  for (const auto& a : n.areas) any_areas = any_areas || a.trials > 0;
  if (!any_areas) return "";
  std::ostringstream md;
  md << "## Where the target's area goes\n\nTarget (label 1) surface area per stage as a share of the "
        "area visible in the noise-free labelled scan (`areas`, docs/decisions/noise.md): what the "
        "fitvox samples stand for, the cocone mesh, all ncut segments, and the "
     << p.max_segments
     << " largest segments that gmatch matches. Ratios of sums over the trials of each noise level; "
        "the last column is the matched area relative to 0 mm on the same object/scene pairs. "
        "Per trial: `out/<object>/<scene>/noise-<mm>/areas.json`; this table as CSV: `areas.csv` "
        "(`figures plot -i areas.csv` draws it).\n\n"
     << "| noise (mm) | trials | visible (m², mean) | samples | mesh | segments | matched | matched vs 0 "
        "mm |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const auto& a : n.areas) {
    if (a.trials == 0) continue;
    md << "| " << a.noise_mm << " | " << a.trials << " | " << fmt("%.1f", a.visible / a.trials) << " | "
       << fmt("%.0f%%", 100 * a.samples) << " | " << fmt("%.0f%%", 100 * a.mesh) << " | "
       << fmt("%.0f%%", 100 * a.segments) << " | " << fmt("%.0f%%", 100 * a.matched) << " | "
       << (a.pairs_vs_0 > 0 ? fmt("%.0f%%", 100 * a.matched_vs_0) : "–") << " |\n";
  }
  // A text plot: one bar per stage and noise level, 2% of the visible area per character.
  md << "\n```\narea retained (share of the visible target area; # = 2%)\n";
  for (const char* stage : {"samples", "mesh", "segments", "matched"}) {
    for (const auto& a : n.areas) {
      if (a.trials == 0) continue;
      const double v = stage_share(a, stage);
      char label[40];
      std::snprintf(label, sizeof label, "%-8s %2d mm |", stage, a.noise_mm);
      md << label << std::string(static_cast<std::size_t>(std::lround(std::clamp(v, 0.0, 1.0) * 50)), '#')
         << ' ' << fmt("%.0f%%", 100 * v) << "\n";
    }
  }
  md << "```\n\n";
  return md.str();
}

std::string failures_markdown(const Params& p, const Numbers& n) {
  std::ostringstream md;
  md << "## Causes of the failures\n\n";
  if (n.failed == 0) {
    md << "No trial failed.\n\n";
    return md.str();
  }
  md << n.failed
     << " trials did not rank the correct model first. Measured against the ground-truth "
        "labels (a trial can have several causes):\n\n"
     << "| cause | trials | test |\n|---|---|---|\n"
     << "| over-segmentation | " << n.over_segmented << " | target segments > " << p.overseg_ratio
     << " × the model's segments |\n"
     << "| missing area | " << n.missing_area << " | target area < " << p.missing_area_ratio
     << " × the model's area |\n"
     << "| spurious segments | " << n.spurious << " | non-target share of the " << p.max_segments
     << " largest segments' area > " << p.spurious_share << " |\n"
     << "| none of these | " << n.unexplained << " | |\n\n";
  return md.str();
}

// One table row per trial of the object: ours, the thesis's, the diagnosis.
void object_rows(const Inputs& in, const Numbers& n, const std::string& o, std::ostringstream& md) {
  for (const auto& s : in.scenes) {
    for (int noise : in.noises) {
      const std::string k = key(o, s, noise);
      const auto dit = n.by_key.find(k);
      if (dit == n.by_key.end()) continue;
      const Diagnosis& d = dit->second;
      const auto th = in.thesis.find(k);
      md << "| " << s << " | " << noise << " | " << fmt("%.3f", d.correct_score) << " | "
         << (d.correct_rank == 1 ? "1" : "**" + std::to_string(d.correct_rank) + "**") << " | "
         << fmt("%.2f", d.entropy) << " | " << d.best_model << " | ";
      if (th != in.thesis.end()) {
        md << fmt("%.3f", th->second.score) << " | " << th->second.rank << " | "
           << fmt("%.2f", th->second.entropy);
      } else {
        md << "– | – | –";
      }
      md << " | " << d.target_segments << "/" << d.model_segments << " | " << fmt("%.1f", d.target_area)
         << "/" << fmt("%.1f", d.model_area) << " | " << fmt("%.2f", d.spurious_area_share) << " |\n";
    }
  }
}

std::string per_object_markdown(const Inputs& in, const Numbers& n) {
  std::ostringstream md;
  md << "## Per object\n\nScore and rank of the correct model, entropy of the scores over the models "
        "(bits; "
     << fmt("%.2f", std::log2(std::max<std::size_t>(1, in.models.size())))
     << " = no idea); the thesis's values beside ours. Diagnosis columns: target segments / model "
        "segments, target area / model area (m²), non-target area share of the largest segments.\n\n";
  for (const auto& o : in.objects) {
    md << "### " << o << " — " << pct(n.per_object.at(o)) << " (thesis " << thesis_printed(o) << ")\n\n"
       << "| scene | noise (mm) | score | rank | entropy | best model | thesis score | thesis rank | "
          "thesis entropy | segments | area | spurious "
          "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    object_rows(in, n, o, md);
    md << "\n";
  }
  return md.str();
}

std::string times_csv(const Numbers& n) {
  std::ostringstream csv;
  csv << "stage,runs,total_s,mean_s,peak_mb,cpu_s,cpu_runs\n";
  for (const char* s : {"rangetrace", "addnoise", "fitvox", "cocone", "ncut", "gmatch", "verify"}) {
    const StageTotal& t = n.stages.at(s);
    csv << s << ',' << t.runs << ',' << fmt("%.3f", t.seconds) << ','
        << fmt("%.3f", t.runs ? t.seconds / t.runs : 0) << ',' << fmt("%.0f", t.peak_mb) << ','
        << fmt("%.3f", t.cpu_seconds) << ',' << t.cpu_runs << '\n';
  }
  return csv.str();
}

// One row of the time table: our stage beside the thesis's Table A.1.
void time_row(const Numbers& n, const std::string& label, const std::string& tool, int images,
              std::ostringstream& md) {
  const StageTotal& t = n.stages.at(tool);
  md << "| " << label << " | `" << tool << "` | " << t.runs;
  if (images > 0) md << " (" << images << " images)";
  md << " | " << hms(t.seconds) << " | " << cpu_cell(hms(t.cpu_seconds), t.cpu_runs, t.runs) << " | "
     << fmt("%.2f", t.runs ? t.seconds / t.runs : 0) << " | " << fmt("%.0f", t.peak_mb) << " | ";
  for (const auto& th : kThesisTimes) {
    if (tool == th.ours) md << th.runs << " | " << th.minutes / 60 << ":" << fmt("%02.0f", th.minutes % 60);
  }
  if (tool == "addnoise" || tool == "verify") md << "– | –";
  md << " |\n";
}

std::string times_markdown(const Numbers& n) {
  std::ostringstream md;
  md << "## Time per stage\n\nWall time on this machine (the stage runner `tools/stagerun` around every run; "
        "with "
        "`-j2` two runs share the 2 cores, and wall time includes waiting for the CPU) and CPU time (user + "
        "system, which the load does not change), beside the thesis's Table A.1 (2002 hardware).\n\n"
     << "| stage | tool | runs | total (h:mm:ss) | CPU (h:mm:ss) | mean (s) | peak memory (MB) | thesis runs "
        "| thesis total (h:mm) |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  time_row(n, "Range image generation", "rangetrace", n.render_images, md);
  time_row(n, "Noise", "addnoise", 0, md);
  time_row(n, "Local surface fitting", "fitvox", 0, md);
  time_row(n, "Surface reconstruction", "cocone", 0, md);
  time_row(n, "Segmentation", "ncut", 0, md);
  time_row(n, "Recognition", "gmatch", 0, md);
  md << "| **all stages** | | | **" << hms(n.total_seconds) << "** | **"
     << cpu_cell(hms(n.total_cpu_seconds), n.total_cpu_runs, n.total_runs) << "** | | | | 11:54 |\n";
  if (n.stages.at("verify").runs > 0) time_row(n, "Verification (not in the total)", "verify", 0, md);
  md << "\n";
  return md.str();
}

std::string closing_markdown(const Inputs& in) {
  std::ostringstream md;
  if (!in.figures.empty()) {
    md << "## Figures\n\n";
    for (const auto& f : in.figures) md << "![" << f << "](" << f << ")\n\n";
  }
  md << "## Reproduce\n\n    make -f Makefile.experiments all -j2\n\nArtifacts per trial: "
        "`out/<object>/<scene>/noise-<mm>/"
        "{scan.pcd,samples.pcd,mesh.ply,segments.json,segments.ply,match.json,verdict.json}` "
        "(open the PLY files in MeshLab; `pcd2ply` converts the PCD files). Decisions behind every "
        "default: `docs/decisions.md`.\n";
  return md.str();
}

}  // namespace

Outputs render(const Inputs& in, const Params& p, const Numbers& n) {
  Outputs out;
  out.markdown = rates_markdown(in, n) + scene_split_markdown(in, n) + ablations_markdown(in, n) +
                 areas_markdown(p, n) + verify_markdown(in, n.verify) + failures_markdown(p, n) +
                 per_object_markdown(in, n) + times_markdown(n) + closing_markdown(in);
  out.cases_csv = cases_csv(in, n);
  out.scores_csv = scores_csv(in, n);
  out.times_csv = times_csv(n);
  out.areas_csv = areas_csv(n);
  out.verdicts_csv = verdicts_csv(in, n.verify);
  return out;
}

std::string rate_ci_units(int k, int n, double units) {
  if (n <= 0) return "–";
  const common::Interval w = common::wilson_effective(static_cast<double>(k) / n, units);
  return std::to_string(k) + "/" + std::to_string(n) + " = " + fmt("%.1f", 100.0 * k / n) + "% [" +
         fmt("%.1f", 100 * w.lo) + ", " + fmt("%.1f", 100 * w.hi) + "]";
}

}  // namespace canopy::report
