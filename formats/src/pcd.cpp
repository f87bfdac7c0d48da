#include "canopy/formats/pcd.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "binary_io.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "lzf.h"

namespace canopy::formats {
namespace {

using common::DataError;
using detail::read_scalar;

struct Header {
  std::vector<std::string> fields;
  std::vector<int> sizes;
  std::vector<char> kinds;
  std::vector<int> counts;
  long long width = -1, height = 1, points = -1;
  std::string data;
  std::vector<std::string> comments;
  std::size_t data_offset = 0;
};

std::vector<std::string> split_ws(const std::string& line) {
  std::istringstream ss(line);
  std::vector<std::string> out;
  std::string t;
  while (ss >> t) out.push_back(t);
  return out;
}

long long to_count(const std::string& text, const std::string& name, const std::string& key) {
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0' || v < 0) {
    throw DataError(name, "header " + key + " '" + text + "' is not a non-negative integer");
  }
  return v;
}

Header parse_header(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw DataError(name, "empty file (not a PCD file)");
  Header h;
  std::size_t pos = 0;
  bool have_count = false;
  while (true) {
    if (pos >= bytes.size()) throw DataError(name, "PCD header has no DATA line (truncated or not a PCD file)");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::string c = line.substr(1);
      if (!c.empty() && c[0] == ' ') c.erase(0, 1);
      if (c.rfind(".PCD v", 0) != 0) h.comments.push_back(c);
      continue;
    }
    auto tok = split_ws(line);
    const std::string key = tok[0];
    tok.erase(tok.begin());
    if (key == "VERSION") {
    } else if (key == "FIELDS" || key == "COLUMNS") {
      h.fields = tok;
    } else if (key == "SIZE") {
      for (auto& t : tok) h.sizes.push_back(static_cast<int>(to_count(t, name, "SIZE")));
    } else if (key == "TYPE") {
      for (auto& t : tok) {
        if (t.size() != 1) throw DataError(name, "header TYPE '" + t + "' is not one of F, U, I");
        h.kinds.push_back(t[0]);
      }
    } else if (key == "COUNT") {
      have_count = true;
      for (auto& t : tok) h.counts.push_back(static_cast<int>(to_count(t, name, "COUNT")));
    } else if (key == "WIDTH") {
      if (tok.size() != 1) throw DataError(name, "header WIDTH needs one value");
      h.width = to_count(tok[0], name, "WIDTH");
    } else if (key == "HEIGHT") {
      if (tok.size() != 1) throw DataError(name, "header HEIGHT needs one value");
      h.height = to_count(tok[0], name, "HEIGHT");
    } else if (key == "POINTS") {
      if (tok.size() != 1) throw DataError(name, "header POINTS needs one value");
      h.points = to_count(tok[0], name, "POINTS");
    } else if (key == "VIEWPOINT") {
    } else if (key == "DATA") {
      if (tok.size() != 1) throw DataError(name, "header DATA needs one value");
      h.data = tok[0];
      h.data_offset = pos;
      break;
    } else {
      throw DataError(name, "unknown PCD header line '" + key + "' (is this a PCD file?)");
    }
  }
  if (h.fields.empty()) throw DataError(name, "PCD header has no FIELDS line");
  if (!have_count) h.counts.assign(h.fields.size(), 1);
  if (h.sizes.size() != h.fields.size() || h.kinds.size() != h.fields.size() ||
      h.counts.size() != h.fields.size()) {
    throw DataError(name, "PCD header lists " + std::to_string(h.fields.size()) + " FIELDS but " +
                              std::to_string(h.sizes.size()) + " SIZE, " +
                              std::to_string(h.kinds.size()) + " TYPE and " +
                              std::to_string(h.counts.size()) + " COUNT entries");
  }
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    if (!detail::valid_type({h.kinds[i], h.sizes[i]})) {
      throw DataError(name, "field '" + h.fields[i] + "' has unsupported TYPE " + h.kinds[i] +
                                " SIZE " + std::to_string(h.sizes[i]));
    }
  }
  if (h.width < 0) throw DataError(name, "PCD header has no WIDTH");
  if (h.points < 0) h.points = h.width * h.height;
  if (h.points != h.width * h.height) {
    throw DataError(name, "PCD header POINTS " + std::to_string(h.points) + " != WIDTH x HEIGHT " +
                              std::to_string(h.width * h.height));
  }
  if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed") {
    throw DataError(name, "unknown DATA type '" + h.data + "' (want ascii, binary or binary_compressed)");
  }
  return h;
}

// Column layout: one entry per stored scalar; target < 0 for padding fields.
struct Slot {
  FieldType type;
  int column;
};

std::vector<Slot> make_columns(const Header& h, PointCloud* cloud) {
  std::vector<Slot> slots;
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    const FieldType t{h.kinds[f], h.sizes[f]};
    for (int k = 0; k < h.counts[f]; ++k) {
      if (h.fields[f] == "_") {
        slots.push_back({t, -1});
        continue;
      }
      const std::string col = h.counts[f] == 1 ? h.fields[f] : h.fields[f] + "_" + std::to_string(k);
      if (cloud->has(col)) throw DataError("", "duplicate field '" + col + "'");
      cloud->add(col, t);
      slots.push_back({t, static_cast<int>(cloud->names().size()) - 1});
    }
  }
  return slots;
}

void check_coordinates(const PointCloud& cloud, const std::string& name) {
  for (const char* c : {"x", "y", "z"}) {
    if (!cloud.has(c)) continue;
    const auto& v = cloud.col(c);
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!std::isfinite(v[i])) {
        throw DataError(name, std::string("point ") + std::to_string(i) + " has a non-finite " + c +
                                  " (NaN or infinite coordinates are not accepted)");
      }
    }
  }
}

}  // namespace

PointCloud parse_pcd(const std::string& bytes, const std::string& name) {
  const Header h = parse_header(bytes, name);
  PointCloud cloud;
  std::vector<Slot> slots;
  try {
    slots = make_columns(h, &cloud);
  } catch (const DataError& e) {
    throw DataError(name, e.cause());
  }
  cloud.comments = h.comments;
  const std::size_t n = static_cast<std::size_t>(h.points);
  cloud.resize(n);
  std::size_t step = 0;
  for (const auto& s : slots) step += static_cast<std::size_t>(s.type.size);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data()) + h.data_offset;
  const std::size_t avail = bytes.size() - std::min(bytes.size(), h.data_offset);

  if (h.data == "ascii") {
    const char* p = bytes.c_str() + h.data_offset;
    const char* end = bytes.c_str() + bytes.size();
    for (std::size_t i = 0; i < n; ++i) {
      for (const auto& s : slots) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
        if (p >= end) {
          throw DataError(name, "data truncated: header says " + std::to_string(n) +
                                    " points, ascii data ends in point " + std::to_string(i));
        }
        char* q = nullptr;
        const double v = std::strtod(p, &q);
        if (q == p) throw DataError(name, "point " + std::to_string(i) + ": '" +
                                              std::string(p, std::min<std::size_t>(12, static_cast<std::size_t>(end - p))) +
                                              "' is not a number");
        p = q;
        if (s.column >= 0) cloud.col(static_cast<std::size_t>(s.column))[i] = v;
      }
    }
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
    if (p < end) throw DataError(name, "more ascii data than the header's " + std::to_string(n) + " points");
  } else if (h.data == "binary") {
    if (avail < n * step) {
      throw DataError(name, "data truncated: header says " + std::to_string(n) + " points of " +
                                std::to_string(step) + " bytes, file holds " + std::to_string(avail) +
                                " bytes of data");
    }
    if (avail > n * step) {
      throw DataError(name, "data longer than the header says (" + std::to_string(avail) + " bytes for " +
                                std::to_string(n) + " points of " + std::to_string(step) + " bytes)");
    }
    for (std::size_t i = 0; i < n; ++i) {
      const unsigned char* row = data + i * step;
      std::size_t off = 0;
      for (const auto& s : slots) {
        if (s.column >= 0) cloud.col(static_cast<std::size_t>(s.column))[i] = read_scalar(row + off, s.type);
        off += static_cast<std::size_t>(s.type.size);
      }
    }
  } else {  // binary_compressed: uint32 compressed size, uint32 raw size, LZF block of SoA data
    if (avail < 8) throw DataError(name, "data truncated: binary_compressed block header missing");
    std::uint32_t csize, usize;
    std::memcpy(&csize, data, 4);
    std::memcpy(&usize, data + 4, 4);
    if (avail - 8 < csize) {
      throw DataError(name, "data truncated: compressed block of " + std::to_string(csize) +
                                " bytes, file holds " + std::to_string(avail - 8));
    }
    if (usize != n * step) {
      throw DataError(name, "compressed block holds " + std::to_string(usize) + " bytes, header needs " +
                                std::to_string(n * step));
    }
    std::vector<unsigned char> raw(usize);
    if (n > 0 && !detail::lzf_decompress(data + 8, csize, raw.data(), usize)) {
      throw DataError(name, "corrupt binary_compressed data (LZF decompression failed)");
    }
    std::size_t off = 0;  // field-major: all values of slot 0, then slot 1, ...
    for (const auto& s : slots) {
      const std::size_t sz = static_cast<std::size_t>(s.type.size);
      if (s.column >= 0) {
        auto& col = cloud.col(static_cast<std::size_t>(s.column));
        for (std::size_t i = 0; i < n; ++i) col[i] = read_scalar(raw.data() + off + i * sz, s.type);
      }
      off += sz * n;
    }
  }
  check_coordinates(cloud, name);
  return cloud;
}

PointCloud read_pcd(const std::string& path) { return parse_pcd(common::read_file(path), path); }

std::string serialize_pcd(const PointCloud& cloud) {
  std::string out = "# .PCD v0.7 - Point Cloud Data file format\n";
  for (const auto& c : cloud.comments) out += "# " + c + "\n";
  std::string fields, sizes, types, counts;
  for (std::size_t i = 0; i < cloud.names().size(); ++i) {
    const auto t = cloud.types()[i];
    fields += " " + cloud.names()[i];
    sizes += " " + std::to_string(t.size);
    types += std::string(" ") + t.kind;
    counts += " 1";
  }
  const std::string n = std::to_string(cloud.size());
  out += "VERSION 0.7\nFIELDS" + fields + "\nSIZE" + sizes + "\nTYPE" + types + "\nCOUNT" + counts +
         "\nWIDTH " + n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA binary\n";
  std::size_t step = 0;
  for (const auto& t : cloud.types()) step += static_cast<std::size_t>(t.size);
  out.reserve(out.size() + step * cloud.size());
  const std::size_t nc = cloud.names().size();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (std::size_t c = 0; c < nc; ++c) detail::write_scalar(&out, cloud.col(c)[i], cloud.types()[c]);
  }
  return out;
}

void write_pcd(const PointCloud& cloud, const std::string& path) {
  check_coordinates(cloud, path == "-" ? "<stdout>" : path);
  common::write_file_atomic(path, serialize_pcd(cloud));
}

}  // namespace canopy::formats
