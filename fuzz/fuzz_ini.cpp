// INI reader (formats/ini.h, docs/decisions/ini.md): parse_ini on the bytes under two policies
// (sections and '#;' comments anywhere; no sections, '#' only at a line's start, duplicates
// last-wins, empty values). Every entry must have a key, no control byte, no blank at either
// end of its key or value, a line within the text's lines, and (no sections) the section "".
// Any other exception, crash, sanitizer report or allocation over -malloc_limit_mb is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/ini.h"

namespace f = canopy::formats;

namespace {

bool clean(const std::string& s) {
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && u != '\t') || u == 0x7f) return false;
  }
  return s.empty() || (s.front() != ' ' && s.front() != '\t' && s.back() != ' ' && s.back() != '\t');
}

void check(const std::string& text, const f::IniPolicy& policy) {
  long lines = 1;
  for (const char c : text) lines += c == '\n';
  try {
    const f::IniFile ini = f::parse_ini(text, "fuzz.ini", policy);
    for (const f::IniEntry& e : ini.entries) {
      if (e.key.empty() || !clean(e.key) || !clean(e.value)) std::abort();
      if (e.value.empty() && !policy.empty_values) std::abort();
      if (e.line < 1 || e.line > lines) std::abort();
      if (!policy.sections && !e.section.empty()) std::abort();
      if (ini.find(e.section, e.key) == nullptr) std::abort();
    }
  } catch (const canopy::common::DataError&) {}
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  f::IniPolicy sections;
  sections.sections = true;
  check(text, sections);
  f::IniPolicy plain;
  plain.comments = "#";
  plain.inline_comments = false;
  plain.duplicates = f::IniPolicy::Duplicates::kLastWins;
  plain.empty_values = true;
  check(text, plain);
  return 0;
}
