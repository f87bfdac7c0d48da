#include "canopy/formats/ply.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "binary_io.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"

namespace canopy::formats {
namespace detail {

std::string format_value(double v, FieldType type) {
  if (type.kind != 'F') {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v);
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

bool ply_type(const std::string& t, FieldType* out) {
  static const std::pair<const char*, FieldType> kTypes[] = {
      {"char", {'I', 1}},   {"int8", {'I', 1}},   {"uchar", {'U', 1}},   {"uint8", {'U', 1}},
      {"short", {'I', 2}},  {"int16", {'I', 2}},  {"ushort", {'U', 2}},  {"uint16", {'U', 2}},
      {"int", {'I', 4}},    {"int32", {'I', 4}},  {"uint", {'U', 4}},    {"uint32", {'U', 4}},
      {"float", {'F', 4}},  {"float32", {'F', 4}}, {"double", {'F', 8}}, {"float64", {'F', 8}}};
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

  double next(FieldType t) {
    if (enc_ == 0) {
      const char* p = bytes_.c_str() + pos_;
      const char* end = bytes_.c_str() + bytes_.size();
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
      if (p >= end) throw DataError(name_, "data truncated (ascii body ends early)");
      char* q = nullptr;
      const double v = std::strtod(p, &q);
      if (q == p) throw DataError(name_, "'" + std::string(p, std::min<std::size_t>(12, static_cast<std::size_t>(end - p))) + "' is not a number");
      pos_ = static_cast<std::size_t>(q - bytes_.c_str());
      return v;
    }
    const std::size_t sz = static_cast<std::size_t>(t.size);
    if (pos_ + sz > bytes_.size()) throw DataError(name_, "data truncated (binary body ends early)");
    const double v = detail::read_scalar(reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_, t, enc_ == 2);
    pos_ += sz;
    return v;
  }

 private:
  const std::string& bytes_;
  std::size_t pos_;
  int enc_;  // 0 ascii, 1 little endian, 2 big endian
  const std::string& name_;
};

}  // namespace

Mesh parse_ply(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw DataError(name, "empty file (not a PLY file)");
  if (bytes.compare(0, 3, "ply") != 0) throw DataError(name, "not a PLY file (no 'ply' magic)");
  std::size_t pos = 0;
  int encoding = -1;
  std::vector<Element> elements;
  std::vector<std::string> comments;
  while (true) {
    if (pos >= bytes.size()) throw DataError(name, "PLY header has no end_header (truncated?)");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key.empty() || key == "ply" || key == "obj_info") continue;
    if (key == "comment") {
      std::string rest = line.size() > 8 ? line.substr(8) : "";
      comments.push_back(rest);
    } else if (key == "format") {
      std::string f, v;
      ss >> f >> v;
      if (f == "ascii") encoding = 0;
      else if (f == "binary_little_endian") encoding = 1;
      else if (f == "binary_big_endian") encoding = 2;
      else throw DataError(name, "unknown PLY format '" + f + "'");
    } else if (key == "element") {
      Element e;
      long long count = -1;
      ss >> e.name >> count;
      if (e.name.empty() || count < 0) throw DataError(name, "malformed PLY line '" + line + "'");
      e.count = static_cast<std::size_t>(count);
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
          throw DataError(name, "unknown PLY type in '" + line + "'");
        }
        p.is_list = true;
      } else {
        ss >> p.name;
        if (!ply_type(t, &p.type)) throw DataError(name, "unknown PLY type '" + t + "'");
      }
      if (p.name.empty()) throw DataError(name, "malformed PLY line '" + line + "'");
      elements.back().props.push_back(p);
    } else if (key == "end_header") {
      break;
    } else {
      throw DataError(name, "unknown PLY header line '" + line + "'");
    }
  }
  if (encoding < 0) throw DataError(name, "PLY header has no format line");

  Mesh mesh;
  mesh.vertices.comments = comments;
  bool have_vertices = false;
  Body body(bytes, pos, encoding, name);
  for (const auto& e : elements) {
    if (e.name == "vertex") {
      have_vertices = true;
      auto& v = mesh.vertices;
      std::vector<int> cols;
      for (const auto& p : e.props) {
        if (p.is_list) {
          cols.push_back(-1);
          continue;
        }
        const std::string col = from_file_name(p.name);
        if (v.has(col)) throw DataError(name, "duplicate vertex property '" + p.name + "'");
        v.add(col, p.type);
        cols.push_back(static_cast<int>(v.names().size()) - 1);
      }
      v.resize(e.count);
      for (std::size_t i = 0; i < e.count; ++i) {
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const auto& p = e.props[k];
          if (p.is_list) {
            const auto m = static_cast<long long>(body.next(p.count_type));
            for (long long j = 0; j < m; ++j) body.next(p.type);
          } else {
            const double x = body.next(p.type);
            v.col(static_cast<std::size_t>(cols[k]))[i] = x;
          }
        }
      }
    } else if (e.name == "face") {
      int list_prop = -1;
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        if (e.props[k].is_list && (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index")) {
          list_prop = static_cast<int>(k);
        }
      }
      if (list_prop < 0 && e.count > 0) throw DataError(name, "face element has no vertex_indices list");
      mesh.faces.reserve(e.count);
      for (std::size_t i = 0; i < e.count; ++i) {
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const auto& p = e.props[k];
          if (!p.is_list) {
            body.next(p.type);
            continue;
          }
          const auto m = static_cast<long long>(body.next(p.count_type));
          if (m < 0 || m > 1000000) throw DataError(name, "face " + std::to_string(i) + " has a bad vertex count");
          std::vector<std::int32_t> idx(static_cast<std::size_t>(m));
          for (auto& x : idx) x = static_cast<std::int32_t>(body.next(p.type));
          if (static_cast<int>(k) != list_prop) continue;
          if (m < 3) throw DataError(name, "face " + std::to_string(i) + " has fewer than 3 vertices");
          for (long long j = 1; j + 1 < m; ++j) mesh.faces.push_back({idx[0], idx[static_cast<std::size_t>(j)], idx[static_cast<std::size_t>(j + 1)]});
        }
      }
    } else {
      for (std::size_t i = 0; i < e.count; ++i) {
        for (const auto& p : e.props) {
          if (p.is_list) {
            const auto m = static_cast<long long>(body.next(p.count_type));
            for (long long j = 0; j < m; ++j) body.next(p.type);
          } else {
            body.next(p.type);
          }
        }
      }
    }
  }
  if (!have_vertices) throw DataError(name, "PLY file has no vertex element");
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
    for (double x : mesh.vertices.col(c)) {
      if (!std::isfinite(x)) throw DataError(name, std::string("a vertex has a non-finite ") + c);
    }
  }
  return mesh;
}

Mesh read_ply(const std::string& path) { return parse_ply(common::read_file(path), path); }

std::string serialize_ply(const Mesh& mesh, bool ascii) {
  const auto& v = mesh.vertices;
  std::vector<FieldType> types = v.types();
  for (std::size_t c = 0; c < types.size(); ++c) {
    const auto& n = v.names()[c];
    if (n == "red" || n == "green" || n == "blue" || n == "alpha") types[c] = kUint8;
  }
  std::string out = "ply\nformat ";
  out += ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  for (const auto& c : v.comments) out += "comment " + c + "\n";
  out += "element vertex " + std::to_string(v.size()) + "\n";
  for (std::size_t c = 0; c < types.size(); ++c) {
    out += std::string("property ") + ply_type_name(types[c]) + " " + to_file_name(v.names()[c]) + "\n";
  }
  out += "element face " + std::to_string(mesh.faces.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  const std::size_t nc = types.size();
  if (ascii) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      for (std::size_t c = 0; c < nc; ++c) {
        out += detail::format_value(v.col(c)[i], types[c]);
        out += c + 1 < nc ? " " : "\n";
      }
    }
    for (const auto& f : mesh.faces) {
      out += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    }
  } else {
    for (std::size_t i = 0; i < v.size(); ++i) {
      for (std::size_t c = 0; c < nc; ++c) detail::write_scalar(&out, v.col(c)[i], types[c]);
    }
    for (const auto& f : mesh.faces) {
      out.push_back(3);
      for (auto i : f) detail::put(&out, i);
    }
  }
  return out;
}

void write_ply(const Mesh& mesh, const std::string& path, bool ascii) {
  const auto n = static_cast<std::int64_t>(mesh.vertices.size());
  for (const auto& f : mesh.faces) {
    for (auto i : f) {
      if (i < 0 || i >= n) {
        throw common::DataError(path, "internal: face refers to vertex " + std::to_string(i) + " of " +
                                          std::to_string(n));
      }
    }
  }
  common::write_file_atomic(path, serialize_ply(mesh, ascii));
}

}  // namespace canopy::formats
