#include "canopy/formats/json_document.h"

#include <cstdint>

#include "binary_io.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_fields.h"

namespace canopy::formats {

using common::DataError;
using Json = nlohmann::ordered_json;

namespace {
constexpr int kVersion = 1;  // every canopy document's first version
}  // namespace

Json open_json_document(const std::string& text, const std::string& name, const char* format,
                        const Json::parser_callback_t& filter, int max_version) {
  // canopy documents nest 5 levels; nlohmann copies values recursively (ordered_json's
  // objects copy their values when they grow), so a 60 KB file of nested brackets would
  // overflow the stack. Refuse deep nesting before parsing.
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw DataError(
        name, text.empty() ? "empty file (not a JSON document)" : "only white space (not a JSON document)");
  constexpr int kMaxDepth = 64;
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxDepth) {
        throw DataError(
            name, "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels (not a canopy document)");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  Json j;
  try {
    j = filter ? Json::parse(text, filter) : Json::parse(text);
  } catch (const Json::exception& e) {  // parse errors, and numbers out of double's range (1e400)
    const std::string is = detail::sniff(text);
    if (!is.empty() && is != "a JSON document")
      throw DataError(name, "this is " + is + ", not a JSON document");
    // The JSON library reads a NUL byte as the end of the input ("unexpected end of input" at
    // column 1 for a binary file): say where the NUL is.
    const std::size_t nul = text.find('\0');
    if (nul != std::string::npos) {
      throw DataError(name, "not valid JSON: a NUL byte at byte " + std::to_string(nul) +
                                " (a binary file, not a JSON document)");
    }
    throw DataError(name, "not valid JSON: " + json_library_text(e));
  }
  if (!j.is_object() || !j.contains("format"))
    throw DataError(name, "no \"format\" key (not a canopy JSON document)");
  if (!j["format"].is_string() || j["format"].get<std::string>() != format) {
    throw DataError(name, "format is " + json_describe(j["format"]) + ", expected \"" + format + "\"");
  }
  if (!j.contains("version") || !(j["version"].is_number_integer() || j["version"].is_number_unsigned())) {
    throw DataError(name, "no integer \"version\"");
  }
  const Json& v = j["version"];
  const bool known = v.is_number_unsigned()
                         ? v.get<std::uint64_t>() >= static_cast<std::uint64_t>(kVersion) &&
                               v.get<std::uint64_t>() <= static_cast<std::uint64_t>(max_version)
                         : v.get<std::int64_t>() >= kVersion && v.get<std::int64_t>() <= max_version;
  if (!known) {
    throw DataError(name, std::string(format) + " version " + v.dump() +
                              " is not supported (this build reads " +
                              (max_version > kVersion ? "versions 1 to " + std::to_string(max_version)
                                                      : std::string("version 1")) +
                              ")");
  }
  return j;
}

}  // namespace canopy::formats
