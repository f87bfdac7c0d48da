// collect: candidates index (detect) + one verdict per candidate (verify) -> detections.json
// and a GeoJSON of the detections in the tile's coordinates.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "collect/collect.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

// The top-view box of a modelbase surface (<model>.pcd, model frame; label-1 rows when the
// samples carry labels, as verify keeps them).
collect::ModelBox model_box(const std::string& path) {
  const formats::PointCloud pc = formats::read_points(path, "collect");
  pc.require({"x", "y"}, path, "is this a modelbase surface?");
  const auto& x = pc.col("x");
  const auto& y = pc.col("y");
  const std::vector<double>* label = pc.has("label") ? &pc.col("label") : nullptr;
  collect::ModelBox b{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::size_t n = 0;
  for (std::size_t i = 0; i < pc.size(); ++i) {
    if (label && (*label)[i] != 1) continue;
    b.x0 = std::min(b.x0, x[i]);
    b.x1 = std::max(b.x1, x[i]);
    b.y0 = std::min(b.y0, y[i]);
    b.y1 = std::max(b.y1, y[i]);
    ++n;
  }
  if (n == 0) throw common::DataError(path, "has no vehicle points (label 1) to bound the model");
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("collect",
                    "One tile's detections: the candidates index of detect plus one verify verdict "
                    "per candidate -> detections.json (canopy.detections v1) and a GeoJSON of the "
                    "detections' footprints in the tile's coordinates.");
  tool.without_threads();
  std::string in, out = "-", plan, key = "TILE", verdicts, name = "verdict.json", geojson, crs, modelbase;
  tool.add_input(&in, "candidates index.json (canopy.candidates v1)");
  tool.add_output(&out, "detections.json");
  tool.add_output("--plan", &plan,
                  "instead: write the make plan of the candidates (ids and transforms, "
                  "mk/scenes.mk) and stop; needs no verdicts");
  tool.add("--plan-key", &key, "prefix of the plan's make variables (<key>_CANDS, <key>_TRANSFORM_<id>)");
  tool.add("--verdicts", &verdicts,
           "directory holding <id>/<verdict-name> per candidate (default: the index's directory)");
  tool.add("--verdict-name", &name, "file name of each candidate's verdict");
  tool.add_output("--geojson", &geojson, "also write the detections as a GeoJSON FeatureCollection");
  tool.add("--crs", &crs,
           "coordinate reference system of the tile, EPSG:<code>: recorded in detections.json "
           "and as the GeoJSON \"crs\" member (omitted without it)");
  tool.add("--modelbase", &modelbase,
           "directory of <model>.pcd surfaces: footprints are the posed model's "
           "top-view box (else the candidate's footprint)");
  return tool.run(argc, argv, [&] {
    if (in.empty() || in == "-") throw common::UsageError("-i must name the candidates index.json");
    if (!crs.empty() && !std::regex_match(crs, std::regex("EPSG:[0-9]{1,6}"))) {
      throw common::UsageError("--crs must be EPSG:<code>, e.g. EPSG:32633");
    }
    if (!plan.empty()) {
      if (out != "-" || !geojson.empty())
        throw common::UsageError("--plan is alone: no -o or --geojson with it");
      if (!std::regex_match(key, std::regex("[A-Za-z_][A-Za-z0-9_]{0,99}"))) {
        throw common::UsageError("--plan-key must be a make variable name (letters, digits, _)");
      }
      common::check_output(plan);
      const collect::Index index = collect::parse_index(common::read_file(in), in);
      common::write_file_atomic(plan, collect::plan(index, key));
      common::log::info(std::to_string(index.candidates.size()) + " candidates planned");
      return;
    }
    if (name.empty() || name.find('/') != std::string::npos)
      throw common::UsageError("--verdict-name must be a file name");
    common::OutputSet outputs;
    outputs.add(out, "-o");
    if (!geojson.empty()) outputs.add(geojson, "--geojson");
    const collect::Index index = collect::parse_index(common::read_file(in), in);
    const fs::path dir = verdicts.empty() ? fs::path(in).parent_path() : fs::path(verdicts);
    std::vector<collect::Verdict> vs;
    std::vector<std::string> inputs{in};
    for (const auto& c : index.candidates) {
      const std::string path = (dir / c.id / name).string();
      vs.push_back(collect::parse_verdict(common::read_file(path), path));
      inputs.push_back(path);
    }
    collect::Params p;
    p.crs = crs;
    if (!modelbase.empty()) {
      std::set<std::string> models;
      for (const auto& v : vs) {
        if (!v.model.empty()) models.insert(v.model);
      }
      for (const auto& m : models) {
        const fs::path path = fs::path(modelbase) / (m + ".pcd");
        if (!fs::exists(path)) {
          common::log::info("no " + path.string() + ": " + m + " footprints are the candidates'");
          continue;
        }
        p.boxes[m] = model_box(path.string());
        inputs.push_back(path.string());
      }
    }
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [k, v] : tool.parameters()) params[k] = v;
    const nlohmann::ordered_json prov{
        {"tool", "collect"}, {"version", CANOPY_VERSION}, {"parameters", params}, {"inputs", inputs}};
    const collect::Output o = collect::collect(index, vs, p, prov);
    outputs.set(out, o.detections);
    if (!geojson.empty()) outputs.set(geojson, o.geojson);
    outputs.commit();
    common::log::info(std::to_string(index.candidates.size()) + " candidates: " + std::to_string(o.found) +
                      " vehicles found, " + std::to_string(o.none) + " none" +
                      (o.failed ? ", " + std::to_string(o.failed) + " failed (empty verdict)" : ""));
  });
}
