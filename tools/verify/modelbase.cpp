// Reading the modelbase entries a match result names: the only I/O of the verify library.
#include <algorithm>
#include <filesystem>
#include <system_error>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/pcd.h"
#include "canopy/documents/modelbase.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/documents/verdict.h"
#include "verify/verify.h"

namespace canopy::verify {

std::vector<Model> read_models(const std::string& dir, const std::vector<std::string>& names,
                               const std::string& who) {
  namespace fs = std::filesystem;
  using common::DataError;
  std::error_code ec;
  documents::require_modelbase_dir(dir, "<model>.json graphs and <model>.pcd surfaces");
  std::vector<Model> models;
  std::vector<std::string> unlabelled;  // surfaces read with a label field of 0 only
  for (const auto& name : names) {
    const std::string graph = (fs::path(dir) / (name + ".json")).string();
    const std::string surface = (fs::path(dir) / (name + ".pcd")).string();
    if (!documents::is_model_name(name)) {
      throw DataError(who, "hypothesis names model '" + name.substr(0, 80) +
                               "', which is not a model name (a file stem: no '/', not . or .., no control "
                               "characters)");
    }
    if (!fs::is_regular_file(graph, ec)) {
      throw DataError(who, "hypothesis names model '" + name + "', which is not in the modelbase " + dir +
                               " (no " + graph + ")");
    }
    if (!fs::is_regular_file(surface, ec)) {
      throw DataError(surface, "model '" + name +
                                   "' has no surface samples in the modelbase "
                                   "(build it with make -f Makefile.experiments verify-modelbase)");
    }
    Model m;
    m.name = name;
    m.graph = documents::read_segment_graph(graph);  // errors name the file
    bool zero_labels = false;
    m.surface = surface_from_cloud(formats::read_pcd(surface), surface, kSurfaceMinZ, &zero_labels);
    if (zero_labels && std::find(unlabelled.begin(), unlabelled.end(), surface) == unlabelled.end()) {
      unlabelled.push_back(surface);
    }
    if (auto cls = documents::read_model_class(dir, name)) m.vehicle_class = *cls;
    models.push_back(std::move(m));
  }
  if (!unlabelled.empty()) {
    std::string files;
    for (const auto& f : unlabelled) files += (files.empty() ? "" : ", ") + f;
    common::log::info(std::to_string(unlabelled.size()) + " modelbase surface" +
                      (unlabelled.size() == 1 ? "" : "s") +
                      " with a label field of 0 (unknown) only, as fitvox writes for unlabelled input: "
                      "the points above the ground (z > " +
                      common::format_length(kSurfaceMinZ) + ") are the model (" + files + ")");
  }
  return models;
}

}  // namespace canopy::verify
