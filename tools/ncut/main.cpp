// ncut: PLY mesh -> JSON segment graph (+ PLY coloured by segment) by recursive normalized cuts.
#include <cstdio>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/json_io.h"
#include "canopy/formats/ply.h"
#include "ncut/ncut.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("ncut", "Segments a mesh into surface patches by recursive two-way "
                            "normalized cuts (thesis ch. 5) and writes the segment graph.", true);
  ncut::Params p;
  std::string in = "-", out = "-", colored, exponent = "linear", solver = "auto", pca = "surface";
  tool.add_input(&in, "mesh PLY (x y z, nx ny nz [computed from faces if absent], [label])");
  tool.add_output(&out, "segment graph JSON");
  tool.add_output("--colored", &colored, "also write the mesh with 'segment' and red/green/blue fields (PLY)");
  tool.add_angle("--sigma-n", &p.affinity.sigma_n, "normal-angle scale sigma_n of Eq. 5.11 (> 0)");
  tool.add("--anisotropy", &p.affinity.anisotropy, "E of Eq. 5.8: weight of the normal offset (>= 1)");
  tool.add_length("--radius", &p.affinity.radius, "r: distance scale of Eq. 5.11 and affinity cut-off");
  tool.add("--exponent", &exponent, "'squared' (Eq. 5.1 form) or 'linear' (Eq. 5.11 as printed, "
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
  tool.add("--solver", &solver, "eigensolver: auto, dense, lanczos, shift-invert");
  tool.add("--tolerance", &p.cut.tolerance, "Spectra relative Ritz tolerance (0, 1e-3]");
  tool.add("--max-restarts", &p.cut.max_restarts, "Spectra restart limit (>= 1)");
  tool.add("--ncv", &p.cut.ncv, "Lanczos basis size (>= 3)");
  tool.add("--fallback", &p.cut.fallback,
           "when an eigensolve does not converge, retry with other settings/solvers (true/false)");
  tool.add("--pca", &pca, "segment PCA/centroid weighting: 'surface' (area) or 'vertices'");
  return tool.run(argc, argv, [&] {
    const auto& a = p.affinity;
    const auto& s = p.sparsify;
    // Each option's valid range; lengths beyond [1 mm, 100 m] are not a mesh of a vehicle.
    auto need = [](bool ok, const std::string& rule) {
      if (!ok) throw common::UsageError(rule);
    };
    const double deg = 3.14159265358979323846 / 180;
    need(a.sigma_n > 0 && a.sigma_n <= 180 * deg, "--sigma-n must be in (0, 180] deg");
    need(a.anisotropy >= 1 && a.anisotropy <= 1e6, "--anisotropy must be in [1, 1e6]");
    need(a.radius >= 1e-3 && a.radius <= 100, "--radius must be in [1mm, 100m]");
    need(s.dense_radius >= 0 && s.dense_radius <= 100, "--dense-radius must be in [0, 100m]");
    need(s.keep_fraction >= 0 && s.keep_fraction <= 1, "--keep-fraction must be in [0, 1]");
    need(s.min_affinity >= 0 && s.min_affinity < 1, "--min-affinity must be in [0, 1)");
    need(s.mesh_edge_floor >= 0 && s.mesh_edge_floor <= 0.1, "--mesh-edge-floor must be in [0, 0.1]");
    need(p.cut.max_ncut > 0, "--max-ncut must be > 0");
    need(p.cut.min_segment >= 1, "--min-segment must be >= 1");
    need(p.cut.tolerance > 0 && p.cut.tolerance <= 1e-3, "--tolerance must be in (0, 1e-3]");
    need(p.cut.max_restarts >= 1, "--max-restarts must be >= 1");
    need(p.cut.ncv >= 3, "--ncv must be >= 3");
    need(exponent == "squared" || exponent == "linear", "--exponent: 'squared' or 'linear'");
    need(pca == "surface" || pca == "vertices", "--pca: 'surface' or 'vertices'");
    need(solver == "auto" || solver == "dense" || solver == "lanczos" || solver == "shift-invert",
         "--solver: auto, dense, lanczos or shift-invert");
    // Both outputs are written together at the end, or neither (checked now, before the work).
    common::OutputSet outputs;
    outputs.add(out, "-o");
    if (!colored.empty()) outputs.add(colored, "--colored");
    p.affinity.exponent = exponent == "squared" ? ncut::Exponent::kSquared : ncut::Exponent::kLinear;
    p.pca = pca == "surface" ? ncut::PcaWeighting::kSurface : ncut::PcaWeighting::kVertices;
    p.cut.solver = solver == "dense" ? ncut::Solver::kDense
                   : solver == "lanczos" ? ncut::Solver::kLanczos
                   : solver == "shift-invert" ? ncut::Solver::kShiftInvert : ncut::Solver::kAuto;
    p.sparsify.radius = p.affinity.radius;
    p.sparsify.seed = tool.seed();

    common::log::Phase read("read");
    const formats::Mesh mesh = formats::read_ply(in);
    const ncut::Input input = ncut::input_from_mesh(mesh, common::display_name(in));
    read.done(std::to_string(input.points.size()) + " vertices, " +
              std::to_string(input.faces.size()) + " faces");
    if (input.normals.empty()) {
      common::log::info(common::display_name(in) + ": no normals; using area-weighted face normals");
    }
    common::log::Phase seg("segment");
    const ncut::Result r = ncut::run(input, p);
    const auto& g = r.stats.graph;
    const auto& c = r.stats.cut;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%zu segments; graph %zu edges (%zu forced mesh edges) %.3f s; %d components, "
                  "%d splits, %d eigensolves (%d dense, %d lanczos, %d shift-invert, %d fallbacks), "
                  "%lld matvecs, max residual %.1e, %.3f s",
                  r.graph.segments.size(), g.edges, g.mesh_edges_forced, r.stats.seconds_graph,
                  c.components, c.splits, c.solves, c.dense_solves, c.lanczos_solves,
                  c.shift_invert_solves, c.fallbacks, c.matvecs, c.max_residual, r.stats.seconds_cut);
    seg.done(buf);
    if (r.stats.vertices_without_normal > 0) {
      common::log::warn(std::to_string(r.stats.vertices_without_normal) +
                        " vertices have no normal (no input normal, no face)");
    }

    formats::SegmentGraph graph = r.graph;
    graph.provenance = {"ncut", CANOPY_VERSION, tool.parameters(), {in}};
    graph.mesh = in;
    if (!colored.empty()) {
      formats::Mesh cm = ncut::colored_mesh(mesh, r.segment);
      cm.vertices.comments.push_back("ncut (canopy) " CANOPY_VERSION);
      for (const auto& [name, value] : tool.parameters()) {
        cm.vertices.comments.push_back("parameter " + name + " = " + value);
      }
      cm.vertices.comments.push_back("input " + in);
      outputs.set(colored, formats::serialize_ply(cm));
    }
    outputs.set(out, formats::serialize_segment_graph(graph));
    outputs.commit();
    common::log::info("wrote " + std::to_string(graph.segments.size()) + " segments to " +
                      common::display_name(out, true) +
                      (colored.empty() ? "" : " and " + common::display_name(colored, true)));
  });
}
