// Provenance: who wrote a canopy document and from what (the "provenance" object of the JSON
// documents, formats/README.md).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace canopy::formats {

// Who wrote a document and from what.
struct Provenance {
  std::string tool;
  std::string version;
  std::vector<std::pair<std::string, std::string>> parameters;  // option name -> value text
  std::vector<std::string> inputs;                              // input paths as given
};

// The same provenance as header comment lines of a PCD, PLY or LAS file, one format for every
// tool:
//   <tool> (canopy) <version>
//   parameter <name> = <value>    one per option, in the order given
//   input <path>                  one per input, as given
std::vector<std::string> provenance_comments(const Provenance& provenance);

// The same provenance as the "provenance" object of a canopy JSON document:
//   {"tool": ..., "version": ..., "parameters": {name: value, ...}, "inputs": [path, ...]}
nlohmann::ordered_json provenance_json(const Provenance& provenance);

}  // namespace canopy::formats
