#include "canopy/formats/las_crs.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/printable.h"

namespace canopy::formats {
namespace {

constexpr std::uint16_t kGeoKeys = 34735, kWkt = 2112;
constexpr int kMaxDepth = 32;
constexpr std::size_t kMaxKeyword = 64;      // WKT's longest is 20 (e.g. PARAMETRICUNIT)
constexpr std::size_t kMaxUnitSource = 200;  // a unit node's text in LinearUnit::source, at most

std::uint32_t u16(const unsigned char* p) { return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8; }

// A WKT node: KEYWORD[values and nodes], the keyword upper-cased.
struct Node {
  std::string key;
  std::vector<std::string> values;  // quoted strings (unquoted) and bare words, in order
  std::vector<Node> children;
  std::size_t begin = 0, end = 0;  // the node's bytes in the text: its keyword to its closing bracket
};

struct Malformed {
  std::string why;
};

class WktParser {
 public:
  explicit WktParser(const std::string& t) : t_(t) {}

  Node root() {
    Node n = node(0);
    space();
    if (i_ < t_.size()) fail("text after the outermost node");
    return n;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Malformed{"byte " + std::to_string(i_) + ": " + what};
  }
  void space() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
  }
  static bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

  Node node(int depth) {
    if (depth >= kMaxDepth) fail("nested deeper than " + std::to_string(kMaxDepth) + " levels");
    space();
    Node n;
    n.begin = i_;
    while (i_ < t_.size() && word_char(t_[i_]))
      n.key += static_cast<char>(std::toupper(static_cast<unsigned char>(t_[i_++])));
    if (n.key.empty() || !std::isalpha(static_cast<unsigned char>(n.key[0]))) fail("a keyword expected");
    if (n.key.size() > kMaxKeyword) fail("a keyword over " + std::to_string(kMaxKeyword) + " characters");
    space();
    if (i_ >= t_.size() || (t_[i_] != '[' && t_[i_] != '(')) fail("'[' expected after " + n.key);
    const char close = t_[i_++] == '[' ? ']' : ')';
    space();
    if (i_ < t_.size() && t_[i_] == close) {
      n.end = ++i_;
      return n;
    }
    for (;;) {
      arg(depth, &n);
      space();
      if (i_ >= t_.size()) fail(n.key + " not closed (cut short?)");
      if (t_[i_] == ',') {
        ++i_;
        continue;
      }
      if (t_[i_] != close) fail("',' or '" + std::string(1, close) + "' expected in " + n.key);
      n.end = ++i_;
      return n;
    }
  }

  void arg(int depth, Node* parent) {
    space();
    if (i_ >= t_.size()) fail(parent->key + " not closed (cut short?)");
    if (t_[i_] == '"') {
      std::string s;
      for (++i_;; ++i_) {
        if (i_ >= t_.size()) fail("a quoted string not closed (cut short?)");
        if (t_[i_] == '"') {
          if (i_ + 1 < t_.size() && t_[i_ + 1] == '"') {
            s += '"';
            ++i_;
            continue;
          }
          ++i_;
          break;
        }
        s += t_[i_];
      }
      parent->values.push_back(std::move(s));
      return;
    }
    // A bare word or number, or a nested node (a word followed by a bracket).
    const std::size_t start = i_;
    while (i_ < t_.size() && t_[i_] != ',' && t_[i_] != '[' && t_[i_] != '(' && t_[i_] != ']' &&
           t_[i_] != ')' && t_[i_] != '"')
      ++i_;
    if (i_ < t_.size() && (t_[i_] == '[' || t_[i_] == '(')) {
      i_ = start;
      parent->children.push_back(node(depth + 1));
      return;
    }
    std::size_t end = i_;
    while (end > start && std::isspace(static_cast<unsigned char>(t_[end - 1]))) --end;
    if (end == start) fail("a value expected in " + parent->key);
    parent->values.push_back(t_.substr(start, end - start));
  }

  const std::string& t_;
  std::size_t i_ = 0;
};

bool is_one_of(const std::string& key, std::initializer_list<const char*> keys) {
  for (const char* k : keys) {
    if (key == k) return true;
  }
  return false;
}

bool horizontal(const Node& n) {
  if (is_one_of(n.key, {"PROJCS", "PROJCRS", "PROJECTEDCRS", "GEOGCS", "GEOGCRS", "GEOGRAPHICCRS"}))
    return true;
  // WKT2-2015's geodetic CRS is geographic when its coordinate system is ellipsoidal (else
  // geocentric: no map coordinates).
  if (!is_one_of(n.key, {"GEODCRS", "GEODETICCRS"})) return false;
  for (const Node& c : n.children) {
    if (c.key != "CS" || c.values.empty()) continue;
    std::string type = c.values[0];
    for (char& ch : type) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return type == "ellipsoidal";
  }
  return false;
}

// An EPSG code: 1 to 6 digits, > 0.
int epsg_number(const std::string& s) {
  if (s.empty() || s.size() > 6) return 0;
  int v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return 0;
    v = 10 * v + (c - '0');
  }
  return v;
}

// The first AUTHORITY["EPSG", code] or ID["EPSG", code] that is a direct child of `n`.
EpsgCode authority(const Node& n, const std::string& path) {
  for (const Node& c : n.children) {
    if (c.key != "AUTHORITY" && c.key != "ID") continue;
    if (c.values.size() < 2) continue;
    std::string name = c.values[0];
    for (char& ch : name) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    if (name != "EPSG") continue;
    if (const int code = epsg_number(c.values[1])) {
      return EpsgCode{code, path + n.key + " " + c.key + " EPSG " + std::to_string(code), ""};
    }
  }
  return EpsgCode{0, "", "the WKT's " + path + n.key + " names no EPSG code"};
}

bool projected(const Node& n) { return is_one_of(n.key, {"PROJCS", "PROJCRS", "PROJECTEDCRS"}); }

// A unit node (UNIT["name",factor,...], LENGTHUNIT[...]) as a linear unit; none when its
// factor is not a number > 0.
std::optional<LinearUnit> linear_unit(const Node& u, const std::string& text) {
  if (u.values.size() < 2) return std::nullopt;
  const std::string& f = u.values[1];
  char* end = nullptr;
  const double factor = std::strtod(f.c_str(), &end);
  if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(factor) || !(factor > 0))
    return std::nullopt;
  // One line: whitespace runs as one space, control bytes as \xNN (common::printable), at most
  // kMaxUnitSource bytes and "..." when cut.
  auto line = [](const std::string& t, std::size_t from, std::size_t to) {
    std::string out;
    std::size_t i = from;
    for (; i < to && out.size() < kMaxUnitSource; ++i) {
      const auto c = static_cast<unsigned char>(t[i]);
      if (!std::isspace(c)) {
        out += static_cast<char>(c);
      } else if (out.empty() || out.back() != ' ') {
        out += ' ';
      }
    }
    bool cut = i < to;
    out = common::printable(out);
    if (out.size() > kMaxUnitSource) {
      out.resize(kMaxUnitSource);
      cut = true;
    }
    return cut ? out + "..." : out;
  };
  return LinearUnit{line(u.values[0], 0, u.values[0].size()), factor, "WKT " + line(text, u.begin, u.end)};
}

// A projected CRS's own linear unit: its UNIT or LENGTHUNIT (WKT 1, and WKT 2's CS-wide unit),
// else its first AXIS's (WKT 2 may give the unit per axis). Never a nested CRS's.
std::optional<LinearUnit> own_unit(const Node& n, const std::string& text) {
  if (!projected(n)) return std::nullopt;
  auto unit_child = [](const Node& p) -> const Node* {
    for (const Node& c : p.children) {
      if (c.key == "UNIT" || c.key == "LENGTHUNIT") return &c;
    }
    return nullptr;
  };
  const Node* u = unit_child(n);
  if (u == nullptr) {
    const auto axis =
        std::find_if(n.children.begin(), n.children.end(), [](const Node& c) { return c.key == "AXIS"; });
    if (axis != n.children.end()) u = unit_child(*axis);
  }
  return u != nullptr ? linear_unit(*u, text) : std::nullopt;
}

// The code and the unit of the CRS `n` (the outermost node, or a BOUNDCRS's source): both read
// from the same horizontal CRS.
CrsRecord crs_record(const Node& n, const std::string& text, const std::string& path, int depth) {
  if (horizontal(n)) return {authority(n, path), own_unit(n, text)};
  if (is_one_of(n.key, {"COMPD_CS", "COMPOUNDCRS"})) {
    const auto h = std::find_if(n.children.begin(), n.children.end(), horizontal);
    std::optional<LinearUnit> unit;
    if (h != n.children.end()) {
      EpsgCode code = authority(*h, path + n.key + "'s ");
      unit = own_unit(*h, text);
      if (code.code != 0) return {code, unit};
    }
    EpsgCode own = authority(n, path);
    if (own.code == 0)
      own.problem = "the WKT's " + path + n.key + " names no EPSG code (nor its horizontal part)";
    return {own, unit};
  }
  if (n.key == "BOUNDCRS" && depth < 2) {
    for (const Node& c : n.children) {
      if (c.key == "SOURCECRS" && !c.children.empty())
        return crs_record(c.children[0], text, path + "BOUNDCRS's SOURCECRS's ", depth + 1);
    }
  }
  return {EpsgCode{0, "",
                   "the WKT's outermost node is " + n.key + ", not a projected, geographic or compound CRS"},
          std::nullopt};
}

// A GeoTIFF ProjLinearUnitsGeoKey value as a unit.
LinearUnit geotiff_unit(std::uint32_t code) {
  const std::string source = "GeoTIFF key ProjLinearUnits = " + std::to_string(code);
  switch (code) {
    case 9001: return LinearUnit{"metre", 1.0, source};
    case 9002: return LinearUnit{"foot", 0.3048, source};
    case 9003: return LinearUnit{"US survey foot", 1200.0 / 3937.0, source};
    default: return LinearUnit{"EPSG unit " + std::to_string(code), 0.0, source};
  }
}

}  // namespace

CrsRecord read_geokeys(const std::string& payload) {
  const std::size_t len = payload.size();
  if (len < 8)
    return {EpsgCode{0, "", "GeoKey directory of " + std::to_string(len) + " bytes (its header has 8)"},
            std::nullopt};
  const auto* d = reinterpret_cast<const unsigned char*>(payload.data());
  const std::size_t keys = u16(d + 6), held = (len - 8) / 8;
  // The keys' inline values (location 0, count 1); -1 = absent. Only the keys the payload holds.
  long model = -1, projected = -1, geographic = -1, linear = -1;
  for (std::size_t k = 0; k < std::min(keys, held); ++k) {
    const unsigned char* e = d + 8 + 8 * k;
    if (u16(e + 2) != 0 || u16(e + 4) != 1) continue;
    const long v = u16(e + 6);
    switch (u16(e)) {
      case 1024: model = v; break;
      case 3072: projected = v; break;
      case 2048: geographic = v; break;
      case 3076:
        if (linear < 0) linear = v;
        break;
      default: break;
    }
  }
  CrsRecord out;
  if (linear >= 0) out.unit = geotiff_unit(static_cast<std::uint32_t>(linear));
  if (held < keys) {
    out.code = EpsgCode{0, "",
                        "GeoKey directory says " + std::to_string(keys) + " keys but holds " +
                            std::to_string(held) + " (cut short)"};
    return out;
  }
  auto code_of = [](long v, const char* key) -> EpsgCode {
    if (v >= 1024 && v <= 32766)  // GeoTIFF: 1-1023 obsolete or reserved, 32767 user-defined
      return EpsgCode{static_cast<int>(v), std::string(key) + " " + std::to_string(v), ""};
    return EpsgCode{0, "",
                    std::string(key) + " is " + std::to_string(v) +
                        (v == 32767 ? " (user-defined): no EPSG code" : " (not an EPSG code)")};
  };
  if (projected >= 0) {
    out.code = code_of(projected, "ProjectedCSTypeGeoKey");
  } else if (geographic >= 0 && (model == 2 || model < 0)) {
    out.code = code_of(geographic, "GeographicTypeGeoKey");
  } else {
    out.code =
        EpsgCode{0, "",
                 model == 3   ? "the GeoTIFF keys give a geocentric model (no map coordinates)"
                 : model == 1 ? "the GeoTIFF keys give a projected model without ProjectedCSTypeGeoKey"
                              : "the GeoTIFF keys hold no ProjectedCSTypeGeoKey or GeographicTypeGeoKey"};
  }
  return out;
}

EpsgCode epsg_from_geokeys(const std::string& payload) { return read_geokeys(payload).code; }

CrsRecord read_wkt(const std::string& wkt) {
  const std::string text = wkt.substr(0, strnlen(wkt.data(), wkt.size()));
  try {
    const Node root = WktParser(text).root();
    return crs_record(root, text, "", 0);
  } catch (const Malformed& m) {
    return {EpsgCode{0, "", "the WKT is not well-formed (" + m.why + ")"}, std::nullopt};
  }
}

EpsgCode epsg_from_wkt(const std::string& wkt) { return read_wkt(wkt).code; }

std::string LasCrs::code() const { return epsg > 0 ? "EPSG:" + std::to_string(epsg) : ""; }

bool is_epsg_code(const std::string& text) {
  // As canopy writes one: epsg_number's digits, without a leading zero.
  return text.compare(0, 5, "EPSG:") == 0 && text.size() > 5 && text[5] != '0' &&
         epsg_number(text.substr(5)) > 0;
}

bool is_crs_record(const std::string& user_id, std::uint16_t record_id) {
  return (user_id == "LASF_Projection" && (record_id == kGeoKeys || record_id == kWkt)) ||
         (user_id == "liblas" && record_id == kWkt);
}

LasCrs las_crs(const LasHeaderBlock& header) {
  struct Read {
    CrsRecord read;
    std::string record;
    bool evlr = false;
  };
  std::vector<Read> reads;
  // The WKT bit of the global encoding is LAS 1.4's (reserved before).
  const bool wkt_first = header.major == 1 && header.minor >= 4 && (header.global_encoding & 16) != 0;
  // The records of one list (the VLRs, then the EVLRs), in the order the WKT bit says.
  auto add = [&](const std::vector<LasVlr>& records, bool evlr) {
    const LasVlr *keys = nullptr, *wkt = nullptr, *liblas_wkt = nullptr;
    for (const LasVlr& v : records) {
      if (v.user_id == "LASF_Projection" && v.record_id == kGeoKeys && keys == nullptr) keys = &v;
      if (v.user_id == "LASF_Projection" && v.record_id == kWkt && wkt == nullptr) wkt = &v;
      if (v.user_id == "liblas" && v.record_id == kWkt && liblas_wkt == nullptr) liblas_wkt = &v;
    }
    if (wkt == nullptr) wkt = liblas_wkt;
    const std::string kind = evlr ? "EVLR " : "";
    auto add_keys = [&] {
      if (keys != nullptr)
        reads.push_back({read_geokeys(keys->payload), kind + "LASF_Projection 34735 (GeoTIFF keys)", evlr});
    };
    auto add_wkt = [&] {
      if (wkt != nullptr)
        reads.push_back({read_wkt(wkt->payload), kind + wkt->user_id + " 2112 (OGC WKT)", evlr});
    };
    if (wkt_first) {
      add_wkt();
      add_keys();
    } else {
      add_keys();
      add_wkt();
    }
  };
  add(header.vlrs, false);
  add(header.evlrs, true);
  LasCrs out;
  std::string problems;
  bool from_evlr = false;
  for (const Read& r : reads) {
    if (!out.unit) out.unit = r.read.unit;
    const EpsgCode& code = r.read.code;
    if (code.code == 0) {
      problems += (problems.empty() ? "" : "; ") + r.record + ": " + code.problem;
      continue;
    }
    if (out.epsg == 0) {
      out.epsg = code.code;
      out.from = r.record + ": " + code.from;
      from_evlr = r.evlr;
    } else if (code.code != out.epsg) {
      out.note = "its " + out.from.substr(0, out.from.find(':')) + " gives EPSG:" + std::to_string(out.epsg) +
                 ", its " + r.record + " EPSG:" + std::to_string(code.code) + "; the first taken (" +
                 (r.evlr && !from_evlr ? "a VLR before an EVLR"
                  : wkt_first          ? "the global encoding's WKT bit is set"
                                       : "the global encoding's WKT bit is clear") +
                 ")";
    }
  }
  if (out.epsg == 0) {
    if (!header.evlr_note.empty()) problems += (problems.empty() ? "" : "; ") + header.evlr_note;
    out.note = problems;
  }
  return out;
}

LasCrs read_las_crs(const std::string& path) {
  struct stat st {};
  // Standard input, a FIFO or a device cannot be read again (read_points hands back its block).
  if (path == "-" || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};
  try {
    return las_crs(read_las_header_block(path));
  } catch (const common::DataError&) { return {}; }
}

}  // namespace canopy::formats
