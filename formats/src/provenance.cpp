#include "canopy/formats/provenance.h"

namespace canopy::formats {
namespace {

// Appends the escape of control byte c: \n, \r, \t by name, the others as \xHH.
void escape_control(unsigned char c, std::string* out) {
  static const char* const kHex = "0123456789abcdef";
  if (c == '\n') {
    *out += "\\n";
  } else if (c == '\r') {
    *out += "\\r";
  } else if (c == '\t') {
    *out += "\\t";
  } else {
    *out += "\\x";
    *out += kHex[c >> 4];
    *out += kHex[c & 15];
  }
}

bool is_control(unsigned char c) { return c < 0x20 || c == 0x7f; }

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::string escape_comment_text(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\\') {
      out += "\\\\";
    } else if (is_control(c)) {
      escape_control(c, &out);
    } else {
      out += ch;
    }
  }
  return out;
}

std::string unescape_comment_text(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\\' || i + 1 == text.size()) {
      out += text[i];
      continue;
    }
    const char e = text[i + 1];
    if (e == '\\' || e == 'n' || e == 'r' || e == 't') {
      out += e == 'n' ? '\n' : e == 'r' ? '\r' : e == 't' ? '\t' : '\\';
      ++i;
    } else if (e == 'x' && i + 3 < text.size() && hex_digit(text[i + 2]) >= 0 && hex_digit(text[i + 3]) >= 0) {
      out += static_cast<char>(hex_digit(text[i + 2]) * 16 + hex_digit(text[i + 3]));
      i += 3;
    } else {
      out += text[i];  // not an escape this function writes: kept as it is
    }
  }
  return out;
}

std::string header_safe_comment(const std::string& line) {
  std::string out;
  out.reserve(line.size());
  for (const char ch : line) {
    const auto c = static_cast<unsigned char>(ch);
    if (is_control(c)) {
      escape_control(c, &out);
    } else {
      out += ch;
    }
  }
  return out;
}

std::vector<std::string> provenance_comments(const Provenance& p) {
  std::vector<std::string> lines;
  lines.push_back(escape_comment_text(p.tool) + " (canopy) " + escape_comment_text(p.version));
  for (const auto& [name, value] : p.parameters) {
    lines.push_back("parameter " + escape_comment_text(name) + " = " + escape_comment_text(value));
  }
  for (const std::string& in : p.inputs) lines.push_back("input " + escape_comment_text(in));
  return lines;
}

nlohmann::ordered_json provenance_json(const Provenance& p) {
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const auto& [k, v] : p.parameters) params[k] = v;
  return nlohmann::ordered_json{
      {"tool", p.tool}, {"version", p.version}, {"parameters", params}, {"inputs", p.inputs}};
}

}  // namespace canopy::formats
