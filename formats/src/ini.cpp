#include "canopy/formats/ini.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/common/printable.h"

namespace canopy::formats {
namespace {

constexpr const char* kBlanks = " \t";

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(kBlanks);
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(kBlanks) - b + 1);
}

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

class Reader {
 public:
  Reader(IniFile* out, const IniPolicy& policy) : out_(*out), policy_(policy) {}

  void line(std::string text, int number) {
    number_ = number;
    check_bytes(text);
    const std::string lead = trim(text);
    if (lead.empty() || policy_.comments.find(lead[0]) != std::string::npos) return;
    if (policy_.inline_comments) {
      const auto c = text.find_first_of(policy_.comments);
      if (c != std::string::npos) text.resize(c);
    }
    text = trim(text);
    if (text.front() == '[' && text.back() == ']') return section(trim(text.substr(1, text.size() - 2)));
    const auto eq = text.find('=');
    if (eq == std::string::npos) fail("expected 'key = value', got '" + text + "'");
    entry(trim(text.substr(0, eq)), trim(text.substr(eq + 1)));
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const { out_.fail(number_, problem); }

  void check_bytes(const std::string& text) const {
    for (std::size_t c = 0; c < text.size(); ++c) {
      const auto u = static_cast<unsigned char>(text[c]);
      if ((u < 0x20 && u != '\t') || u == 0x7f) {
        char byte[8];
        std::snprintf(byte, sizeof byte, "0x%02x", u);
        fail("control byte " + std::string(byte) + " in column " + std::to_string(c + 1) + " (" +
             policy_.kind + " is text)");
      }
    }
  }

  void section(const std::string& name) {
    if (!policy_.sections) fail("section [" + name + "], but " + policy_.kind + " has no sections");
    if (name.empty() || name.find_first_of("[]") != std::string::npos)
      fail("malformed section [" + name + "]");
    if (!policy_.section_names.empty() && !contains(policy_.section_names, name)) {
      fail("unknown section [" + name + "] (the sections: " + listed(policy_.section_names) + ")");
    }
    const auto [it, first] = section_lines_.emplace(name, number_);
    if (!first) {
      fail("section [" + name + "] is given twice, on lines " + std::to_string(it->second) + " and " +
           std::to_string(number_));
    }
    section_ = name;
    out_.sections.push_back(name);
  }

  void entry(const std::string& key, const std::string& value) {
    if (key.empty()) fail("no key before '='");
    if (!policy_.keys.empty() && !contains(policy_.keys, key)) {
      fail("unknown key '" + key + "' (the keys: " + listed(policy_.keys) + ")");
    }
    if (value.empty() && !policy_.empty_values) fail("key '" + key + "' has no value");
    IniEntry e{section_, key, value, number_};
    if (!(policy_.repeatable && policy_.repeatable(key))) {
      const auto [it, first] = given_.emplace(std::make_pair(section_, key), out_.entries.size());
      if (!first) {
        if (policy_.duplicates == IniPolicy::Duplicates::kError) {
          fail("'" + key + "' is given twice, on lines " + std::to_string(out_.entries[it->second].line) +
               " and " + std::to_string(number_) + " (a key may appear once)");
        }
        out_.entries[it->second] = std::move(e);
        return;
      }
    }
    out_.entries.push_back(std::move(e));
  }

  IniFile& out_;
  const IniPolicy& policy_;
  int number_ = 0;
  std::string section_;
  std::map<std::string, int> section_lines_;
  std::map<std::pair<std::string, std::string>, std::size_t> given_;  // (section, key) -> entry
};

}  // namespace

const IniEntry* IniFile::find(const std::string& section, const std::string& key) const {
  for (auto it = entries.rbegin(); it != entries.rend(); ++it) {
    if (it->section == section && it->key == key) return &*it;
  }
  return nullptr;
}

void IniFile::fail(int line, const std::string& problem) const {
  throw common::DataError(common::printable(file),
                          line > 0 ? "line " + std::to_string(line) + ": " + problem : problem);
}

IniFile parse_ini(const std::string& text, const std::string& file, const IniPolicy& policy) {
  IniFile out;
  out.file = file;
  Reader reader(&out, policy);
  std::size_t pos = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  int number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::size_t stop = end;
    if (stop > pos && text[stop - 1] == '\r') --stop;
    reader.line(text.substr(pos, stop - pos), ++number);
    pos = end + 1;
  }
  return out;
}

std::vector<std::string> ini_words(const std::string& value) {
  std::vector<std::string> words;
  std::size_t pos = value.find_first_not_of(kBlanks);
  while (pos != std::string::npos) {
    const std::size_t end = value.find_first_of(kBlanks, pos);
    words.push_back(value.substr(pos, end == std::string::npos ? std::string::npos : end - pos));
    pos = value.find_first_not_of(kBlanks, end);
  }
  return words;
}

}  // namespace canopy::formats
