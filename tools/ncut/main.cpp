// ncut: PLY mesh -> JSON segment graph (+ PLY coloured by segment) by recursive normalized cuts.
#include <cstdio>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/provenance.h"
#include "ncut/ncut.h"

using namespace canopy;

namespace {

// The options given as text: files, and the choices that become the stage's enums.
struct Cli {
  std::string in = "-", out = "-", colored, exponent = "linear", solver = "auto", pca = "surface";
};

void bind_options(common::Tool& tool, ncut::Params& p, Cli& c) {
  tool.add_input(&c.in, "mesh PLY (x y z, nx ny nz [computed from faces if absent], [label])");
  tool.add_output(&c.out, "segment graph JSON");
  tool.add_output("--colored", &c.colored,
                  "also write the mesh with 'segment' and red/green/blue fields (PLY)");
  tool.add_angle("--sigma-n", &p.affinity.sigma_n, "normal-angle scale sigma_n of Eq. 5.11 (> 0)");
  tool.add("--anisotropy", &p.affinity.anisotropy, "E of Eq. 5.8: weight of the normal offset (>= 1)");
  tool.add_length("--radius", &p.affinity.radius, "r: distance scale of Eq. 5.11 and affinity cut-off");
  tool.add("--exponent", &c.exponent,
           "'squared' (Eq. 5.1 form) or 'linear' (Eq. 5.11 as printed, "
           "lengths in mm)");
  tool.add_length("--dense-radius", &p.sparsify.dense_radius,
                  "beyond this distance keep only --keep-fraction of the affinities");
  tool.add("--keep-fraction", &p.sparsify.keep_fraction, "random share kept beyond --dense-radius [0, 1]");
  tool.add("--min-affinity", &p.sparsify.min_affinity, "drop affinities below this [0, 1)");
  tool.add("--keep-mesh-edges", &p.sparsify.keep_mesh_edges,
           "always keep the affinities of mesh neighbours (true/false)");
  tool.add("--mesh-edge-floor", &p.sparsify.mesh_edge_floor,
           "lower bound of kept mesh-neighbour affinities, for a numerically connected graph [0, 0.1]");
  tool.add("--max-ncut", &p.cut.max_ncut, "split a part only while its best Ncut is below this (> 0)");
  tool.add("--min-segment", &p.cut.min_segment, "no cut leaves fewer vertices on a side (>= 1)");
  tool.add("--solver", &c.solver, "eigensolver: auto, dense, lanczos, shift-invert");
  tool.add("--tolerance", &p.cut.tolerance, "Spectra relative Ritz tolerance (0, 1e-3]");
  tool.add("--max-restarts", &p.cut.max_restarts, "Spectra restart limit (>= 1)");
  tool.add("--ncv", &p.cut.ncv, "Lanczos basis size (>= 3)");
  tool.add("--fallback", &p.cut.fallback,
           "when an eigensolve does not converge, retry with other settings/solvers (true/false)");
  tool.add("--pca", &c.pca, "segment PCA/centroid weighting: 'surface' (area) or 'vertices'");
}

// The text choices as the stage's enums (usage errors name the option).
void apply_choices(const Cli& c, ncut::Params& p) {
  auto need = [](bool ok, const std::string& rule) {
    if (!ok) throw common::UsageError(rule);
  };
  need(c.exponent == "squared" || c.exponent == "linear", "--exponent: 'squared' or 'linear'");
  need(c.pca == "surface" || c.pca == "vertices", "--pca: 'surface' or 'vertices'");
  need(c.solver == "auto" || c.solver == "dense" || c.solver == "lanczos" || c.solver == "shift-invert",
       "--solver: auto, dense, lanczos or shift-invert");
  p.affinity.exponent = c.exponent == "squared" ? ncut::Exponent::kSquared : ncut::Exponent::kLinear;
  p.pca = c.pca == "surface" ? ncut::PcaWeighting::kSurface : ncut::PcaWeighting::kVertices;
  p.cut.solver = c.solver == "dense"          ? ncut::Solver::kDense
                 : c.solver == "lanczos"      ? ncut::Solver::kLanczos
                 : c.solver == "shift-invert" ? ncut::Solver::kShiftInvert
                                              : ncut::Solver::kAuto;
}

std::string summary(const ncut::Result& r) {
  const auto& g = r.stats.graph;
  const auto& c = r.stats.cut;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "%zu segments; graph %zu edges (%zu forced mesh edges) %.3f s; %d components, "
                "%d splits, %d eigensolves (%d dense, %d lanczos, %d shift-invert, %d fallbacks), "
                "%lld matvecs, max residual %.1e, %.3f s",
                r.graph.segments.size(), g.edges, g.mesh_edges_forced, r.stats.seconds_graph, c.components,
                c.splits, c.solves, c.dense_solves, c.lanczos_solves, c.shift_invert_solves, c.fallbacks,
                c.matvecs, c.max_residual, r.stats.seconds_cut);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("ncut",
                    "Segments a mesh into surface patches by recursive two-way "
                    "normalized cuts (thesis ch. 5) and writes the segment graph.",
                    true);
  tool.without_threads();
  ncut::Params p;
  Cli c;
  bind_options(tool, p, c);
  return tool.run(argc, argv, [&] {
    apply_choices(c, p);
    p.sparsify.seed = tool.seed();
    ncut::validate(p);
    // Both outputs are written together at the end, or neither (checked now, before the work).
    common::OutputSet outputs;
    outputs.add(c.out, "-o");
    if (!c.colored.empty()) outputs.add(c.colored, "--colored");

    common::log::Phase read("read");
    const formats::Mesh mesh = formats::read_ply(c.in);
    const ncut::Inputs input = ncut::input_from_mesh(mesh, common::display_name(c.in));
    read.done(std::to_string(input.points.size()) + " vertices, " + std::to_string(input.faces.size()) +
              " faces");
    if (input.normals.empty()) {
      common::log::info(common::display_name(c.in) + ": no normals; using area-weighted face normals");
    }
    common::log::Phase seg("segment");
    const ncut::Result r = common::naming_input(c.in, [&] { return ncut::run(p, input); });
    ncut::check_segments(r, common::display_name(c.in));
    seg.done(summary(r));
    if (r.stats.vertices_without_normal > 0) {
      common::log::warn(std::to_string(r.stats.vertices_without_normal) +
                        " vertices have no normal (no input normal, no face)");
    }

    documents::SegmentGraph graph = r.graph;
    graph.provenance = {"ncut", CANOPY_VERSION, tool.parameters(), {c.in}};
    graph.mesh = c.in;
    if (!c.colored.empty()) {
      formats::Mesh cm = ncut::colored_mesh(mesh, r.segment);
      const std::vector<std::string> provenance = formats::provenance_comments(graph.provenance);
      cm.vertices.comments.insert(cm.vertices.comments.end(), provenance.begin(), provenance.end());
      outputs.set(c.colored, formats::serialize_ply(cm));
    }
    outputs.set(c.out, documents::serialize_segment_graph(graph));
    outputs.commit();
    common::log::info("wrote " + std::to_string(graph.segments.size()) + " segments to " +
                      common::display_name(c.out, true) +
                      (c.colored.empty() ? "" : " and " + common::display_name(c.colored, true)));
  });
}
