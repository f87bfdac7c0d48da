// gmatch at scale (issue 17): a 1000-entry modelbase built from real segment graphs, and the
// time, memory and accuracy of matching one candidate against it with and without the
// prefilter (docs/decisions/gmatch.md §9).
//
//   bench_gmatch_scale build OUT_DIR GRAPH...      writes OUT_DIR/<entry>.json (1000 entries)
//   bench_gmatch_scale run MODELBASE OBJECT=GRAPH...   load time, RSS, ms/query and rank-1
//                                                       for --prefilter 0 and several K
//
// Entries: every input graph whose file stem is not "segments" enters under its own stem (the
// real models, e.g. out/modelbase/sedan.json -> "sedan"); the rest of the 1000 are scaled
// copies "<source object>-s<NNNN>" of the inputs taken round-robin. A scaled copy keeps only the
// segments labelled target (a trial graph's foliage is not part of a make) and applies a
// per-entry anisotropic scaling S = diag(sx, sy, sz), each factor log-uniform in [0.7, 1.4]
// (seeded): centroid -> S c, normal -> S^-1 n / |S^-1 n| (the normal of a scaled plane), area ->
// area det(S) |S^-1 n| (the area of a scaled planar patch). Thickness, elongation and radii
// are kept (the scaling changes them only slightly for the moderate factors used).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "canopy/common/rng.h"
#include "canopy/formats/labels.h"
#include "canopy/documents/segment_graph.h"
#include "gmatch/gmatch.h"

namespace fs = std::filesystem;
namespace gm = canopy::gmatch;
using canopy::documents::SegmentGraph;

namespace {

constexpr int kEntries = 1000;

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// The object an input graph shows: the stem for a model file, else the directory three levels
// up (out/<object>/<scene>/noise-<mm>/segments.json).
std::string source_object(const fs::path& p) {
  if (p.stem() != "segments") return p.stem().string();
  return p.parent_path().parent_path().parent_path().filename().string();
}

SegmentGraph scaled(const SegmentGraph& g, canopy::common::Rng& rng) {
  double s[3];
  for (double& f : s) f = std::exp(rng.uniform(std::log(0.7), std::log(1.4)));
  const double det = s[0] * s[1] * s[2];
  SegmentGraph out;
  out.provenance = g.provenance;
  out.mesh = g.mesh;
  for (auto seg : g.segments) {
    if (seg.label != canopy::formats::kLabelTarget) continue;
    double n[3], len = 0;
    for (int i = 0; i < 3; ++i) {
      n[i] = seg.normal[i] / s[i];
      len += n[i] * n[i];
    }
    len = std::sqrt(len);
    seg.area *= det * len;
    for (int i = 0; i < 3; ++i) {
      seg.normal[i] = n[i] / len;
      seg.centroid[i] *= s[i];
    }
    out.segments.push_back(seg);
  }
  return out;
}

int build(const fs::path& dir, const std::vector<fs::path>& inputs) {
  fs::create_directories(dir);
  std::vector<std::pair<std::string, SegmentGraph>> sources;
  int written = 0;
  for (const auto& p : inputs) {
    SegmentGraph g = canopy::documents::read_segment_graph(p.string());
    if (p.stem() != "segments") {
      canopy::documents::write_segment_graph(g, (dir / (p.stem().string() + ".json")).string());
      ++written;
    }
    sources.emplace_back(source_object(p), std::move(g));
  }
  canopy::common::Rng rng(17);
  for (int i = 0; written < kEntries; ++i) {
    const auto& [object, g] = sources[i % sources.size()];
    SegmentGraph s = scaled(g, rng);
    if (s.segments.empty()) continue;
    char name[64];
    std::snprintf(name, sizeof name, "%s-s%04d.json", object.c_str(), i);
    canopy::documents::write_segment_graph(s, (dir / name).string());
    ++written;
  }
  std::printf("wrote %d entries to %s from %zu graphs\n", written, dir.c_str(), inputs.size());
  return 0;
}

const gm::PrefilterBy kBys[2] = {gm::PrefilterBy::kCoarse, gm::PrefilterBy::kSummary};

struct Row {
  double ms = 0, worst = 0;
  int exact = 0, source = 0, agree = 0, identical = 0;
};
using Rows = std::map<std::pair<int, int>, Row>;  // (by, K)

// One query through every prefilter setting (off first); returns the result without prefilter.
gm::Outputs measure_query(const SegmentGraph& q, const std::string& object,
                          const std::vector<gm::Model>& models, Rows* rows) {
  const std::vector<int> ks = {0, 8, 16, 32, 64, 128, 256};
  gm::Outputs off;
  for (int b = 0; b < 2; ++b) {
    for (int k : ks) {
      if (b == 1 && k == 0) continue;
      gm::Params p;
      p.prefilter = k;
      p.prefilter_by = kBys[b];
      const double t = now_ms();
      gm::Outputs out = gm::run(p, {&q, &models});
      const double ms = now_ms() - t;
      Row& r = (*rows)[{b, k}];
      r.ms += ms;
      r.worst = std::max(r.worst, ms);
      const std::string& best = out.result.models.front().model;
      r.exact += best == object;
      r.source += best.substr(0, best.find('-')) == object;
      if (k == 0) off = out;
      r.agree += best == off.result.models.front().model;
      // The first five of the ranking (model and score) as without the prefilter.
      bool same = true;
      for (std::size_t i = 0; i < 5 && i < off.result.models.size(); ++i) {
        same = same && i < out.result.models.size() &&
               out.result.models[i].model == off.result.models[i].model &&
               out.result.models[i].score == off.result.models[i].score;
      }
      r.identical += same;
    }
  }
  return off;
}

// Where the full search's winner (and the true model) stand in the coarse prefilter's order;
// prints the query's line, returns the winner's rank (1-based).
int winner_rank_of(const SegmentGraph& q, const std::string& object, const fs::path& path,
                   const std::vector<gm::Model>& models, const gm::Outputs& off) {
  gm::Params cp;
  cp.max_segments = cp.coarse_segments;
  std::vector<std::pair<double, std::string>> d;
  for (const auto& m : models) d.emplace_back(-gm::match_model(q, m, cp).score, m.name);
  std::sort(d.begin(), d.end());
  const std::string& w = off.result.models.front().model;
  int rank = 0;
  while (d[rank].second != w) ++rank;
  int true_rank = 0;
  while (d[true_rank].second != object) ++true_rank;
  std::printf(
      "  %-40s true %-10s full-search winner %-18s prefilter rank of winner %4d, of "
      "true model %4d\n",
      path.parent_path().string().c_str(), object.c_str(), w.c_str(), rank + 1, true_rank + 1);
  std::fflush(stdout);
  return rank + 1;
}

void print_rows(const Rows& rows, double n) {
  std::printf(
      "\n| prefilter | K | ms/query | worst ms | rank-1 exact | rank-1 source object | "
      "same answer as off | "
      "same top 5 as off |\n|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& [key, r] : rows) {
    const int k = key.second;
    std::printf("| %s | %d | %.0f | %.0f | %d/%.0f | %d/%.0f | %d/%.0f | %d/%.0f |\n",
                k == 0 ? "off" : gm::to_string(kBys[key.first]), k, r.ms / n, r.worst, r.exact, n, r.source,
                n, r.agree, n, r.identical, n);
  }
}

int run(const std::string& modelbase, const std::vector<std::pair<std::string, fs::path>>& queries) {
  const double rss0 = peak_rss_mb();
  double t0 = now_ms();
  const std::vector<gm::Model> models = gm::read_modelbase(modelbase);
  const double load_ms = now_ms() - t0;
  const double rss1 = peak_rss_mb();
  std::size_t segs = 0;
  for (const auto& m : models) segs += m.graph.segments.size();
  t0 = now_ms();
  for (const auto& m : models) (void)gm::summarize(m.graph, 15);
  const double summary_ms = now_ms() - t0;
  std::printf(
      "modelbase: %zu entries, %zu segments; load %.0f ms, peak RSS %.0f MB -> %.0f MB; "
      "summaries of all entries %.2f ms\n",
      models.size(), segs, load_ms, rss0, rss1, summary_ms);

  Rows rows;
  std::vector<int> winner_rank;  // rank of the full search's winner in prefilter order
  for (const auto& [object, path] : queries) {
    const SegmentGraph q = canopy::documents::read_segment_graph(path.string());
    const gm::Outputs off = measure_query(q, object, models, &rows);
    winner_rank.push_back(winner_rank_of(q, object, path, models, off));
  }
  print_rows(rows, static_cast<double>(queries.size()));
  std::sort(winner_rank.begin(), winner_rank.end());
  std::printf("\nprefilter rank of the full search's winner: median %d, max %d\n",
              winner_rank[winner_rank.size() / 2], winner_rank.back());
  std::printf("peak RSS %.0f MB\n", peak_rss_mb());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage =
      "usage: bench_gmatch_scale build OUT_DIR GRAPH... | run MODELBASE OBJECT=GRAPH...\n";
  if (argc < 4) {
    std::fputs(usage.c_str(), stderr);
    return 2;
  }
  const std::string mode = argv[1];
  if (mode == "build") {
    std::vector<fs::path> inputs(argv + 3, argv + argc);
    return build(argv[2], inputs);
  }
  if (mode == "run") {
    std::vector<std::pair<std::string, fs::path>> queries;
    for (int i = 3; i < argc; ++i) {
      const std::string a = argv[i];
      const auto eq = a.find('=');
      if (eq == std::string::npos) {
        std::fputs(usage.c_str(), stderr);
        return 2;
      }
      queries.emplace_back(a.substr(0, eq), a.substr(eq + 1));
    }
    return run(argv[2], queries);
  }
  std::fputs(usage.c_str(), stderr);
  return 2;
}
