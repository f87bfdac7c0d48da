// A modelbase directory (formats/README.md): <model>.json segment graphs (segment_graph.h reads
// one), beside them the <model>.pcd surfaces and optional <model>.class names. ncut and the
// experiment's make rules build it; gmatch, verify, classify, baseline and famscore read it.
// Listing it and reading a model's class; what a stage checks beyond that stays in the stage.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace canopy::documents {

struct ModelbaseEntry {
  std::string name;  // the file stem: the model's name
  std::string path;  // <dir>/<name>.json
};

// Throws common::DataError naming `dir` unless it is a directory: "<what> directory does not
// exist", "<what> is not a directory (<hint>)" for a file or other non-directory, "<what>: <why>"
// for a link loop or an unreadable parent. For an input directory a tool is given by name (a
// modelbase; collect's --verdicts).
void require_input_dir(const std::string& dir, const std::string& what, const std::string& hint);

// require_input_dir(dir, "modelbase", "give a directory of <holds>"). Every reader of a
// modelbase checks its argument with it.
void require_modelbase_dir(const std::string& dir, const std::string& holds);

// Every regular file "<model>.json" in `dir`, sorted by file name; other entries are ignored.
// Throws common::DataError naming the directory: missing, not a directory, cannot be listed,
// or holding no <model>.json.
std::vector<ModelbaseEntry> list_modelbase(const std::string& dir);

// The class of model `name` from <dir>/<name>.class: one word (at most 64 characters) on one
// line; std::nullopt when there is no such file. Anything else (empty, two words, longer, more
// than 4 KiB) throws common::DataError naming the .class file.
std::optional<std::string> read_model_class(const std::string& dir, const std::string& name);

}  // namespace canopy::documents
