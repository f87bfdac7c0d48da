#include "canopy/common/error.h"

#include <cstdio>

#include "canopy/common/printable.h"

namespace canopy::common {
namespace {

// text with its control bytes as \xNN; newline and tab kept when keep_layout.
std::string escape_controls(const std::string& text, bool keep_layout) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && !(keep_layout && (c == '\n' || c == '\t'))) || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

DataError::DataError(const std::string& file, const std::string& cause)
    // The message as it may be printed: a NUL quoted from a file cut what() there (report's
    // "unknown record '" for a manifest line holding one, stop 68); an escape sequence would
    // reach the terminal. Newline and tab stay (multi-line causes).
    : Error(escape_controls(display_name(file) + ": " + cause, true)), file_(file), cause_(cause) {}

std::string display_name(const std::string& path, bool output) {
  if (path == "-") return output ? "<stdout>" : "<stdin>";
  return path;
}

std::string printable(const std::string& text) { return escape_controls(text, false); }

}  // namespace canopy::common
