// Opening any canopy JSON document (segment graph, match result, verdict, candidates,
// detections, scene truth): one parser with bounded nesting and errors that name the file.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace canopy::formats {

// Parses `text` (the contents of file `name`) and checks that it is a canopy document of
// `format`, version 1. Throws common::DataError naming `name`: not JSON (library text quoted,
// never cut at a NUL), another kind of file ("this is a PNG image"), nested deeper than 64
// levels (refused before parsing: the library's recursive copy would overflow the stack), no
// or another "format", no integer or an unsupported "version".
nlohmann::ordered_json open_json_document(const std::string& text, const std::string& name, const char* format);

}  // namespace canopy::formats
