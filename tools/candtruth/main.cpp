// candtruth: the ground truth of detect's candidates from the labelled tile and detect's index
// -> candidate_truth.json (canopy.candidate_truth). Outside the recogniser's path (issue 30).
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "candtruth/candtruth.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("candtruth",
                    "Ground truth of detect's candidates: which labelled vehicle each candidate's "
                    "crop holds (coverage, purity) and which candidates hold each vehicle, from the "
                    "labelled tile (rangetrace) and detect's index.json.");
  tool.without_threads();
  candtruth::Params p;
  std::string index, tile, out = "-";
  double margin = 0;
  tool.add_input(&index, "candidates index.json (canopy.candidates v1 or v2)");
  tool.add("--tile", &tile, "the labelled tile detect read (PCD, PLY, LAS or LAZ)")->required();
  tool.add_output(&out, "candidate_truth.json");
  CLI::Option* margin_opt =
      tool.add_length("--margin", &margin, "crop margin (detect's --margin); default: the index's")
          ->default_str("");
  tool.add("--label-field", &p.label_field, "ground-truth class field (1 = vehicle, 3 = ground), if present");
  tool.add("--instance-field", &p.instance_field, "ground-truth vehicle id field (0 = none)");
  return tool.run(argc, argv, [&] {
    if (margin_opt->count() > 0) p.margin = margin;
    candtruth::validate(p);
    common::log::Phase phase("candtruth");
    candtruth::Inputs in;
    in.index = documents::read_candidates_file(index);
    in.index_name = index;
    const formats::PointCloud cloud = formats::read_points(tile, "candtruth");
    in.tile = &cloud;
    in.tile_name = tile;
    const candtruth::Outputs r = candtruth::run(p, in);
    const formats::Provenance prov{"candtruth", CANOPY_VERSION, tool.parameters(), {index, tile}};
    common::write_file_atomic(out, documents::write_candidate_truth(r, prov));
    std::size_t covered = 0;
    for (const auto& it : r.instances) covered += !it.candidates.empty();
    phase.done(std::to_string(r.candidates.size()) + " candidates; " + std::to_string(covered) + " of " +
               std::to_string(r.instances.size()) + " labelled vehicles covered by a candidate");
  });
}
