// collect: candidates index (detect) + one verdict per candidate (verify) -> detections.json
// and a GeoJSON of the detections in the tile's coordinates.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/density_scale.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/model_classes.h"
#include "canopy/documents/modelbase.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/points_io.h"
#include "collect/collect.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

// The top-view box of a modelbase surface (<model>.pcd, model frame; label-1 rows when the
// samples carry labels, as verify keeps them).
collect::ModelBox model_box(const std::string& path, bool need_height) {
  const formats::PointCloud pc = formats::read_points(path, "collect");
  if (need_height) {
    pc.require({"x", "y", "z"}, path, "is this a modelbase surface? (--size-only needs its height)");
  } else {
    pc.require({"x", "y"}, path, "is this a modelbase surface?");
  }
  const auto& x = pc.col("x");
  const auto& y = pc.col("y");
  // (a label field of 0 everywhere, fitvox's for unlabelled input, carries no labels: every row)
  const std::vector<double>* label = formats::carries_labels(pc) ? &pc.col("label") : nullptr;
  const std::vector<double>* z = pc.has("z") ? &pc.col("z") : nullptr;
  collect::ModelBox b{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::size_t n = 0;
  for (std::size_t i = 0; i < pc.size(); ++i) {
    if (label && (*label)[i] != 1) continue;
    b.x0 = std::min(b.x0, x[i]);
    b.x1 = std::max(b.x1, x[i]);
    b.y0 = std::min(b.y0, y[i]);
    b.y1 = std::max(b.y1, y[i]);
    if (z) b.z1 = n == 0 ? (*z)[i] : std::max(b.z1, (*z)[i]);
    ++n;
  }
  if (n == 0) throw common::DataError(path, "has no vehicle points (label 1) to bound the model");
  return b;
}

// The command line: the index, the outputs, where the verdicts and modelbase are.
struct Options {
  std::string in, out = "-", plan, key = "TILE", verdicts, name = "verdict.json", class_name = "class.json",
                  geojson, crs, modelbase, calibration, model_classes;
  double model_density = collect::kModelDensity;
  bool size_only = false, no_density_scale = false;
  double size_gate = 0.25;
  double contradicted_below = 0.5;
  std::string contradiction_level = "group";
  double refused_below = 0.8;
  double coarse_none_below = common::kDenseDensity;
  double class_accept = 0;
};

void bind(common::Tool& tool, Options& o) {
  tool.add_input(&o.in, "candidates index.json (canopy.candidates v1 or v2)");
  tool.add_output(&o.out, "detections.json");
  tool.add_output("--plan", &o.plan,
                  "instead: write the make plan of the candidates (ids and transforms, "
                  "mk/scenes.mk) and stop; needs no verdicts");
  tool.add("--plan-key", &o.key, "prefix of the plan's make variables (<key>_CANDS, <key>_TRANSFORM_<id>)");
  tool.add("--verdicts", &o.verdicts,
           "directory holding <id>/<verdict-name> per candidate (default: the index's directory)");
  tool.add("--verdict-name", &o.name, "file name of each candidate's model-level verdict (verify)");
  tool.add("--class-name", &o.class_name,
           "file name of each candidate's class-level answer (classify; used where the model "
           "chain found nothing or did not run; \"\" = none)");
  tool.add("--model-density", &o.model_density,
           "--plan: candidates whose object density (points/m²) is below this run classify only "
           "(<key>_LEVEL_<id> := class), the others the model chain too");
  tool.add_flag("--no-density-scale", &o.no_density_scale,
                "--plan: no density rule: every model-level candidate runs the stages' configured "
                "lengths (otherwise one below 370 points/m² gets fitvox's voxel, cocone's facet area "
                "and ncut's radii scaled to its density, <key>_FITVOX_<id> ...: "
                "docs/decisions/density-scale.md)");
  tool.add_output("--geojson", &o.geojson, "also write the detections as a GeoJSON FeatureCollection");
  tool.add("--crs", &o.crs,
           "coordinate reference system of the tile, EPSG:<code>: recorded in detections.json "
           "and as the GeoJSON \"crs\" member; without it, the CRS detect read from the tile's "
           "LAS/LAZ CRS record (the index's \"crs\"), else none (no member)");
  tool.add("--modelbase", &o.modelbase,
           "directory of <model>.pcd surfaces: footprints are the posed model's "
           "top-view box (else the candidate's footprint)");
  tool.add_flag("--size-only", &o.size_only,
                "the size-only ablation: no model chain (no verdict is read) and none of classify's "
                "decisions; each candidate classify measured becomes a detection of the --modelbase "
                "model nearest to its measured length, width and height when each is within "
                "--size-gate of the model's");
  tool.add("--contradicted-below", &o.contradicted_below,
           "a model answer whose confidence is below this, and whose class classify's class "
           "answer contradicts (neither its class nor its group), gives way to classify's "
           "answer (0 = off: the model answer first)");
  tool.add("--contradiction-level", &o.contradiction_level,
           "--contradicted-below: group (default) = classify's answer contradicts only when its "
           "group differs from the model class's group in classify's taxonomy (a pickup model "
           "stands against a car answer: classify states the group); class = when its class and "
           "group both differ from the model's class (as before; docs/decisions/open-set.md "
           "\"Thirteenth round\")");
  tool.add("--refused-below", &o.refused_below,
           "a model answer whose confidence is below this gives way to classify's none when "
           "classify refused the candidate on its shape or surface (a flat box, an oval, no roof, "
           "porous, ...; not its density or size alone): the candidate is rejected (0 = off: the "
           "model answer first)");
  tool.add("--calibration", &o.calibration,
           "file of the Platt maps that calibrate the confidence each final answer states, per level "
           "(share/params/calibration.ini; docs/decisions/verify.md §16); \"\" (the default) = "
           "each level's own confidence as it stated it");
  tool.add("--coarse-none-below", &o.coarse_none_below,
           "--calibration: verify's none of a candidate whose object density (points/m², the "
           "index's) is below this states the file's none-coarse map, the others its none-dense map "
           "(default 370, the density rule's dense end; docs/decisions/verify.md §19); 0 = off: "
           "every verify none through the none map (the ablation, as before §19)");
  tool.add("--class-accept", &o.class_accept,
           "a class-level answer (classify's class, where no model answer is given) whose stated "
           "confidence (after --calibration) is below this is not a detection: the candidate is "
           "rejected as low_confidence (0 = off: every class answer a detection; "
           "docs/decisions/open-set.md \"Seventeenth round\")");
  tool.add("--model-classes", &o.model_classes,
           "CSV 'model,class' (e.g. share/models/classes.csv): a model-level detection whose answer "
           "has no class (a modelbase without <model>.class files; --size-only's) is written with its "
           "model's class and that class's group; an answer's own class stays (and gets its group), a "
           "model not in the file stays without. Only what is written: every decision (--contradicted-below, "
           "--refused-below, ...) reads the answers as they are (not read with --plan)");
  tool.add("--size-gate", &o.size_gate,
           "--size-only: the largest relative difference of length, width or height from the "
           "nearest model's that is still that model");
}

// --plan: the candidates' make plan, alone.
void write_plan(const Options& o) {
  if (o.out != "-" || !o.geojson.empty())
    throw common::UsageError("--plan is alone: no -o or --geojson with it");
  if (!std::regex_match(o.key, std::regex("[A-Za-z_][A-Za-z0-9_]{0,99}"))) {
    throw common::UsageError("--plan-key must be a make variable name (letters, digits, _)");
  }
  common::check_output(o.plan);
  const collect::Index index = collect::parse_index(common::read_file(o.in), o.in);
  if (!(o.model_density >= 0) || !std::isfinite(o.model_density))
    throw common::UsageError("--model-density must be a number >= 0");
  const std::string text = collect::plan(index, o.key, o.model_density, !o.no_density_scale);
  common::write_file_atomic(o.plan, text);
  std::size_t model = 0, scaled = 0;
  for (const auto& c : index.candidates) {
    const bool m = !c.density || *c.density >= o.model_density;
    model += m;
    scaled += m && !o.no_density_scale && c.density && !common::density_scale(*c.density).dense_end();
  }
  common::log::info(std::to_string(index.candidates.size()) +
                    (index.candidates.size() == 1 ? " candidate planned, " : " candidates planned, ") +
                    std::to_string(model) +
                    " for the model chain (object density >= " + std::to_string(int(o.model_density)) +
                    " points/m²), " + std::to_string(scaled) + " of them with the density rule's scale");
}

// Each candidate's answers, <verdicts>/<id>/<name> (verify) and <verdicts>/<id>/<class-name>
// (classify; default: beside the index), either of which may be missing; the paths read join
// the inputs.
std::vector<collect::Answers> read_answers(const Options& o, const collect::Index& index,
                                           std::vector<std::string>& inputs) {
  const fs::path dir = o.verdicts.empty() ? fs::path(o.in).parent_path() : fs::path(o.verdicts);
  const std::string index_dir = fs::path(o.in).parent_path().string();
  auto read = [&](const std::string& path, const std::string& id) {
    collect::Verdict v = collect::read_verdict(path);
    if (!v.present) return v;
    collect::check_verdict_of(v, id, index_dir);
    inputs.push_back(path);
    return v;
  };
  std::vector<collect::Answers> as;
  for (const auto& c : index.candidates) {
    collect::Answers a;
    a.model = o.size_only ? collect::absent_verdict((dir / c.id / o.name).string())
                          : read((dir / c.id / o.name).string(), c.id);
    a.cls =
        o.class_name.empty() ? collect::absent_verdict("") : read((dir / c.id / o.class_name).string(), c.id);
    if (!a.model.present && !a.cls.present) {
      // Neither: the v1 message (the verdict file cannot be read).
      common::read_file(a.model.name);
    }
    as.push_back(std::move(a));
  }
  return as;
}

// The top-view boxes of the found models that the modelbase holds; their paths join the inputs.
// With `all`, every <model>.pcd of the modelbase (--size-only chooses among them).
std::map<std::string, collect::ModelBox> read_boxes(const std::string& modelbase,
                                                    const std::vector<collect::Answers>& as,
                                                    std::vector<std::string>& inputs, bool all) {
  std::map<std::string, collect::ModelBox> boxes;
  std::set<std::string> models;
  for (const auto& a : as) {
    if (a.model.present && !a.model.model.empty()) models.insert(a.model.model);
  }
  if (all) {
    std::error_code ec;
    if (!fs::is_directory(modelbase, ec)) throw common::DataError(modelbase, "is not a modelbase directory");
    // Surfaces only: regular <model>.pcd files, not hidden ones (an interrupted writer's
    // .<name>.tmp….pcd would tie with its model and win the tie by name).
    for (fs::directory_iterator it(modelbase, ec), end; !ec && it != end; it.increment(ec)) {
      const fs::path& p = it->path();
      std::error_code e2;
      if (p.extension() == ".pcd" && p.filename().string()[0] != '.' && fs::is_regular_file(p, e2))
        models.insert(p.stem().string());
    }
    if (ec) throw common::DataError(modelbase, "cannot be listed: " + ec.message());
    if (models.empty()) throw common::DataError(modelbase, "holds no <model>.pcd surface for --size-only");
  }
  for (const auto& m : models) {
    const fs::path path = fs::path(modelbase) / (m + ".pcd");
    if (!fs::exists(path)) {
      common::log::info("no " + path.string() + ": " + m + " footprints are the candidates'");
      continue;
    }
    boxes[m] = model_box(path.string(), all);
    inputs.push_back(path.string());
  }
  return boxes;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("collect",
                    "One tile's detections: the candidates index of detect plus one verify verdict "
                    "per candidate (or classify's class-level answer) -> detections.json (canopy.detections "
                    "v2) and a GeoJSON of the "
                    "detections' footprints in the tile's coordinates.");
  tool.without_threads();
  Options o;
  bind(tool, o);
  return tool.run(argc, argv, [&] {
    if (o.in.empty() || o.in == "-") throw common::UsageError("-i must name the candidates index.json");
    collect::Params p;
    p.crs = o.crs;
    collect::validate(p);
    if (!o.plan.empty()) return write_plan(o);
    if (o.name.empty() || o.name.find('/') != std::string::npos)
      throw common::UsageError("--verdict-name must be a file name");
    common::OutputSet outputs;
    outputs.add(o.out, "-o");
    if (!o.geojson.empty()) outputs.add(o.geojson, "--geojson");
    collect::Inputs in;
    in.index = collect::parse_index(common::read_file(o.in), o.in);
    if (!p.crs.empty() && !in.index.crs.empty() && p.crs != in.index.crs) {
      common::log::warn("--crs " + p.crs + " given: used, though the tile's file records " + in.index.crs +
                        " (" + in.index.crs_from + ")");
    }
    in.provenance = {"collect", CANOPY_VERSION, tool.parameters(), {o.in}};
    if (o.class_name.find('/') != std::string::npos)
      throw common::UsageError("--class-name must be a file name");
    // The directories named are checked even when the index lists no candidate (they are read
    // per candidate, so a mistyped path went unnoticed on an empty tile: hardening.md, stop 68).
    if (!o.modelbase.empty()) documents::require_modelbase_dir(o.modelbase, "<model>.pcd surfaces");
    if (!o.verdicts.empty())
      documents::require_input_dir(o.verdicts, "verdicts", "give the directory of <id>/verdict.json");
    in.answers = read_answers(o, in.index, in.provenance.inputs);
    if (o.size_only && o.modelbase.empty()) throw common::UsageError("--size-only needs --modelbase");
    p.size_only = o.size_only;
    if (!(o.size_gate > 0 && o.size_gate <= 10)) throw common::UsageError("--size-gate must be in (0, 10]");
    p.size_gate = o.size_gate;
    if (!(o.contradicted_below >= 0 && o.contradicted_below <= 1))
      throw common::UsageError("--contradicted-below must be in [0, 1]");
    p.contradicted_below = o.contradicted_below;
    if (o.contradiction_level != "group" && o.contradiction_level != "class")
      throw common::UsageError("--contradiction-level must be group or class, not \"" +
                               o.contradiction_level + "\"");
    p.contradicted_by_group = o.contradiction_level == "group";
    if (!(o.refused_below >= 0 && o.refused_below <= 1))
      throw common::UsageError("--refused-below must be in [0, 1]");
    p.refused_below = o.refused_below;
    if (!(o.coarse_none_below >= 0) || !std::isfinite(o.coarse_none_below))
      throw common::UsageError("--coarse-none-below must be a number >= 0 (points/m²)");
    p.coarse_none_below = o.coarse_none_below;
    if (!(o.class_accept >= 0 && o.class_accept <= 1))
      throw common::UsageError("--class-accept must be in [0, 1]");
    if (o.size_only && o.class_accept > 0)
      throw common::UsageError("--class-accept is canopy's class level's: not with --size-only");
    p.class_accept = o.class_accept;
    if (!o.calibration.empty()) {
      if (o.size_only) throw common::UsageError("--calibration is canopy's levels': not with --size-only");
      p.calibration = collect::parse_calibration(common::read_file(o.calibration), o.calibration);
      in.provenance.inputs.push_back(o.calibration);
    }
    if (!o.model_classes.empty()) {
      p.model_classes = documents::parse_model_classes(common::read_file(o.model_classes), o.model_classes);
      in.provenance.inputs.push_back(o.model_classes);
    }
    if (!o.modelbase.empty())
      p.boxes = read_boxes(o.modelbase, in.answers, in.provenance.inputs, o.size_only);
    const collect::Outputs r = collect::run(p, in);
    outputs.set(o.out, r.detections);
    if (!o.geojson.empty()) outputs.set(o.geojson, r.geojson);
    outputs.commit();
    common::log::info(r.summary);
    if (!r.warning.empty()) common::log::warn(r.warning);
    // RFC 7946 GeoJSON is WGS 84 longitude/latitude: GDAL (so QGIS) reads a file without the
    // 2008 "crs" member so, and would place a tile's metres as degrees.
    if (!o.geojson.empty() && p.crs.empty() && in.index.crs.empty()) {
      common::log::info(o.geojson +
                        ": no CRS (no --crs, and detect recorded none for the tile): a GIS reads a GeoJSON "
                        "without one as WGS 84 longitude/latitude; give --crs EPSG:<code> (make tile: "
                        "CRS=EPSG:<code>)");
    }
  });
}
