#include "canopy/formats/ply.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>

#include "binary_io.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/provenance.h"

namespace canopy::formats {
namespace detail {

std::string format_value(double v, FieldType type) {
  if (type.kind != 'F') {  // the value the binary writer would store: rounded, clamped
    double lo = 0, hi = 4294967295.0;
    if (type.kind == 'U')
      hi = type.size == 1 ? 255.0 : type.size == 2 ? 65535.0 : hi;
    else if (type.size == 1)
      lo = -128, hi = 127;
    else if (type.size == 2)
      lo = -32768, hi = 32767;
    else
      lo = -2147483648.0, hi = 2147483647.0;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", std::isnan(v) ? 0.0 : std::min(hi, std::max(lo, std::nearbyint(v))));
    return buf;
  }
  char buf[64];
  for (int prec = 1; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    const double back = std::strtod(buf, nullptr);
    if (type.size == 4 ? static_cast<float>(back) == static_cast<float>(v) : back == v) break;
  }
  return buf;
}

}  // namespace detail

namespace {

using common::DataError;

struct Property {
  std::string name;
  FieldType type;
  bool is_list = false;
  FieldType count_type;
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> props;
};

// Sane limit on the properties of one element (formats/README.md).
constexpr std::size_t kMaxProperties = 4096;

bool ply_type(const std::string& t, FieldType* out) {
  static const std::pair<const char*, FieldType> kTypes[] = {
      {"char", {'I', 1}},  {"int8", {'I', 1}},    {"uchar", {'U', 1}},  {"uint8", {'U', 1}},
      {"short", {'I', 2}}, {"int16", {'I', 2}},   {"ushort", {'U', 2}}, {"uint16", {'U', 2}},
      {"int", {'I', 4}},   {"int32", {'I', 4}},   {"uint", {'U', 4}},   {"uint32", {'U', 4}},
      {"float", {'F', 4}}, {"float32", {'F', 4}}, {"double", {'F', 8}}, {"float64", {'F', 8}}};
  for (const auto& [n, ft] : kTypes) {
    if (t == n) {
      *out = ft;
      return true;
    }
  }
  return false;
}

const char* ply_type_name(FieldType t) {
  if (t.kind == 'F') return t.size == 4 ? "float" : "double";
  if (t.kind == 'U') return t.size == 1 ? "uchar" : t.size == 2 ? "ushort" : "uint";
  return t.size == 1 ? "char" : t.size == 2 ? "short" : "int";
}

std::string to_file_name(const std::string& col) {
  if (col == "normal_x") return "nx";
  if (col == "normal_y") return "ny";
  if (col == "normal_z") return "nz";
  return col;
}

std::string from_file_name(const std::string& prop) {
  if (prop == "nx") return "normal_x";
  if (prop == "ny") return "normal_y";
  if (prop == "nz") return "normal_z";
  return prop;
}

// Sequential reader over the body in one of the three encodings.
class Body {
 public:
  Body(const std::string& bytes, std::size_t pos, int encoding, const std::string& name)
      : bytes_(bytes), pos_(pos), enc_(encoding), name_(name) {}

  std::size_t remaining() const { return bytes_.size() - std::min(pos_, bytes_.size()); }
  std::size_t position() const { return pos_; }

  // The next value, of type t, of property `prop` (for messages).
  double next(FieldType t, const std::string& prop) {
    if (enc_ == 0) {
      const char* p = bytes_.c_str() + pos_;
      const char* end = bytes_.c_str() + bytes_.size();
      while (p < end && is_space(*p)) ++p;
      if (p >= end)
        throw DataError(name_,
                        "data truncated (ascii body ends early, in property '" + detail::quote(prop) + "')");
      char* q = nullptr;
      const double v = std::strtod(p, &q);
      if (q == p || (q < end && !is_space(*q))) {
        const char* e = p;
        while (e < end && !is_space(*e)) ++e;
        throw DataError(name_, "property '" + detail::quote(prop) + "': '" +
                                   detail::quote(p, static_cast<std::size_t>(e - p), 16) +
                                   "' is not a number");
      }
      if (t.kind != 'F') check_int(v, t, prop, p, static_cast<std::size_t>(q - p));
      pos_ = static_cast<std::size_t>(q - bytes_.c_str());
      return t == kFloat32 ? static_cast<float>(v) : v;  // a float property holds a float
    }
    const std::size_t sz = static_cast<std::size_t>(t.size);
    if (sz > remaining()) {
      throw DataError(name_,
                      "data truncated (binary body ends early, in property '" + detail::quote(prop) + "')");
    }
    const double v =
        detail::read_scalar(reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_, t, enc_ == 2);
    pos_ += sz;
    return v;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

  // An ascii value of an integer type must be an integer in the type's range.
  void check_int(double v, FieldType t, const std::string& prop, const char* text, std::size_t len) const {
    double lo = 0, hi = 0;
    if (t.kind == 'U')
      hi = t.size == 1 ? 255.0 : t.size == 2 ? 65535.0 : 4294967295.0;
    else if (t.size == 1) {
      lo = -128;
      hi = 127;
    } else if (t.size == 2) {
      lo = -32768;
      hi = 32767;
    } else {
      lo = -2147483648.0;
      hi = 2147483647.0;
    }
    if (!(v >= lo && v <= hi) || v != std::floor(v)) {
      throw DataError(name_, "property '" + detail::quote(prop) + "': '" + detail::quote(text, len, 24) +
                                 "' is not a " + ply_type_name(t) + " (an integer from " +
                                 detail::format_value(lo, t) + " to " + detail::format_value(hi, t) + ")");
    }
  }

  const std::string& bytes_;
  std::size_t pos_;
  int enc_;  // 0 ascii, 1 little endian, 2 big endian
  const std::string& name_;
};

// Length of the next list of property p of element e, checked against the data left.
std::size_t list_length(Body& body, const Element& e, const Property& p, int encoding, const std::string& name) {
  const double m = body.next(p.count_type, p.name);
  if (!(m >= 0))
    throw DataError(name, "list " + detail::quote(e.name + "." + p.name) + " has a negative length");
  const double per = encoding == 0 ? 2.0 : static_cast<double>(p.type.size);
  if (m * per > static_cast<double>(body.remaining()) + 1.0) {
    throw DataError(name, "data truncated: a list " + detail::quote(e.name + "." + p.name) + " of " +
                              detail::format_value(m, kFloat64) + " items does not fit in the " +
                              std::to_string(body.remaining()) + " bytes left");
  }
  return static_cast<std::size_t>(m);
}

void skip_list(Body& body, const Element& e, const Property& p, int encoding, const std::string& name) {
  const std::size_t m = list_length(body, e, p, encoding, name);
  for (std::size_t j = 0; j < m; ++j) body.next(p.type, p.name);
}

// Fewest bytes one row of an element can take: binary, the scalars and list counts; ascii,
// two bytes ("0 ") per scalar or list count.
std::size_t min_row_bytes(const Element& e, int encoding) {
  std::size_t n = 0;
  for (const auto& p : e.props) {
    n += encoding == 0 ? 2 : static_cast<std::size_t>(p.is_list ? p.count_type.size : p.type.size);
  }
  return n;
}

// The header: elements with their properties, comments, encoding (0 ascii, 1 little endian,
// 2 big endian) and the offset of the body.
struct Header {
  std::vector<Element> elements;
  std::vector<std::string> comments;
  int encoding = -1;
  std::size_t body = 0;
};

// One header line after its keyword: a format, element or property line.
void header_line(const std::string& key, const std::string& line, std::istringstream& ss, Header& h,
                 const std::string& name) {
  std::vector<Element>& elements = h.elements;
  if (key == "format") {
    std::string f, v;
    ss >> f >> v;
    if (f == "ascii")
      h.encoding = 0;
    else if (f == "binary_little_endian")
      h.encoding = 1;
    else if (f == "binary_big_endian")
      h.encoding = 2;
    else
      throw DataError(name, "unknown PLY format '" + detail::quote(f) + "'");
  } else if (key == "element") {
    Element e;
    std::string count, extra;
    ss >> e.name >> count >> extra;
    std::uint64_t c = 0;
    if (e.name.empty() || !extra.empty())
      throw DataError(name, "malformed PLY line '" + detail::quote(line) + "'");
    if (!detail::parse_count(count, std::numeric_limits<std::int64_t>::max(), &c)) {
      throw DataError(name, "element " + detail::quote(e.name) + " count '" + detail::quote(count) +
                                "' is not an integer from 0 to 2^63-1");
    }
    e.count = static_cast<std::size_t>(c);
    elements.push_back(e);
  } else if (key == "property") {
    if (elements.empty()) throw DataError(name, "PLY property before any element");
    Property p;
    std::string t;
    ss >> t;
    if (t == "list") {
      std::string ct, it;
      ss >> ct >> it >> p.name;
      if (!ply_type(ct, &p.count_type) || !ply_type(it, &p.type)) {
        throw DataError(name, "unknown PLY type in '" + detail::quote(line) + "'");
      }
      if (p.count_type.kind == 'F') {
        throw DataError(name, "list count type '" + detail::quote(ct) + "' is not an integer type");
      }
      p.is_list = true;
    } else {
      ss >> p.name;
      if (!ply_type(t, &p.type)) throw DataError(name, "unknown PLY type '" + detail::quote(t) + "'");
    }
    if (p.name.empty()) throw DataError(name, "malformed PLY line '" + detail::quote(line) + "'");
    if (elements.back().props.size() >= kMaxProperties) {
      throw DataError(name, "element " + detail::quote(elements.back().name) + " has more than " +
                                std::to_string(kMaxProperties) + " properties");
    }
    elements.back().props.push_back(p);
  } else {
    throw DataError(name, "unknown PLY header line '" + detail::quote(line) + "'");
  }
}

Header parse_header(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw DataError(name, "empty file (not a PLY file)");
  if (bytes.compare(0, 3, "ply") != 0 || (bytes.size() > 3 && bytes[3] != '\n' && bytes[3] != '\r')) {
    const std::string is = detail::sniff(bytes);
    if (!is.empty() && is != "a PLY file") throw DataError(name, "this is " + is + ", not a PLY file");
    throw DataError(name, "not a PLY file (no 'ply' magic)");
  }
  Header h;
  std::size_t pos = 0;
  while (true) {
    if (pos >= bytes.size()) throw DataError(name, "PLY header has no end_header (truncated?)");
    std::size_t eol = bytes.find('\n', pos);
    const bool last = eol == std::string::npos;
    if (last) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    // The file ends inside a header line: cut there (it read "unknown PLY header line 'elem'").
    if (last && key != "end_header") {
      throw DataError(name, "PLY header truncated: the file ends in its line '" + detail::quote(line) +
                                "', before end_header");
    }
    if (key.empty() || key == "ply" || key == "obj_info") continue;
    if (key == "end_header") break;
    if (key == "comment") {
      h.comments.push_back(line.size() > 8 ? line.substr(8) : "");
    } else {
      header_line(key, line, ss, h, name);
    }
  }
  if (h.encoding < 0) throw DataError(name, "PLY header has no format line");
  h.body = pos;
  return h;
}

// Bounds every allocation by what the body can hold.
void check_counts(const Header& h, const std::string& bytes, const std::string& name) {
  const std::size_t body_size = bytes.size() - std::min(h.body, bytes.size());
  std::uint64_t need = 0;
  for (const auto& e : h.elements) {
    std::uint64_t row = min_row_bytes(e, h.encoding), all = 0;
    if (h.encoding == 0 && row > 0) row -= 1;  // the last value of the file needs no separator
    if (__builtin_mul_overflow(static_cast<std::uint64_t>(e.count), std::max<std::uint64_t>(row, 1), &all) ||
        __builtin_add_overflow(need, all, &need) || need > body_size + (h.encoding == 0 ? 1 : 0)) {
      throw DataError(name, "data truncated: element " + detail::quote(e.name) + " count " +
                                std::to_string(e.count) + " needs more than the " + std::to_string(body_size) +
                                " bytes of data the file holds (truncated file or wrong count)");
    }
  }
}

void read_vertices(Body& body, const Element& e, int encoding, const std::string& name, Mesh& mesh) {
  auto& v = mesh.vertices;
  std::vector<int> cols;
  std::set<std::string> file_names;
  for (const auto& p : e.props) file_names.insert(p.name);
  for (const auto& p : e.props) {
    if (p.is_list) {
      cols.push_back(-1);
      continue;
    }
    std::string col = from_file_name(p.name);
    // CloudCompare's scalar fields: "scalar_f" is read as f (unless f is there too).
    if (col.rfind("scalar_", 0) == 0 && col.size() > 7 && !file_names.count(col.substr(7)))
      col = col.substr(7);
    if (v.has(col)) throw DataError(name, "duplicate vertex property '" + detail::quote(p.name) + "'");
    v.add(col, p.type);
    cols.push_back(static_cast<int>(v.names().size()) - 1);
  }
  v.resize(e.count);
  std::vector<double*> dst;
  for (int c : cols) dst.push_back(c < 0 ? nullptr : v.col(static_cast<std::size_t>(c)).data());
  for (std::size_t i = 0; i < e.count; ++i) {
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      const auto& p = e.props[k];
      if (p.is_list) {
        skip_list(body, e, p, encoding, name);
      } else {
        dst[k][i] = body.next(p.type, p.name);
      }
    }
  }
}

void read_faces(Body& body, const Element& e, int encoding, const std::string& name, Mesh& mesh) {
  int list_prop = -1;
  for (std::size_t k = 0; k < e.props.size(); ++k) {
    if (e.props[k].is_list && (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index")) {
      list_prop = static_cast<int>(k);
    }
  }
  if (list_prop < 0 && e.count > 0) throw DataError(name, "face element has no vertex_indices list");
  if (list_prop >= 0 && e.props[static_cast<std::size_t>(list_prop)].type.kind == 'F') {
    throw DataError(name, "face vertex indices are of a floating-point type");
  }
  mesh.faces.reserve(mesh.faces.size() + e.count);
  std::vector<std::int32_t> idx;
  for (std::size_t i = 0; i < e.count; ++i) {
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      const auto& p = e.props[k];
      if (static_cast<int>(k) != list_prop) {
        if (p.is_list)
          skip_list(body, e, p, encoding, name);
        else
          body.next(p.type, p.name);
        continue;
      }
      const std::size_t m = list_length(body, e, p, encoding, name);
      if (m < 3) throw DataError(name, "face " + std::to_string(i) + " has fewer than 3 vertices");
      idx.resize(m);
      for (auto& x : idx) {
        const double d = body.next(p.type, p.name);
        if (!(d >= -2147483648.0 && d <= 2147483647.0)) {
          throw DataError(
              name, "face " + std::to_string(i) + " refers to vertex " + detail::format_value(d, kFloat64));
        }
        x = static_cast<std::int32_t>(d);
      }
      for (std::size_t j = 1; j + 1 < m; ++j) mesh.faces.push_back({idx[0], idx[j], idx[j + 1]});
    }
  }
}

void skip_element(Body& body, const Element& e, int encoding, const std::string& name) {
  for (std::size_t i = 0; i < e.count; ++i) {
    for (const auto& p : e.props) {
      if (p.is_list)
        skip_list(body, e, p, encoding, name);
      else
        body.next(p.type, p.name);
    }
  }
}

// Nothing but white space (ascii) or nothing at all (binary) after the last element: data
// left over means a count or a list length is wrong (a uchar list count that wrapped 1000 to
// 232 left 3072 bytes of indices; they were ignored).
void check_end(const Body& body, const Header& h, const std::string& bytes, const std::string& name) {
  std::size_t at = body.position();
  if (h.encoding == 0) {
    while (at < bytes.size() &&
           (bytes[at] == ' ' || bytes[at] == '\t' || bytes[at] == '\n' || bytes[at] == '\r')) {
      ++at;
    }
  }
  if (at >= bytes.size()) return;
  const std::size_t left = bytes.size() - at;
  std::string counts;
  bool byte_count = false;  // a list with a one-byte count: a writer may have wrapped it
  for (const auto& e : h.elements) {
    counts += (counts.empty() ? "" : ", ") + std::to_string(e.count) + " " + detail::quote(e.name);
    for (const auto& p : e.props) byte_count = byte_count || (p.is_list && p.count_type.size == 1);
  }
  throw DataError(name,
                  std::to_string(left) + " bytes of data after the last element (the header says " + counts +
                      "): a wrong element count or list length" +
                      (h.encoding != 0 && byte_count ? " (a list of over 255 items in a uchar count?)" : ""));
}

// Face indices within the vertices, finite coordinates.
void check_mesh(const Mesh& mesh, const std::string& name) {
  mesh.vertices.require({"x", "y", "z"}, name, "PLY vertices need x, y, z");
  const auto n = static_cast<std::int64_t>(mesh.vertices.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (auto i : mesh.faces[f]) {
      if (i < 0 || i >= n) {
        throw DataError(name, "face " + std::to_string(f) + " refers to vertex " + std::to_string(i) +
                                  " of " + std::to_string(n));
      }
    }
  }
  for (const char* c : {"x", "y", "z"}) {
    const auto& col = mesh.vertices.col(c);
    for (std::size_t i = 0; i < col.size(); ++i) {
      if (!std::isfinite(col[i])) {
        throw DataError(name, "vertex " + std::to_string(i) + " has a non-finite " + c +
                                  " (NaN or infinite coordinates are not accepted)");
      }
    }
  }
}

}  // namespace

Mesh parse_ply(const std::string& bytes, const std::string& name) {
  const Header h = parse_header(bytes, name);
  check_counts(h, bytes, name);
  Mesh mesh;
  mesh.vertices.comments = h.comments;
  bool have_vertices = false;
  Body body(bytes, h.body, h.encoding, name);
  for (const auto& e : h.elements) {
    if (e.name == "vertex") {
      if (have_vertices) throw DataError(name, "PLY header has two vertex elements");
      have_vertices = true;
      read_vertices(body, e, h.encoding, name, mesh);
    } else if (e.name == "face") {
      read_faces(body, e, h.encoding, name, mesh);
    } else {
      skip_element(body, e, h.encoding, name);
    }
  }
  if (!have_vertices) throw DataError(name, "PLY file has no vertex element");
  check_end(body, h, bytes, name);
  check_mesh(mesh, name);
  return mesh;
}

Mesh read_ply(const std::string& path) { return parse_ply(common::read_file(path), path); }

std::string serialize_ply(const Mesh& mesh, bool ascii) {
  PlyWriteOptions o;
  o.ascii = ascii;
  return serialize_ply(mesh, o);
}

namespace {

// The largest value of the columns `cols` of v, rounded as the writer rounds (-1 when none; NaN
// skipped), read block by block: a packed column (a LAS file's) is not unpacked.
double largest(const PointCloud& v, const std::vector<std::size_t>& cols) {
  double most = -1;
  std::vector<double> buf(std::min<std::size_t>(4096, v.size()));
  for (std::size_t c : cols) {
    for (std::size_t first = 0; first < v.size(); first += buf.size()) {
      const std::size_t k = std::min(buf.size(), v.size() - first);
      v.values(c, first, k, buf.data());
      for (std::size_t i = 0; i < k; ++i) {
        if (std::nearbyint(buf[i]) > most) most = std::nearbyint(buf[i]);
      }
    }
  }
  return most;
}

// A 16-bit colour value as the uchar PLY readers show: its high byte (LAS 1.4 R15: an 8-bit
// colour is stored times 256; a full-range one times 257: both give back the 8-bit value).
double high_byte(double x) {
  if (std::isnan(x)) return 0;
  return std::floor(std::min(65535.0, std::max(0.0, std::nearbyint(x))) / 256);
}

}  // namespace

std::string serialize_ply(const Mesh& mesh, const PlyWriteOptions& options) {
  const bool ascii = options.ascii;
  const auto& v = mesh.vertices;
  std::vector<FieldType> types = v.types();
  // Colours are uchar (MeshLab reads red green blue only as uchar, Open3D divides by 255). When
  // any red, green or blue value is above 255 (LAS colour: 16 bits) the three are written as
  // their high byte; alpha is judged alone. 8-bit colours are written as before (formats/README.md
  // "PLY", docs/decisions/formats.md).
  std::vector<std::size_t> rgb, alpha;
  for (std::size_t c = 0; c < types.size(); ++c) {
    const auto& n = v.names()[c];
    if (n == "red" || n == "green" || n == "blue") rgb.push_back(c);
    if (n == "alpha") alpha.push_back(c);
  }
  std::vector<char> shift(types.size(), 0);
  std::vector<std::string> notes;
  for (const auto* group : {&rgb, &alpha}) {
    const double most = largest(v, *group);
    if (most <= 255) continue;
    std::string names;
    for (std::size_t c : *group) {
      shift[c] = 1;
      names += (names.empty() ? "" : " ") + v.names()[c];
    }
    notes.push_back(names + ": 16-bit values (up to " + std::to_string(static_cast<long long>(most)) +
                    ") written as value / 256 (the high byte)");
  }
  for (std::size_t c = 0; c < types.size(); ++c) {
    const auto& n = v.names()[c];
    if (n == "red" || n == "green" || n == "blue" || n == "alpha") types[c] = kUint8;
    // uint32 as int (Open3D skips uint properties) whenever every value fits.
    if (types[c] == kUint32) {
      const auto& col = v.col(c);
      if (std::all_of(col.begin(), col.end(), [](double x) { return x >= 0 && x <= 2147483647.0; }))
        types[c] = kInt32;
    }
  }
  std::string out = "ply\nformat ";
  out += ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  for (const auto& c : v.comments) out += "comment " + header_safe_comment(c) + "\n";
  for (const auto& c : notes) out += "comment " + c + "\n";
  out += "element vertex " + std::to_string(v.size()) + "\n";
  static const std::set<std::string> kKnown = {"x",        "y",   "z",     "normal_x", "normal_y",
                                               "normal_z", "red", "green", "blue",     "alpha"};
  for (std::size_t c = 0; c < types.size(); ++c) {
    const std::string& n = v.names()[c];
    const std::string prefix = options.scalar_prefix && !kKnown.count(n) ? "scalar_" : "";
    out += std::string("property ") + ply_type_name(types[c]) + " " + prefix + to_file_name(n) + "\n";
  }
  out += "element face " + std::to_string(mesh.faces.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  const std::size_t nc = types.size();
  // Block by block (for_each_block): a packed column (a LAS file's) is written without being
  // unpacked into doubles first.
  if (ascii) {
    for_each_block(v, [&](std::size_t, std::size_t k, const std::vector<const double*>& col) {
      for (std::size_t i = 0; i < k; ++i) {
        for (std::size_t c = 0; c < nc; ++c) {
          out += detail::format_value(shift[c] ? high_byte(col[c][i]) : col[c][i], types[c]);
          out += c + 1 < nc ? " " : "\n";
        }
      }
    });
    for (const auto& f : mesh.faces) {
      out += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    }
  } else {
    std::size_t row = 0;  // bytes a vertex
    for (const FieldType& t : types) row += static_cast<std::size_t>(t.size);
    out.reserve(out.size() + v.size() * row + mesh.faces.size() * 13);  // no regrowth of a large file
    for_each_block(v, [&](std::size_t, std::size_t k, const std::vector<const double*>& col) {
      for (std::size_t i = 0; i < k; ++i) {
        for (std::size_t c = 0; c < nc; ++c)
          detail::write_scalar(&out, shift[c] ? high_byte(col[c][i]) : col[c][i], types[c]);
      }
    });
    for (const auto& f : mesh.faces) {
      out.push_back(3);
      for (auto i : f) detail::put(&out, i);
    }
  }
  return out;
}

void write_ply(const Mesh& mesh, const std::string& path, bool ascii) {
  PlyWriteOptions o;
  o.ascii = ascii;
  write_ply(mesh, path, o);
}

void write_ply(const Mesh& mesh, const std::string& path, const PlyWriteOptions& options) {
  // What read_ply needs: a PLY without them could not be read back.
  mesh.vertices.require({"x", "y", "z"}, common::display_name(path, true), "a PLY canopy writes has x, y, z");
  const auto n = static_cast<std::int64_t>(mesh.vertices.size());
  for (const auto& f : mesh.faces) {
    for (auto i : f) {
      if (i < 0 || i >= n) {
        throw common::DataError(
            path, "internal: face refers to vertex " + std::to_string(i) + " of " + std::to_string(n));
      }
    }
  }
  common::write_file_atomic(path, serialize_ply(mesh, options));
}

}  // namespace canopy::formats
