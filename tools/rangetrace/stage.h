// rangetrace as a stage: what one run renders, its inputs read, its outputs (stage.cpp). The
// CLI binding is main.cpp; this neither parses options nor writes files.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "rangetrace/rangetrace.h"
#include "rangetrace/tile.h"

namespace canopy::rangetrace {

// What one run renders (the CLI's --model, --scene, --units/--up, --picture/--view, --truth).
struct Request {
  std::string model;  // load_model spec; "" with a tile scene (its recipe places the vehicles)
  std::string scene;  // load_scene name or path; "" only for a picture of the model alone
  MeshImport import;
  bool picture = false;  // a shaded PNG picture instead of a scan
  int view = 0;          // the scene's view shown by a picture
  bool truth = false;    // a tile scan's truth.json too
};

// The request and its inputs, read: the scene recipe (when given) and, without a tile scene,
// the model.
struct Inputs {
  Request request;
  std::optional<SceneRecipe> scene;
  std::optional<Model> model;
  bool tile() const { return scene && scene->tile; }
};

// The request (kept in Inputs), then the scene and the model read. Throws common::UsageError
// naming the option of a request that cannot be rendered: --model with a tile scene, no --model
// without one, --truth without a tile scene, no --scene for a scan.
Inputs load_inputs(const Request& request);

struct Outputs {
  formats::PointCloud cloud;       // the scan, without comments: the caller adds its provenance,
  std::vector<std::string> notes;  // then these lines (the vehicle's class, the tile's origin)
  std::string picture;             // PNG bytes (request.picture)
  std::optional<Tile> tile;        // a tile scan's tile, canopy cover measured (truth_json's input)
  std::string summary;             // "<n> points (<what>, <views>)" for the closing INFO line
};

// Renders what inputs.request asks (validate()s the parameters first). Throws Error when the
// scan holds no point.
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::rangetrace
