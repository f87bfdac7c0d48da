#include "canopy/common/error.h"

#include <cstdio>

#include "canopy/common/printable.h"

namespace canopy::common {
namespace {

// The message as it may be printed: control bytes but newline and tab as \xNN. A NUL quoted
// from a file cut what() there (report's "unknown record '" for a manifest line holding one,
// stop 68); an escape sequence would reach the terminal.
std::string message_text(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && c != '\n' && c != '\t') || u == 0x7f) {
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
    : Error(message_text(display_name(file) + ": " + cause)), file_(file), cause_(cause) {}

std::string display_name(const std::string& path, bool output) {
  if (path == "-") return output ? "<stdout>" : "<stdin>";
  return path;
}

std::string printable(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace canopy::common
