// The lexical check of user includes (layer 2 of docs/decisions/sandbox.md): POV-Ray 3.7's
// tokens (comments nest, strings keep their backslashes) are scanned for the directives and
// keywords that name files.
#include <limits.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/sim/sandbox.h"

namespace canopy::sim {

namespace {

struct Token {
  enum Kind { kWord, kString, kOther } kind = kOther;
  std::string text;  // a word, a string's content (between the quotes, as POV-Ray keeps it), a character
  int line = 0;
};

// POV-Ray's tokenizer as far as file names are concerned (source/backend/parser/tokenize.cpp
// of 3.7): whitespace, // and nested /* */ comments, string literals ("\"" is a quote, any
// other backslash stays), words [A-Za-z_][A-Za-z0-9_]*, numbers (skipped), single characters.
// Tokens are made on demand and only a few are kept (a mesh include may hold 10^7 of them).
class Lexer {
 public:
  explicit Lexer(const std::string& s) : s_(s) {}

  // Token i (counted from the start), or nullptr past the end; tokens before `keep_from`
  // (the last value passed to forget_before) are no longer available.
  const Token* at(std::size_t i) {
    while (base_ + window_.size() <= i) {
      Token t;
      if (!next(&t)) return nullptr;
      window_.push_back(std::move(t));
    }
    return &window_[i - base_];
  }
  void forget_before(std::size_t i) {
    while (base_ < i && !window_.empty()) {
      window_.pop_front();
      ++base_;
    }
  }

 private:
  char peek(std::size_t k) const { return k < s_.size() ? s_[k] : '\0'; }
  static bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

  bool next(Token* t) {
    const std::size_t n = s_.size();
    while (i_ < n) {
      const char c = s_[i_];
      if (c == '\n') {
        ++line_;
        ++i_;
      } else if (c == '/' && peek(i_ + 1) == '/') {
        while (i_ < n && s_[i_] != '\n') ++i_;
      } else if (c == '/' && peek(i_ + 1) == '*') {
        int depth = 1;
        i_ += 2;
        while (i_ < n && depth > 0) {
          if (s_[i_] == '\n') ++line_;
          if (s_[i_] == '*' && peek(i_ + 1) == '/') {
            --depth;
            i_ += 2;
          } else if (s_[i_] == '/' && peek(i_ + 1) == '*') {
            ++depth;
            i_ += 2;
          } else {
            ++i_;
          }
        }
      } else if (c == '"') {
        *t = Token{Token::kString, "", line_};
        ++i_;
        while (i_ < n && s_[i_] != '"') {
          if (s_[i_] == '\\' && i_ + 1 < n) {
            if (s_[i_ + 1] != '"') t->text += '\\';
            if (s_[i_ + 1] == '\n') ++line_;
            t->text += s_[i_ + 1];
            i_ += 2;
            continue;
          }
          if (s_[i_] == '\n') ++line_;
          t->text += s_[i_++];
        }
        ++i_;  // the closing quote (an unterminated string is POV-Ray's error)
        return true;
      } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        *t = Token{Token::kWord, "", line_};
        const std::size_t b = i_;
        while (i_ < n && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) ++i_;
        t->text.assign(s_, b, i_ - b);
        return true;
      } else if (digit(c) || c == '.') {
        // A number: digits and points, an exponent only when digits follow (so "3include" is 3
        // and the keyword include, as for POV-Ray).
        while (i_ < n && (digit(s_[i_]) || s_[i_] == '.')) ++i_;
        if (i_ < n && (s_[i_] == 'e' || s_[i_] == 'E')) {
          std::size_t j = i_ + 1;
          if (j < n && (s_[j] == '+' || s_[j] == '-')) ++j;
          if (j < n && digit(s_[j])) {
            while (j < n && digit(s_[j])) ++j;
            i_ = j;
          }
        }
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++i_;
      } else {
        *t = Token{Token::kOther, std::string(1, c), line_};
        ++i_;
        return true;
      }
    }
    return false;
  }

  const std::string& s_;
  std::size_t i_ = 0;
  int line_ = 1;
  std::deque<Token> window_;
  std::size_t base_ = 0;  // index of window_.front()
};

// File name extensions POV-Ray tries for a keyword (source/backend/support/fileutil.cpp).
std::vector<std::string> extensions_of(const std::string& keyword) {
  if (keyword == "include") return {".inc", ".INC"};
  if (keyword == "jpeg") return {".jpg", ".JPG", ".jpeg", ".JPEG"};
  if (keyword == "tiff") return {".tif", ".TIF", ".tiff", ".TIFF"};
  if (keyword == "sys") return {".png", ".PNG"};
  if (keyword == "fopen") return {};
  std::string upper = keyword;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return {"." + keyword, "." + upper};
}

// Keywords whose next token is a file name: images, density files, fonts.
bool is_file_keyword(const std::string& w) {
  static const std::set<std::string> k = {"gif",  "tga", "iff", "ppm", "pgm", "png", "jpeg",
                                          "tiff", "sys", "exr", "hdr", "bmp", "df3", "ttf"};
  return k.count(w) > 0;
}

// Macros of POV-Ray's standard include files that write, or #include, a file whose name the
// caller passes (arrays.inc, makegrass.inc, meshmaker.inc, shapes.inc, strings.inc of 3.7):
// refused when nothing but this check confines POV-Ray.
bool is_writing_macro(const std::string& w) {
  static const std::set<std::string> k = {
      "ARRAYS_WriteDF3", "MakeGrassPatch", "MakePrairie",  "BuildWriteMesh2", "CheckFileName", "MSM",
      "Parametric",      "Paramcalc",      "Prism",        "Prism1",          "Lathe",         "Coons",
      "TwoVarSurf",      "SweepSpline1",   "SweepSpline2", "HF_Square",       "HF_Sphere",     "HF_Cylinder",
      "HF_Torus",        "HFCreate_",      "Parse_String"};
  return k.count(w) > 0;
}

bool is_regular(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string real_path(const std::string& path) {
  char buf[PATH_MAX];
  return ::realpath(path.c_str(), buf) != nullptr ? std::string(buf) : std::string();
}

bool inside(const std::string& path, const std::string& dir) {
  return path.size() > dir.size() && path.compare(0, dir.size(), dir) == 0 &&
         (dir == "/" || path[dir.size()] == '/');
}

// The name rules: relative, no ".." component, no backslash (POV-Ray decodes escapes later),
// no control byte. Returns the reason a name breaks them, or "".
std::string bad_name(const std::string& name) {
  if (name.empty()) return "an empty file name";
  if (name[0] == '/') return "an absolute path";
  if (name.find('\\') != std::string::npos) return "a backslash";
  for (const char c : name) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "a control byte";
  }
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    if (name.compare(start, end - start, "..") == 0 && end - start == 2) return "a '..' component";
    if (end - start > 1 && name[start] == '.') return "a hidden (dot) component";
    start = end + 1;
  }
  return "";
}

// A name without "." components and repeated slashes.
std::string normal_name(const std::string& name) {
  std::string out;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    const std::string part = name.substr(start, end - start);
    if (!part.empty() && part != ".") out += (out.empty() ? "" : "/") + part;
    start = end + 1;
  }
  return out;
}

class Checker {
 public:
  Checker(std::string dir, bool unconfined) : dir_(std::move(dir)), unconfined_(unconfined) {}

  void check_file(const std::string& path) {
    if (!scanned_.insert(path).second) return;
    files_.push_back(path);
    const std::string text = common::read_file(path);
    Lexer lex(text);
    for (std::size_t k = 0; lex.at(k) != nullptr; ++k) {
      lex.forget_before(k);
      const Token tok = *lex.at(k);
      if (tok.kind == Token::kString) {
        // A string that names a file of the directory (a font or data file passed to a macro):
        // visible to POV-Ray too.
        if (bad_name(tok.text).empty()) resolve(tok.text, "", path, tok.line, false);
        continue;
      }
      if (tok.kind != Token::kWord) continue;
      const std::string& w = tok.text;
      auto fail = [&](const std::string& why) {
        throw common::DataError(
            path, "line " + std::to_string(tok.line) + ": " + why + " (docs/decisions/sandbox.md)");
      };
      auto literal_after = [&](std::size_t at, const std::string& what) -> Token {
        const Token* t = lex.at(at);
        if (t == nullptr || t->kind != Token::kString)
          fail(what + " needs a literal file name, not one built while parsing");
        const std::string why = bad_name(t->text);
        if (!why.empty()) {
          fail(what + " \"" + printable(t->text) + "\": " + why +
               "; an include may read only files of its own directory, named by literal relative paths");
        }
        return *t;
      };
      auto text_at = [&](std::size_t at) {
        const Token* t = lex.at(at);
        return t == nullptr ? std::string() : t->text;
      };
      if (w == "write" || w == "append") {
        fail("'" + w + "': an include may not write files");
      } else if (w == "fopen") {
        // #fopen HANDLE "name" read
        const Token* handle = lex.at(k + 1);
        if (handle == nullptr || handle->kind != Token::kWord) fail("#fopen needs a handle");
        const std::string mode = text_at(k + 3);
        if (mode == "write" || mode == "append")
          fail("#fopen ... " + mode + ": an include may not write files");
        const Token name = literal_after(k + 2, "#fopen");
        if (mode != "read") fail("#fopen needs the mode read");
        resolve(name.text, "fopen", path, tok.line, true);
      } else if (w == "include") {
        const Token name = literal_after(k + 1, "#include");
        for (const auto& f : resolve(name.text, "include", path, tok.line, true)) pending_.push_back(f);
      } else if (w == "file_exists") {
        if (text_at(k + 1) != "(") fail("file_exists needs a literal file name");
        literal_after(k + 2, "file_exists");
      } else if (is_file_keyword(w)) {
        resolve(literal_after(k + 1, "'" + w + "'").text, w, path, tok.line, true);
      } else if (unconfined_ && is_writing_macro(w)) {
        fail("'" + w +
             "' (a macro of POV-Ray's standard includes) writes or includes a file it is given, which "
             "only the sandbox can confine (CANOPY_POVRAY_SANDBOX=off)");
      }
    }
  }

  // Checks `file` and, breadth first, the files of the directory it includes.
  std::vector<std::string> run(const std::string& file) {
    check_file(file);
    while (!pending_.empty()) {
      const std::string next = pending_.front();
      pending_.erase(pending_.begin());
      check_file(next);
    }
    std::sort(files_.begin(), files_.end());
    files_.erase(std::unique(files_.begin(), files_.end()), files_.end());
    return files_;
  }

 private:
  // The files of the directory that `name` (with POV-Ray's extension variants for `keyword`)
  // names; each must resolve inside the directory (a symbolic link out of it is refused when
  // `strict`, i.e. the name is used as a file name, and ignored otherwise).
  std::vector<std::string> resolve(const std::string& name, const std::string& keyword,
                                   const std::string& from, int line, bool strict) {
    std::vector<std::string> found;
    const std::string base = normal_name(name);
    if (base.empty()) return found;
    std::vector<std::string> names = {base};
    if (!keyword.empty()) {
      for (const auto& ext : extensions_of(keyword)) names.push_back(base + ext);
    }
    for (const auto& nm : names) {
      const std::string path = dir_ + "/" + nm;
      if (!is_regular(path)) continue;
      const std::string real = real_path(path);
      if (!inside(real, real_dir_())) {
        if (!strict) continue;
        throw common::DataError(from, "line " + std::to_string(line) + ": \"" + printable(name) +
                                          "\" leads out of the include's directory " + dir_ +
                                          " (a symbolic link to " + printable(real) + ")");
      }
      found.push_back(path);
      if (std::find(files_.begin(), files_.end(), path) == files_.end()) files_.push_back(path);
    }
    return found;
  }

  const std::string& real_dir_() {
    if (real_dir_cache_.empty()) real_dir_cache_ = real_path(dir_);
    return real_dir_cache_;
  }

  std::string dir_;
  bool unconfined_;
  std::string real_dir_cache_;
  std::set<std::string> scanned_;
  std::vector<std::string> pending_;
  std::vector<std::string> files_;
};

}  // namespace

// Here rather than in sandbox.cpp, so that the model and recipe readers link without the
// process code (fuzz/).
SandboxMode sandbox_mode() {
  const char* env = std::getenv("CANOPY_POVRAY_SANDBOX");
  const std::string v = env != nullptr && *env != '\0' ? env : "auto";
  if (v == "auto") return SandboxMode::kAuto;
  if (v == "bwrap") return SandboxMode::kBwrap;
  if (v == "off") return SandboxMode::kOff;
  throw common::UsageError("CANOPY_POVRAY_SANDBOX='" + printable(v) + "': expected auto, bwrap or off");
}

std::vector<std::string> check_user_include(const std::string& dir, const std::string& file, bool unconfined) {
  if (dir == "/") {
    throw common::DataError("/" + file,
                            "an include directly in / would make the whole file system its directory: put it "
                            "in a directory of its own");
  }
  Checker checker(dir, unconfined);
  return checker.run(dir + "/" + file);
}

}  // namespace canopy::sim
