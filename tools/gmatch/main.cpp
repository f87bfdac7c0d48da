// gmatch: rank the models of a modelbase by how well an object's segment graph matches them.
#include <algorithm>
#include <cstdio>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"
#include "gmatch/gmatch.h"

namespace cm = canopy::common;
namespace gm = canopy::gmatch;

namespace {

// Measured on a 1000-entry modelbase (docs/decisions/gmatch.md §9).
constexpr int kDefaultPrefilter = 64;

// The options given as text (choices) and the files.
struct Options {
  std::string in = "-", out = "-", modelbase, orientation = "relative", normals = "axial", error = "bounded",
              coverage = "both", format = "json", prefilter_by = "coarse";
  bool no_bound = false;
};

// The numeric options of the search and its weights.
void bind_numbers(cm::Tool& tool, gm::Params& p) {
  tool.add("-X,--max-segments", &p.max_segments, "object segments matched, largest area first");
  tool.add("-B,--branches", &p.branches, "best branches recursed on per tree node");
  tool.add("--area-factor", &p.area_factor, "f_a: 100 f_a % area change = one unary unit (>0)");
  tool.add("--thickness-weight", &p.thickness_weight, "w_t: weight of the thickness difference");
  tool.add("--elongation-weight", &p.elongation_weight, "w_e: weight of the elongation term");
  tool.add("--unary-threshold", &p.unary_threshold, "prune a pair when E_U exceeds this [0,1]");
  tool.add("--orientation-threshold", &p.orientation_threshold, "prune when a pairwise E_O exceeds this");
  tool.add("--distance-threshold", &p.distance_threshold, "prune when a pairwise d_R exceeds this");
  tool.add("--exp-unary", &p.exp_unary, "e_u: exponent of the unary term (>=0)");
  tool.add("--exp-orientation", &p.exp_orientation, "e_o: exponent of the orientation term");
  tool.add("--exp-distance", &p.exp_distance, "e_d: exponent of the centroid-distance term");
  tool.add("--exp-area", &p.exp_area, "e_a: exponent of the area-coverage term");
}

// The forms of the error terms and the output format (text choices).
void bind_choices(cm::Tool& tool, Options& o) {
  tool.add("--orientation", &o.orientation,
           "relative: angle(n_si,n_sj) vs angle(n_mi,n_mj), "
           "heading-invariant; thesis: Eq. 6.7 as printed")
      ->check(CLI::IsMember({"relative", "thesis"}));
  tool.add("--normals", &o.normals, "axial: n and -n are the same; signed: normal signs count")
      ->check(CLI::IsMember({"axial", "signed"}));
  tool.add("--error", &o.error,
           "bounded: S = product of (1 - mean errors) and coverage; "
           "thesis: Eq. 6.12 as printed")
      ->check(CLI::IsMember({"bounded", "thesis"}));
  tool.add("--coverage", &o.coverage,
           "bounded form's area coverage: both = model and object side (geometric mean), "
           "model = model side only (before issue 15)")
      ->check(CLI::IsMember({"both", "model"}));
  tool.add("--format", &o.format, "output: json (canopy.match_result) or table (one line per model)")
      ->check(CLI::IsMember({"json", "table"}));
}

// The search limits: node budget, prefilter, branch and bound.
void bind_search(cm::Tool& tool, gm::Params& p, Options& o) {
  tool.add("--max-nodes", &p.max_nodes, "tree nodes expanded per model before stopping (0 = no limit)");
  p.prefilter = kDefaultPrefilter;
  tool.add("--prefilter", &p.prefilter,
           "full search on the K models nearest by graph summaries only (0 = every model; "
           "K >= the modelbase size: every model, same output as 0)");
  tool.add("--prefilter-by", &o.prefilter_by,
           "coarse: the search on the object's --coarse-segments largest segments; "
           "summary: footprint, area and normal-tilt summaries")
      ->check(CLI::IsMember({"coarse", "summary"}));
  tool.add("--coarse-segments", &p.coarse_segments,
           "object segments (largest first) of the coarse prefilter search");
  tool.add_flag("--no-bound", &o.no_bound, "disable branch and bound (same result, slower)")
      ->default_str("false");
}

// The text choices into the parameters.
void apply_choices(const Options& o, gm::Params* p) {
  p->orientation = o.orientation == "thesis" ? gm::OrientationForm::kThesis : gm::OrientationForm::kRelative;
  p->normals = o.normals == "signed" ? gm::NormalSign::kSigned : gm::NormalSign::kAxial;
  p->error = o.error == "thesis" ? gm::ErrorForm::kThesis : gm::ErrorForm::kBounded;
  p->bound = !o.no_bound;
  p->coverage = o.coverage == "model" ? gm::Coverage::kModel : gm::Coverage::kBoth;
  p->prefilter_by = o.prefilter_by == "summary" ? gm::PrefilterBy::kSummary : gm::PrefilterBy::kCoarse;
}

// The match phase's INFO line: segments, models searched, tree nodes, stopped searches.
std::string summary(const gm::Outputs& result, std::size_t object_segments, std::size_t models) {
  std::int64_t nodes = 0, truncated = 0;
  for (const auto& s : result.stats) {
    nodes += s.nodes;
    truncated += s.truncated ? 1 : 0;
  }
  return std::to_string(object_segments) + " object segments against " +
         (result.searched < static_cast<int>(models)
              ? std::to_string(result.searched) + " of " + std::to_string(models) + " models (prefilter)"
              : std::to_string(models) + " models") +
         ", " + std::to_string(nodes) + " tree nodes" +
         (truncated ? ", " + std::to_string(truncated) + " searches stopped at --max-nodes" : "");
}

// The prefilter's options are recorded only when it acted (kept fewer models than the
// modelbase has): otherwise the output is exactly that of a run without it, byte for byte.
std::vector<std::pair<std::string, std::string>> recorded(const cm::Tool& tool, bool prefiltered) {
  auto parameters = tool.parameters();
  if (!prefiltered) {
    parameters.erase(std::remove_if(parameters.begin(), parameters.end(),
                                    [](const auto& kv) {
                                      return kv.first == "prefilter" || kv.first == "prefilter-by" ||
                                             kv.first == "coarse-segments";
                                    }),
                     parameters.end());
  }
  return parameters;
}

}  // namespace

int main(int argc, char** argv) {
  cm::Tool tool("gmatch",
                "Inexact partial graph matching of a segment graph against a modelbase "
                "(thesis ch. 6). Writes a canopy.match_result JSON ranking every model.");
  gm::Params p;
  Options o;
  tool.add_input(&o.in, "object segment graph JSON");
  tool.add_output(&o.out, "match result JSON");
  tool.add("--modelbase", &o.modelbase, "directory of <model>.json segment graphs")->required();
  bind_numbers(tool, p);
  bind_choices(tool, o);
  bind_search(tool, p, o);

  return tool.run(argc, argv, [&] {
    apply_choices(o, &p);
    p.threads = tool.threads();
    gm::validate(p);

    const auto object = canopy::documents::read_segment_graph(o.in);
    gm::validate_graph(object, cm::display_name(o.in));
    const auto models = gm::read_modelbase(o.modelbase);

    cm::log::Phase phase("match");
    gm::Outputs result = gm::run(p, {&object, &models});
    phase.done(summary(result, object.segments.size(), models.size()));

    auto& r = result.result;
    r.provenance = {"gmatch",
                    CANOPY_VERSION,
                    recorded(tool, result.searched != static_cast<int>(models.size())),
                    {o.in, o.modelbase}};
    r.object = o.in;
    if (o.format == "table") {
      cm::write_file_atomic(o.out, gm::format_table(r, gm::object_name(o.in)));
    } else {
      canopy::documents::write_match_result(r, o.out);
    }

    const auto& best = r.models.front();
    char line[256];
    std::snprintf(line, sizeof line, "%s: best %s: score %.3f, entropy %.3f bits over %zu models",
                  gm::object_name(o.in).c_str(), best.model.c_str(), best.score, r.entropy, r.models.size());
    cm::log::info(line);
  });
}
