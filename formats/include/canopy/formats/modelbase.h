// A modelbase directory (formats/README.md): <model>.json segment graphs, beside them the
// <model>.pcd surfaces and optional <model>.class names. Listing it (read_segment_graph reads one graph,
// every error naming the file); what a stage checks beyond that stays in the stage.
#pragma once

#include <string>
#include <vector>

#include "canopy/formats/segment_graph.h"

namespace canopy::formats {

struct ModelbaseEntry {
  std::string name;  // the file stem: the model's name
  std::string path;  // <dir>/<name>.json
};

// Every regular file "<model>.json" in `dir`, sorted by file name; other entries are ignored.
// Throws common::DataError naming the directory: missing, not a directory, cannot be listed,
// or holding no <model>.json.
std::vector<ModelbaseEntry> list_modelbase(const std::string& dir);

}  // namespace canopy::formats
