#include "canopy/formats/las_crs.h"

#include <sys/stat.h>

#include <cctype>
#include <cstdint>
#include <cstring>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::formats {
namespace {

constexpr std::uint16_t kGeoKeys = 34735, kWkt = 2112;
constexpr int kMaxDepth = 32;
constexpr std::size_t kMaxKeyword = 64;  // WKT's longest is 20 (e.g. PARAMETRICUNIT)

std::uint32_t u16(const unsigned char* p) { return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8; }

// A WKT node: KEYWORD[values and nodes], the keyword upper-cased.
struct Node {
  std::string key;
  std::vector<std::string> values;  // quoted strings (unquoted) and bare words, in order
  std::vector<Node> children;
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
    while (i_ < t_.size() && word_char(t_[i_]))
      n.key += static_cast<char>(std::toupper(static_cast<unsigned char>(t_[i_++])));
    if (n.key.empty() || !std::isalpha(static_cast<unsigned char>(n.key[0]))) fail("a keyword expected");
    if (n.key.size() > kMaxKeyword) fail("a keyword over " + std::to_string(kMaxKeyword) + " characters");
    space();
    if (i_ >= t_.size() || (t_[i_] != '[' && t_[i_] != '(')) fail("'[' expected after " + n.key);
    const char close = t_[i_++] == '[' ? ']' : ')';
    space();
    if (i_ < t_.size() && t_[i_] == close) {
      ++i_;
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
      ++i_;
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

EpsgCode crs_code(const Node& n, const std::string& path, int depth) {
  if (horizontal(n)) return authority(n, path);
  if (is_one_of(n.key, {"COMPD_CS", "COMPOUNDCRS"})) {
    for (const Node& c : n.children) {
      if (!horizontal(c)) continue;
      EpsgCode h = authority(c, path + n.key + "'s ");
      if (h.code != 0) return h;
      break;
    }
    EpsgCode own = authority(n, path);
    if (own.code == 0)
      own.problem = "the WKT's " + path + n.key + " names no EPSG code (nor its horizontal part)";
    return own;
  }
  if (n.key == "BOUNDCRS" && depth < 2) {
    for (const Node& c : n.children) {
      if (c.key == "SOURCECRS" && !c.children.empty())
        return crs_code(c.children[0], path + "BOUNDCRS's SOURCECRS's ", depth + 1);
    }
  }
  return EpsgCode{0, "",
                  "the WKT's outermost node is " + n.key + ", not a projected, geographic or compound CRS"};
}

}  // namespace

EpsgCode epsg_from_geokeys(const std::string& payload) {
  const std::size_t len = payload.size();
  if (len < 8)
    return EpsgCode{0, "", "GeoKey directory of " + std::to_string(len) + " bytes (its header has 8)"};
  const auto* d = reinterpret_cast<const unsigned char*>(payload.data());
  const std::size_t keys = u16(d + 6);
  if ((len - 8) / 8 < keys) {
    return EpsgCode{0, "",
                    "GeoKey directory says " + std::to_string(keys) + " keys but holds " +
                        std::to_string((len - 8) / 8) + " (cut short)"};
  }
  // The keys' inline values (location 0, count 1); -1 = absent.
  long model = -1, projected = -1, geographic = -1;
  for (std::size_t k = 0; k < keys; ++k) {
    const unsigned char* e = d + 8 + 8 * k;
    if (u16(e + 2) != 0 || u16(e + 4) != 1) continue;
    const long v = u16(e + 6);
    switch (u16(e)) {
      case 1024: model = v; break;
      case 3072: projected = v; break;
      case 2048: geographic = v; break;
      default: break;
    }
  }
  auto code_of = [](long v, const char* key) -> EpsgCode {
    if (v >= 1024 && v <= 32766)  // GeoTIFF: 1-1023 obsolete or reserved, 32767 user-defined
      return EpsgCode{static_cast<int>(v), std::string(key) + " " + std::to_string(v), ""};
    return EpsgCode{0, "",
                    std::string(key) + " is " + std::to_string(v) +
                        (v == 32767 ? " (user-defined): no EPSG code" : " (not an EPSG code)")};
  };
  if (projected >= 0) return code_of(projected, "ProjectedCSTypeGeoKey");
  if (geographic >= 0 && (model == 2 || model < 0)) return code_of(geographic, "GeographicTypeGeoKey");
  return EpsgCode{0, "",
                  model == 3   ? "the GeoTIFF keys give a geocentric model (no map coordinates)"
                  : model == 1 ? "the GeoTIFF keys give a projected model without ProjectedCSTypeGeoKey"
                               : "the GeoTIFF keys hold no ProjectedCSTypeGeoKey or GeographicTypeGeoKey"};
}

EpsgCode epsg_from_wkt(const std::string& wkt) {
  const std::string text = wkt.substr(0, strnlen(wkt.data(), wkt.size()));
  try {
    const Node root = WktParser(text).root();
    return crs_code(root, "", 0);
  } catch (const Malformed& m) { return EpsgCode{0, "", "the WKT is not well-formed (" + m.why + ")"}; }
}

std::string LasCrs::code() const { return epsg > 0 ? "EPSG:" + std::to_string(epsg) : ""; }

LasCrs las_crs(const LasHeaderBlock& header) {
  const LasVlr *keys = nullptr, *wkt = nullptr, *liblas_wkt = nullptr;
  for (const LasVlr& v : header.vlrs) {
    if (v.user_id == "LASF_Projection" && v.record_id == kGeoKeys && keys == nullptr) keys = &v;
    if (v.user_id == "LASF_Projection" && v.record_id == kWkt && wkt == nullptr) wkt = &v;
    if (v.user_id == "liblas" && v.record_id == kWkt && liblas_wkt == nullptr) liblas_wkt = &v;
  }
  if (wkt == nullptr) wkt = liblas_wkt;
  struct Read {
    EpsgCode code;
    std::string record;
  };
  std::vector<Read> reads;
  // The WKT bit of the global encoding is LAS 1.4's (reserved before).
  const bool wkt_first = header.major == 1 && header.minor >= 4 && (header.global_encoding & 16) != 0;
  auto add_keys = [&] {
    if (keys != nullptr)
      reads.push_back({epsg_from_geokeys(keys->payload), "LASF_Projection 34735 (GeoTIFF keys)"});
  };
  auto add_wkt = [&] {
    if (wkt != nullptr) reads.push_back({epsg_from_wkt(wkt->payload), wkt->user_id + " 2112 (OGC WKT)"});
  };
  if (wkt_first) {
    add_wkt();
    add_keys();
  } else {
    add_keys();
    add_wkt();
  }
  LasCrs out;
  std::string problems;
  for (const Read& r : reads) {
    if (r.code.code == 0) {
      problems += (problems.empty() ? "" : "; ") + r.record + ": " + r.code.problem;
      continue;
    }
    if (out.epsg == 0) {
      out.epsg = r.code.code;
      out.from = r.record + ": " + r.code.from;
    } else if (r.code.code != out.epsg) {
      out.note =
          "its " + out.from.substr(0, out.from.find(':')) + " gives EPSG:" + std::to_string(out.epsg) +
          ", its " + r.record + " EPSG:" + std::to_string(r.code.code) + "; the first taken (" +
          (wkt_first ? "the global encoding's WKT bit is set" : "the global encoding's WKT bit is clear") +
          ")";
    }
  }
  if (out.epsg == 0) out.note = problems;
  return out;
}

LasCrs read_las_crs(const std::string& path) {
  struct stat st {};
  // Standard input, a FIFO or a device cannot be read again.
  if (path == "-" || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};
  try {
    return las_crs(read_las_header_block(path));
  } catch (const common::DataError&) { return {}; }
}

}  // namespace canopy::formats
