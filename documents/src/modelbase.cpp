#include "canopy/documents/modelbase.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "canopy/common/error.h"

namespace canopy::documents {

void require_input_dir(const std::string& dir, const std::string& what, const std::string& hint) {
  namespace fs = std::filesystem;
  using common::DataError;
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  // A link loop or an unreadable parent is not "does not exist" (fs::exists says false for both).
  if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory)
    throw DataError(dir, what + ": " + ec.message());
  if (!fs::exists(st)) throw DataError(dir, what + " directory does not exist");
  if (!fs::is_directory(st)) throw DataError(dir, what + " is not a directory (" + hint + ")");
}

void require_modelbase_dir(const std::string& dir, const std::string& holds) {
  require_input_dir(dir, "modelbase", "give a directory of " + holds);
}

std::vector<ModelbaseEntry> list_modelbase(const std::string& dir) {
  namespace fs = std::filesystem;
  using common::DataError;
  std::error_code ec;
  require_modelbase_dir(dir, "<model>.json");
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

std::optional<std::string> read_model_class(const std::string& dir, const std::string& name) {
  namespace fs = std::filesystem;
  constexpr std::streamsize kMaxBytes = 4096;  // a class file is one short word
  const std::string file = (fs::path(dir) / (name + ".class")).string();
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  std::ifstream f(file, std::ios::binary);
  std::string text(static_cast<std::size_t>(kMaxBytes) + 1, '\0');
  f.read(text.data(), kMaxBytes + 1);
  if (!f && !f.eof()) throw common::DataError(file, "cannot read the model's class file");
  text.resize(static_cast<std::size_t>(f.gcount()));
  std::istringstream in(text);
  std::string word, extra;
  if (f.gcount() > kMaxBytes || !(in >> word) || (in >> extra) || word.size() > 64) {
    throw common::DataError(file, "expected one class name (one word, at most 64 characters)");
  }
  return word;
}

}  // namespace canopy::documents
