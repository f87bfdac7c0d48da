#include "canopy/formats/modelbase.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "canopy/common/error.h"

namespace canopy::formats {

std::vector<ModelbaseEntry> list_modelbase(const std::string& dir) {
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
  std::vector<ModelbaseEntry> entries;
  for (const auto& [name, path] : files) entries.push_back({fs::path(name).stem().string(), path});
  return entries;
}

}  // namespace canopy::formats
