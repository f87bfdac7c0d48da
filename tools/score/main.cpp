// score: detections.json of one or many tiles against their truth.json -> precision, recall,
// F1, false alarms per hectare, precision-recall curve, identification, pose errors and
// recognition against canopy cover and noise (JSON + CSV tables).
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "score/score.h"

using namespace canopy;

namespace {

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
  if (edges.size() < 2) throw common::UsageError("--cover-bins needs at least two edges");
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (edges[i] < 0 || edges[i] > 1 || (i && edges[i] <= edges[i - 1])) {
      throw common::UsageError("--cover-bins: edges must rise strictly within [0, 1]");
    }
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
  return t;
}

// The manifest: one tile a line, "DETECTIONS TRUTH [NOISE_MM [COVER]]", '#' comments; paths as
// given (relative to the working directory).
std::vector<score::Tile> load_manifest(const std::string& path) {
  std::stringstream in(common::read_file(path));
  std::vector<score::Tile> tiles;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::stringstream ls(line);
    std::vector<std::string> words;
    for (std::string w; ls >> w;) words.push_back(w);
    if (words.empty()) continue;
    const std::string where = "line " + std::to_string(n);
    if (words.size() < 2 || words.size() > 4) {
      throw common::DataError(path, where + ": expected DETECTIONS TRUTH [NOISE_MM [COVER]]");
    }
    double noise = std::nan("");
    if (words.size() >= 3) {
      std::size_t used = 0;
      try {
        noise = std::stod(words[2], &used);
      } catch (const std::exception&) { used = 0; }
      if (used != words[2].size() || !(noise >= 0 && noise < 1e6)) {
        throw common::DataError(path, where + ": noise '" + words[2] + "' is not a number of millimetres");
      }
    }
    if (tiles.size() >= 100000) throw common::DataError(path, "more than 100000 tiles");
    tiles.push_back(load(words[0], words[1], noise, words.size() == 4 ? words[3] : ""));
  }
  if (tiles.empty()) throw common::DataError(path, "lists no tiles");
  return tiles;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("score",
                    "Scores detections.json against truth.json for one or many tiles: detection "
                    "precision/recall/F1, false alarms per hectare, a precision-recall curve, "
                    "identification, pose errors, recognition against canopy cover and noise.");
  tool.without_threads();
  score::Params p;
  std::string detections, truth, manifest, cover, bins = "0,0.25,0.5,0.75,1", out = "-", csv;
  double noise = -1;
  tool.add("-d,--detections", &detections, "one tile: its detections.json (canopy.detections v1)");
  tool.add("-t,--truth", &truth, "one tile: its truth.json (canopy.scene_truth v1)");
  tool.add("--noise", &noise, "one tile: its noise level in mm (-1 = not given)");
  tool.add("--cover", &cover, "one tile: its cover level label (light, medium, dense, ...)");
  tool.add("--tiles", &manifest, "many tiles: a file of lines DETECTIONS TRUTH [NOISE_MM [COVER]]");
  tool.add_length("--match-radius", &p.match_radius,
                  "a detection matches a true vehicle within this "
                  "horizontal distance of its centre");
  tool.add("--cover-bins", &bins, "edges of the per-vehicle canopy cover bins, comma-separated");
  tool.add("--flip-threshold", &p.flip_threshold, "heading error (degrees) counted as a flip");
  tool.add_output(&out, "score JSON (canopy.scene_score v1)");
  tool.add("--csv", &csv,
           "also write the tables as <PREFIX>summary.csv, pr.csv, models.csv, "
           "cover_bins.csv, matches.csv");
  return tool.run(argc, argv, [&] {
    if (manifest.empty() == (detections.empty() && truth.empty())) {
      throw common::UsageError("give either --tiles or --detections with --truth");
    }
    if (manifest.empty() && (detections.empty() || truth.empty())) {
      throw common::UsageError("--detections and --truth go together");
    }
    if (!manifest.empty() && (noise != -1 || !cover.empty())) {
      throw common::UsageError("--noise and --cover are for one tile; the --tiles file gives them per tile");
    }
    if (!(noise == -1 || (noise >= 0 && noise < 1e6)))
      throw common::UsageError("--noise must be >= 0 (mm) or -1");
    if (!(p.match_radius > 0 && p.match_radius <= 100))
      throw common::UsageError("--match-radius must be in (0, 100m]");
    if (!(p.flip_threshold > 0 && p.flip_threshold <= 180))
      throw common::UsageError("--flip-threshold must be in (0, 180]");
    p.cover_bins = parse_bins(bins);
    static const char* tables[] = {"summary", "pr", "models", "cover_bins", "matches"};
    common::OutputSet outputs;
    outputs.add(out, "-o");
    if (!csv.empty()) {
      for (const char* t : tables) outputs.add(csv + t + ".csv", "--csv");
    }
    const std::vector<score::Tile> tiles =
        manifest.empty()
            ? std::vector<score::Tile>{load(detections, truth, noise == -1 ? std::nan("") : noise, cover)}
            : load_manifest(manifest);
    nlohmann::ordered_json result = score::score(tiles, p);
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [k, v] : tool.parameters()) params[k] = v;
    nlohmann::ordered_json inputs = nlohmann::ordered_json::array();
    for (const auto& t : tiles) {
      inputs.push_back(t.detections.name);
      inputs.push_back(t.truth.name);
    }
    nlohmann::ordered_json doc{
        {"format", result["format"]},
        {"version", result["version"]},
        {"provenance",
         {{"tool", "score"}, {"version", CANOPY_VERSION}, {"parameters", params}, {"inputs", inputs}}}};
    for (const auto& [k, v] : result.items()) {
      if (k != "format" && k != "version") doc[k] = v;
    }
    result = std::move(doc);
    const auto& all = result["summary"][0];
    outputs.set(out, result.dump(1) + "\n");
    if (!csv.empty()) {
      for (const char* t : tables) outputs.set(csv + t + ".csv", score::csv(result, t));
    }
    outputs.commit();
    auto show = [](const nlohmann::ordered_json& v) {
      return v.is_number() ? std::to_string(v.get<double>()).substr(0, 5) : std::string("n/a");
    };
    common::log::info(std::to_string(tiles.size()) + " tiles, " + all["true"].dump() + " true vehicles, " +
                      all["detections"].dump() + " detections: precision " + show(all["precision"]) +
                      ", recall " + show(all["recall"]) + ", identification " + show(all["identification"]));
  });
}
