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
// Every name, value and path is escape_comment_text'ed: a newline in an input path cannot end
// the comment line (and with it the header).
std::vector<std::string> provenance_comments(const Provenance& provenance);

// Text made safe for a header comment line, reversibly: a backslash becomes "\\", newline
// "\n", carriage return "\r", tab "\t", every other control byte (below 0x20, and 0x7f)
// "\xHH". Other bytes (UTF-8 too) are kept. unescape_comment_text reverses it (a backslash
// followed by anything else is kept as it is).
std::string escape_comment_text(const std::string& text);
std::string unescape_comment_text(const std::string& text);

// What the PCD, PLY and LAS writers do to every comment line they write: control bytes are
// escaped as by escape_comment_text, everything else (backslashes too) is kept, so an
// already-escaped line (provenance_comments) is written unchanged and no comment can break
// the header or split into two comments.
std::string header_safe_comment(const std::string& line);

// The same provenance as the "provenance" object of a canopy JSON document:
//   {"tool": ..., "version": ..., "parameters": {name: value, ...}, "inputs": [path, ...]}
nlohmann::ordered_json provenance_json(const Provenance& provenance);

}  // namespace canopy::formats
