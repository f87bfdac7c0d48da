// score: detections.json of one or many tiles against their truth.json -> precision, recall,
// F1, false alarms per hectare, precision-recall curve, identification, pose errors and
// recognition against canopy cover and noise (JSON + CSV tables).
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/documents/tile_list.h"
#include "canopy/documents/model_classes.h"
#include "score/score.h"

using namespace canopy;

namespace {

// Comma-separated numbers; their range is checked by score::validate.
std::vector<double> parse_bins(const std::string& s) {
  std::vector<double> edges;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) { used = 0; }
    if (used == 0 || used != item.size() || !std::isfinite(v)) {
      throw common::UsageError("--cover-bins: '" + item + "' is not a number");
    }
    edges.push_back(v);
  }
  return edges;
}

score::Tile load(const std::string& detections, const std::string& truth, double noise,
                 const std::string& cover) {
  score::Tile t;
  t.detections = score::parse_detections(common::read_file(detections), detections);
  t.truth = score::parse_truth(common::read_file(truth), truth);
  t.noise_mm = noise;
  t.cover = cover;
  score::check_same_tile(t);
  return t;
}

// The tile list (documents/tile_list.h), each tile's files read.
std::vector<score::Tile> load_manifest(const std::string& path) {
  std::vector<score::Tile> tiles;
  for (const documents::TileListEntry& e : documents::parse_tile_list(common::read_file(path), path))
    tiles.push_back(load(e.detections, e.truth, e.noise_mm, e.cover));
  return tiles;
}

// The command line: one tile (--detections, --truth, --noise, --cover) or many (--tiles).
struct Options {
  std::string detections, truth, manifest, cover, bins = "0,0.25,0.5,0.75,1", out = "-", csv, model_classes;
  double noise = -1;
};

void bind(common::Tool& tool, Options& o, score::Params& p) {
  tool.add("-d,--detections", &o.detections, "one tile: its detections.json (canopy.detections v1)");
  tool.add("-t,--truth", &o.truth, "one tile: its truth.json (canopy.scene_truth v1)");
  tool.add("--noise", &o.noise, "one tile: its noise level in mm (-1 = not given)");
  tool.add("--cover", &o.cover, "one tile: its cover level label (light, medium, dense, ...)");
  tool.add("--tiles", &o.manifest, "many tiles: a file of lines DETECTIONS TRUTH [NOISE_MM [COVER]]");
  tool.add_length("--match-radius", &p.match_radius,
                  "a detection matches a true vehicle within this "
                  "horizontal distance of its centre");
  tool.add("--cover-bins", &o.bins, "edges of the per-vehicle canopy cover bins, comma-separated");
  tool.add("--flip-threshold", &p.flip_threshold, "heading error (degrees) counted as a flip");
  tool.add("--model-classes", &o.model_classes,
           "CSV 'model,class': the class of each model, given to true vehicles and model answers "
           "without one (e.g. share/models/classes.csv)");
  tool.add_output(&o.out, "score JSON (canopy.scene_score v1)");
  tool.add("--csv", &o.csv,
           "also write the tables as <PREFIX>summary.csv, pr.csv, models.csv, "
           "cover_bins.csv, reliability.csv, clutter.csv, matches.csv");
}

// The choice between one tile and a manifest, and the one tile's noise level.
void check_sources(const Options& o) {
  if (o.manifest.empty() == (o.detections.empty() && o.truth.empty())) {
    throw common::UsageError("give either --tiles or --detections with --truth");
  }
  if (o.manifest.empty() && (o.detections.empty() || o.truth.empty())) {
    throw common::UsageError("--detections and --truth go together");
  }
  if (!o.manifest.empty() && (o.noise != -1 || !o.cover.empty())) {
    throw common::UsageError("--noise and --cover are for one tile; the --tiles file gives them per tile");
  }
  if (!(o.noise == -1 || (o.noise >= 0 && o.noise < 1e6)))
    throw common::UsageError("--noise must be >= 0 (mm) or -1");
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("score",
                    "Scores detections.json against truth.json for one or many tiles: detection "
                    "precision/recall/F1, false alarms per hectare, a precision-recall curve, "
                    "identification, pose errors, recognition against canopy cover and noise.");
  tool.without_threads();
  score::Params p;
  Options o;
  bind(tool, o, p);
  return tool.run(argc, argv, [&] {
    check_sources(o);
    p.cover_bins = parse_bins(o.bins);
    score::validate(p);
    static const char* tables[] = {"summary",     "pr",      "models", "cover_bins",
                                   "reliability", "clutter", "matches"};
    common::OutputSet outputs;
    outputs.add(o.out, "-o");
    if (!o.csv.empty()) {
      for (const char* t : tables) outputs.add(o.csv + t + ".csv", "--csv");
    }
    score::Inputs in;
    in.tiles = o.manifest.empty()
                   ? std::vector<score::Tile>{load(o.detections, o.truth,
                                                   o.noise == -1 ? std::nan("") : o.noise, o.cover)}
                   : load_manifest(o.manifest);
    if (!o.model_classes.empty())
      score::apply_model_classes(
          in.tiles, documents::parse_model_classes(common::read_file(o.model_classes), o.model_classes));
    in.provenance = {"score", CANOPY_VERSION, tool.parameters(), {}};
    for (const auto& t : in.tiles) {
      in.provenance.inputs.push_back(t.detections.name);
      in.provenance.inputs.push_back(t.truth.name);
    }
    const documents::SceneScore result = score::score(in.tiles, p);
    outputs.set(o.out, documents::write_scene_score(result, in.provenance));
    if (!o.csv.empty()) {
      for (const char* t : tables) outputs.set(o.csv + t + ".csv", documents::scene_score_csv(result, t));
    }
    outputs.commit();
    common::log::info(score::summary_line(in.tiles.size(), result.summary.at(0)));
  });
}
