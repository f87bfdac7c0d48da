// INI-style `key = value` text: the one reader of canopy's calibration file, scene recipes,
// sensor presets and share/resources.ini (docs/decisions/ini.md). Fixed rules: a UTF-8 BOM at
// the start is skipped, "\r\n" reads as "\n", any other control byte is an error naming its
// column, blank lines are skipped, keys and values are trimmed of spaces and tabs, the first '='
// splits a line, `[name]` starts a section (a name given twice is an error). What differs
// between callers is an IniPolicy. Every error is a common::DataError
// "<file>: line <n>: <problem>".
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace canopy::formats {

struct IniPolicy {
  std::string comments = "#;";             // characters that start a comment
  bool inline_comments = true;             // a comment character anywhere ends the line (else: only first)
  bool sections = false;                   // `[name]` lines allowed (else an error)
  std::vector<std::string> section_names;  // the allowed section names (empty: any)
  std::vector<std::string> keys;           // the known keys (empty: any; the caller checks)
  std::function<bool(const std::string&)> repeatable;  // keys that may be given more than once
  enum class Duplicates { kError, kLastWins };
  Duplicates duplicates = Duplicates::kError;  // any other key given twice (in one section)
  bool empty_values = false;                   // `key =` allowed
  std::string kind = "an INI file";            // in messages: "(an INI file is text)"
};

struct IniEntry {
  std::string section;  // "" before the first `[name]`
  std::string key;
  std::string value;  // trimmed, comment removed; "" only with empty_values
  int line = 0;       // 1-based
};

struct IniFile {
  std::string file;                   // as given (messages show control bytes as \xNN)
  std::vector<IniEntry> entries;      // in file order (kLastWins: a later value replaces the first entry)
  std::vector<std::string> sections;  // the `[name]`s, in file order

  // The entry of `key` in `section`, or nullptr (a repeatable key: its last).
  const IniEntry* find(const std::string& section, const std::string& key) const;
  // Throws the DataError "<file>: line <line>: <problem>" (line 0: "<file>: <problem>").
  [[noreturn]] void fail(int line, const std::string& problem) const;
};

IniFile parse_ini(const std::string& text, const std::string& file, const IniPolicy& policy);

// A value's words, split at spaces and tabs.
std::vector<std::string> ini_words(const std::string& value);

}  // namespace canopy::formats
