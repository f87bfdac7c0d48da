// formats/ini.h: the one INI reader (docs/decisions/ini.md). Known answers for each syntax case
// and each policy, errors naming file and line, and every committed share/params file read as
// CLI11's --config reads it.
#include <CLI/CLI.hpp>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/ini.h"

using namespace canopy::formats;
using canopy::common::DataError;

namespace {

// "section/key=value@line" per entry, joined by '|'.
std::string entries(const std::string& text, const IniPolicy& policy = {}) {
  const IniFile f = parse_ini(text, "t.ini", policy);
  std::string out;
  for (const IniEntry& e : f.entries) {
    out += (out.empty() ? "" : "|") + (e.section.empty() ? "" : e.section + "/") + e.key + "=" + e.value +
           "@" + std::to_string(e.line);
  }
  return out;
}

std::string error(const std::string& text, const IniPolicy& policy = {}, const std::string& file = "t.ini") {
  try {
    parse_ini(text, file, policy);
  } catch (const DataError& e) { return e.what(); }
  return "";
}

IniPolicy with_sections(std::vector<std::string> names = {}) {
  IniPolicy p;
  p.sections = true;
  p.section_names = std::move(names);
  return p;
}

}  // namespace

TEST_CASE("ini: keys, values, blanks and comments") {
  CHECK(entries("a = 1\nb=2\n\t c \t=\t 3 4 \t\n") == "a=1@1|b=2@2|c=3 4@3");
  CHECK(entries("a = 1") == "a=1@1");  // no final newline
  CHECK(entries("") == "");
  CHECK(entries("\n  \n\t\n") == "");
  CHECK(entries("# c\n; c\n  # indented\na = 1\n") == "a=1@4");
  CHECK(entries("a = x=y\n") == "a=x=y@1");  // the first '=' splits
  // Inline comments (the default): the rest of the line from any comment character.
  CHECK(entries("a = 1 # one\nb = 2; two\n") == "a=1@1|b=2@2");
  IniPolicy hash;
  hash.comments = "#";
  CHECK(entries("a = 1;2 # c\n; b = 1\n", hash) == "a=1;2@1|; b=1@2");  // ';' is text
  IniPolicy whole;
  whole.inline_comments = false;
  CHECK(entries("a = 1 # one\n# a = 2\n  ; b = 3\n", whole) == "a=1 # one@1");
  CHECK(ini_words(" 75deg/0deg \t 75deg/180deg ") == std::vector<std::string>{"75deg/0deg", "75deg/180deg"});
  CHECK(ini_words("").empty());
  CHECK(ini_words("one") == std::vector<std::string>{"one"});
}

TEST_CASE("ini: CRLF, BOM and control bytes") {
  CHECK(entries("a = 1\r\nb = 2\r\n") == "a=1@1|b=2@2");
  CHECK(entries("a = 1\r") == "a=1@1");
  CHECK(entries("\xEF\xBB\xBF"
                "a = 1\n") == "a=1@1");
  CHECK(entries("a = caf\xC3\xA9\n") == "a=caf\xC3\xA9@1");  // UTF-8 text is text
  // A BOM anywhere else is part of the text.
  CHECK(entries("a = 1\n\xEF\xBB\xBF"
                "b = 2\n") ==
        "a=1@1|\xEF\xBB\xBF"
        "b=2@2");
  CHECK(error("a = 1\nb = 1\x01x\n") == "t.ini: line 2: control byte 0x01 in column 6 (an INI file is text)");
  CHECK(error("a = 1\rb = 2\n") == "t.ini: line 1: control byte 0x0d in column 6 (an INI file is text)");
  CHECK(error(std::string("a = \0\n", 6)) ==
        "t.ini: line 1: control byte 0x00 in column 5 (an INI file is text)");
  CHECK(error("a = 1\x7f\n") == "t.ini: line 1: control byte 0x7f in column 6 (an INI file is text)");
  IniPolicy recipe;
  recipe.kind = "a recipe";
  CHECK(error("# \x1b\n", recipe) == "t.ini: line 1: control byte 0x1b in column 3 (a recipe is text)");
  // The file name in a message: control bytes escaped.
  CHECK(error("a\n", {}, "t\x1b.ini") == "t\\x1b.ini: line 1: expected 'key = value', got 'a'");
}

TEST_CASE("ini: lines that are not key = value") {
  CHECK(error("a = 1\nb\n") == "t.ini: line 2: expected 'key = value', got 'b'");
  CHECK(error("a = 1 # x\n = 2\n") == "t.ini: line 2: no key before '='");
  CHECK(error("a =\n") == "t.ini: line 1: key 'a' has no value");
  CHECK(error("a = # nothing\n") == "t.ini: line 1: key 'a' has no value");
  IniPolicy empty;
  empty.empty_values = true;
  CHECK(entries("a =\nb = 1\n", empty) == "a=@1|b=1@2");
}

TEST_CASE("ini: sections") {
  CHECK(error("[x]\na = 1\n") == "t.ini: line 1: section [x], but an INI file has no sections");
  CHECK(entries("a = 0\n[x]\na = 1\n[ y ]\na = 2\n", with_sections()) == "a=0@1|x/a=1@3|y/a=2@5");
  const IniFile f = parse_ini("a = 0\n[x]\na = 1\n[y] # c\nb = 2\n", "t.ini", with_sections());
  CHECK(f.sections == std::vector<std::string>{"x", "y"});
  REQUIRE(f.find("x", "a") != nullptr);
  CHECK(f.find("x", "a")->value == "1");
  CHECK(f.find("", "a")->value == "0");
  CHECK(f.find("y", "a") == nullptr);
  CHECK(f.find("z", "b") == nullptr);
  CHECK(error("[x]\n[x]\n", with_sections()) ==
        "t.ini: line 2: section [x] is given twice, on lines 1 and 2");
  CHECK(error("[]\n", with_sections()) == "t.ini: line 1: malformed section []");
  CHECK(error("[a]b]\n", with_sections()) == "t.ini: line 1: malformed section [a]b]");
  CHECK(error("[z]\n", with_sections({"x", "y"})) ==
        "t.ini: line 1: unknown section [z] (the sections: x, y)");
  CHECK(entries("[y]\na = 1\n", with_sections({"x", "y"})) == "y/a=1@2");
  CHECK(error("[x\n", with_sections()) == "t.ini: line 1: expected 'key = value', got '[x'");
}

TEST_CASE("ini: duplicate and unknown keys") {
  CHECK(error("a = 1\nb = 2\na = 3\n") ==
        "t.ini: line 3: 'a' is given twice, on lines 1 and 3 (a key may appear once)");
  CHECK(entries("a = 1\n[s]\na = 2\n", with_sections()) == "a=1@1|s/a=2@3");  // per section
  IniPolicy last;
  last.duplicates = IniPolicy::Duplicates::kLastWins;
  CHECK(entries("a = 1\nb = 2\na = 3\n", last) == "a=3@3|b=2@2");
  CHECK(parse_ini("a = 1\na = 3\n", "t.ini", last).find("", "a")->value == "3");
  IniPolicy repeat;
  repeat.repeatable = [](const std::string& k) { return k == "tree"; };
  CHECK(entries("tree = 1\ntree = 2\n", repeat) == "tree=1@1|tree=2@2");
  CHECK(parse_ini("tree = 1\ntree = 2\n", "t.ini", repeat).find("", "tree")->line == 2);
  CHECK(error("tree = 1\nx = 1\nx = 2\n", repeat) ==
        "t.ini: line 3: 'x' is given twice, on lines 2 and 3 (a key may appear once)");
  IniPolicy known;
  known.keys = {"cpus", "mem"};
  CHECK(entries("mem = 1G\ncpus = 2\n", known) == "mem=1G@1|cpus=2@2");
  CHECK(error("mem = 1G\ncpu = 2\n", known) == "t.ini: line 2: unknown key 'cpu' (the keys: cpus, mem)");
}

// CLI11's --config stays CLI11's (docs/decisions/ini.md): every committed parameter file reads
// to the same keys and values with the one reader as with CLI11's own parser.
TEST_CASE("ini: every committed parameter file reads as CLI11's --config reads it") {
  namespace fs = std::filesystem;
  const fs::path root = CANOPY_SOURCE_DIR;
  std::vector<fs::path> files;
  for (const char* dir : {"share/params", "bench/density"}) {
    for (const auto& e : fs::directory_iterator(root / dir)) {
      if (e.path().extension() == ".ini") files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 14);
  std::size_t keys = 0;
  for (const fs::path& path : files) {
    CAPTURE(path);
    const std::string text = canopy::common::read_file(path.string());
    const IniFile ours = parse_ini(text, path.string(), IniPolicy{});
    std::istringstream in(text);
    const std::vector<CLI::ConfigItem> theirs = CLI::ConfigTOML().from_config(in);
    REQUIRE(ours.entries.size() == theirs.size());
    for (std::size_t i = 0; i < theirs.size(); ++i) {
      CHECK(ours.entries[i].key == theirs[i].fullname());
      // CLI11 drops the quotes around a value (rangetrace.ini's "0,0": one value, not two).
      std::string value = ours.entries[i].value;
      if (value.size() >= 2 && value.front() == '"' && value.back() == '"')
        value = value.substr(1, value.size() - 2);
      CHECK(std::vector<std::string>{value} == theirs[i].inputs);
    }
    keys += theirs.size();
  }
  CHECK(keys > 150);
}
