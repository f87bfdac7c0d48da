// Opening any canopy JSON document (segment graph, match result, verdict, candidates,
// detections, scene truth): one parser with bounded nesting and errors that name the file.
#pragma once

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace canopy::formats {

// Parses `text` (the contents of file `name`) and checks that it is a canopy document of
// `format`, version 1. Throws common::DataError naming `name`: not JSON (library text quoted,
// never cut at a NUL), another kind of file ("this is a PNG image"), nested deeper than 64
// levels (refused before parsing: the library's recursive copy would overflow the stack), no
// or another "format", no integer or an unsupported "version".
// `filter` (optional) is nlohmann's parser callback: a key it returns false for is left out of
// the document with its value (a reader's way to skip what it does not use). `max_version`: a
// reader that knows later versions of the format (canopy.detections 2) accepts 1 … max_version;
// the document's "version" tells it which one it has.
nlohmann::ordered_json open_json_document(const std::string& text, const std::string& name, const char* format,
                                          const nlohmann::ordered_json::parser_callback_t& filter = nullptr,
                                          int max_version = 1);

// A malformed field found while reading a document's members: the reader catches it and throws
// common::DataError naming the file with this text ("vehicles[2]: missing \"pose\"").
struct MalformedField : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// j[key]. Throws MalformedField("<where>: missing \"<key>\"") when j is not an object or lacks key.
const nlohmann::ordered_json& json_member(const nlohmann::ordered_json& j, const char* key,
                                          const std::string& where);

}  // namespace canopy::formats
