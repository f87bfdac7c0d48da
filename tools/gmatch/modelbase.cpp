// Reading a modelbase directory: the only I/O of the gmatch library.
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/modelbase.h"
#include "gmatch/gmatch.h"

namespace canopy::gmatch {

std::vector<Model> read_modelbase(const std::string& dir) {
  using common::DataError;
  std::vector<Model> models;
  for (const documents::ModelbaseEntry& entry : documents::list_modelbase(dir)) {
    Model model;
    model.name = entry.name;
    // Matching uses the segments' statistics, never their vertex lists.
    model.graph = documents::read_segment_graph(entry.path, documents::GraphVertices::kSkip);
    validate_graph(model.graph, entry.path);
    // The matcher keeps two model-by-model tables (pairwise angles and distances): memory grows
    // with the square of the segment count (20 000 segments cost 6.3 GB). ncut's models have
    // tens to a few hundred segments.
    if (model.graph.segments.size() > kMaxModelSegments) {
      throw DataError(entry.path, "model graph has " + std::to_string(model.graph.segments.size()) +
                                      " segments; gmatch matches models of at most " +
                                      std::to_string(kMaxModelSegments) +
                                      " (its pairwise tables grow with the square of the count)");
    }
    models.push_back(std::move(model));
  }
  return models;
}

}  // namespace canopy::gmatch
