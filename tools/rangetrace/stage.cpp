// rangetrace as a stage: the request's inputs, then a single-vehicle scan or picture, or a
// tile scan or picture.
#include "rangetrace/stage.h"

#include <cstdio>
#include <string>
#include <utility>

#include "canopy/common/error.h"

namespace canopy::rangetrace {

namespace {

Outputs tile_output(const Request& request, const SceneRecipe& scene, const Params& params) {
  Outputs out;
  Tile tile = build_tile(*scene.tile, request.scene, params);
  if (request.picture) {
    out.picture = render_tile_picture(tile, params);
    return out;
  }
  TileScan scan = run_tile(&tile, params);
  if (scan.cloud.empty()) throw common::Error("no point in the tile");
  out.cloud = std::move(scan.cloud);
  const TileRecipe& r = *scene.tile;
  if (r.has_origin) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "origin %.3f %.3f %.3f (added to x y z)", r.origin.x(), r.origin.y(),
                  r.origin.z());
    out.notes.push_back(buf);
  }
  double area = 0;
  for (double a : scan.area_per_view) area += a;
  char dens[200];
  std::snprintf(dens, sizeof dens, "%.1f points per m^2 per image, %.1f per m^2 in all",
                area > 0 ? out.cloud.size() / area : 0.0, out.cloud.size() / (r.extent_x * r.extent_y));
  out.summary = std::to_string(out.cloud.size()) + " points (" + request.scene + ", " +
                std::to_string(tile.vehicles.size()) + " vehicles, " +
                std::to_string(scan.points_per_view.size()) + " images; " + dens + ")";
  if (r.sensor) {  // sensor mode: returns and pulses per m^2 of the tile (truth.json "density")
    std::snprintf(dens, sizeof dens, "%.1f returns and %.1f pulses per m^2", tile.returns_per_m2,
                  tile.fired_per_m2);
    out.summary = std::to_string(out.cloud.size()) + " returns (" + request.scene + ", " +
                  std::to_string(tile.vehicles.size()) + " vehicles, " +
                  std::to_string(tile.flight_lines.size()) + " flight lines; " + dens + ")";
  }
  out.tile = std::move(tile);
  return out;
}

Outputs vehicle_output(const Request& request, const Inputs& in, const Params& params) {
  Outputs out;
  const Model& m = *in.model;
  if (request.picture) {
    out.picture = render_picture(m, in.scene ? &*in.scene : nullptr, request.view, params);
    return out;
  }
  const SceneRecipe& s = *in.scene;
  out.cloud = render_scan(m, s, params);
  if (out.cloud.empty()) throw common::Error("no point in the crop box (check --position, --crop-*)");
  if (!m.vehicle_class.empty()) out.notes.push_back("class " + m.vehicle_class);
  out.summary = std::to_string(out.cloud.size()) + " points (" + m.name + ", " + s.name + ", " +
                std::to_string(s.views.size()) + " views)";
  return out;
}

}  // namespace

void validate(const Params& p) {
  if (p.size < 8 || p.size > 8192) {
    throw common::UsageError("--size must be in [8, 8192] pixels (given " + std::to_string(p.size) + ")");
  }
  for (const auto& [name, v] : {std::pair{"--spacing", p.spacing},
                                {"--crop-length", p.crop_length},
                                {"--crop-width", p.crop_width},
                                {"--crop-height", p.crop_height}}) {
    if (!(v > 0)) throw common::UsageError(std::string(name) + " must be > 0");
  }
}

Inputs load_inputs(const Request& request) {
  using common::UsageError;
  Inputs in;
  in.request = request;
  if (!request.scene.empty()) {
    in.scene = load_scene(request.scene);
    if (in.tile()) {
      if (!request.model.empty()) {
        throw UsageError("--model: the tile scene '" + request.scene +
                         "' places its own vehicles "
                         "(vehicle = ... lines)");
      }
      return in;
    }
  }
  if (request.model.empty()) throw UsageError("--model is required (except for tile scenes)");
  if (request.truth) throw UsageError("--truth: only tile scenes write a truth.json");
  in.model = load_model(request.model, request.import);
  if (!request.picture && !in.scene) throw UsageError("--scene is required for a scan");
  return in;
}

Outputs run(const Params& params, const Inputs& inputs) {
  const Request& request = inputs.request;
  validate(params);
  return inputs.tile() ? tile_output(request, *inputs.scene, params) : vehicle_output(request, inputs, params);
}

}  // namespace canopy::rangetrace
