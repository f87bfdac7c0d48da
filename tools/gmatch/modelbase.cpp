// Reading a modelbase directory: the only I/O of the gmatch library.
#include <algorithm>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>

#include "canopy/common/error.h"
#include "gmatch/gmatch.h"

namespace canopy::gmatch {

std::vector<Model> read_modelbase(const std::string& dir) {
  namespace fs = std::filesystem;
  using common::DataError;
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw DataError(dir, "modelbase directory does not exist");
  if (!fs::is_directory(dir, ec)) {
    throw DataError(dir, "modelbase is not a directory (give a directory of <model>.json)");
  }
  std::vector<std::pair<std::string, std::string>> files;  // (file name, path)
  fs::directory_iterator it(dir, ec);
  if (ec) throw DataError(dir, "cannot list modelbase directory: " + ec.message());
  for (const auto& entry : it) {
    const fs::path& path = entry.path();
    if (path.extension() != ".json" || !entry.is_regular_file(ec)) continue;
    files.emplace_back(path.filename().string(), path.string());
  }
  if (files.empty()) throw DataError(dir, "modelbase holds no <model>.json segment graphs");
  std::sort(files.begin(), files.end());

  std::vector<Model> models;
  for (const auto& [name, path] : files) {
    Model model;
    model.name = fs::path(name).stem().string();
    try {
      model.graph = formats::read_segment_graph(path);
    } catch (const DataError& e) {
      if (e.file() == path) throw;
      throw DataError(path, e.what());
    } catch (const std::exception& e) { throw DataError(path, e.what()); }
    validate_graph(model.graph, path);
    // The matcher keeps two model-by-model tables (pairwise angles and distances): memory grows
    // with the square of the segment count (20 000 segments cost 6.3 GB). ncut's models have
    // tens to a few hundred segments.
    if (model.graph.segments.size() > kMaxModelSegments) {
      throw DataError(path, "model graph has " + std::to_string(model.graph.segments.size()) +
                                " segments; gmatch matches models of at most " +
                                std::to_string(kMaxModelSegments) +
                                " (its pairwise tables grow with the square of the count)");
    }
    models.push_back(std::move(model));
  }
  return models;
}

}  // namespace canopy::gmatch
