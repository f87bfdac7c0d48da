#include "canopy/formats/points_io.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <fstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"

namespace canopy::formats {
namespace {

using common::DataError;

bool starts_with(const std::string& s, const char* prefix) {
  return s.compare(0, std::strlen(prefix), prefix) == 0;
}

// The first bytes of a file, escaped for a message (a NUL or a control byte never cuts it).
std::string quote_start(const std::string& bytes, std::size_t n = 16) {
  std::string out;
  for (std::size_t i = 0; i < bytes.size() && i < n; ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if (c >= 32 && c < 127 && c != '\'' && c != '\\') {
      out += static_cast<char>(c);
    } else if (c == '\n') {
      out += "\\n";
    } else {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out + (bytes.size() > n ? "..." : "");
}

bool is_ply(const std::string& b) { return starts_with(b, "ply\n") || starts_with(b, "ply\r\n"); }

// PCD: after blank and '#' comment lines, the first line starts with one of PCD's header keys.
bool is_pcd(const std::string& b) {
  // PCL's own first line: a file cut inside its header is a PCD all the same (parse_pcd then says
  // what is missing; it was "no PCD, PLY or LAS signature (the file starts '# .PCD v0.7 …')").
  const std::size_t first = b.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && b.compare(first, 6, "# .PCD") == 0) return true;
  std::size_t p = 0;
  while (p < b.size()) {
    p = b.find_first_not_of(" \t\r\n", p);
    if (p == std::string::npos) return false;
    if (b[p] != '#') break;
    p = b.find('\n', p);
  }
  if (p >= b.size()) return false;
  for (const char* key : {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT",
                          "VIEWPOINT", "POINTS", "DATA"}) {
    const std::size_t n = std::strlen(key);
    if (b.compare(p, n, key) == 0 && (p + n == b.size() || std::isspace(static_cast<unsigned char>(b[p + n])))) {
      return true;
    }
  }
  return false;
}

// What a file that is no point cloud canopy reads appears to be, for the error message.
std::string what_else(const std::string& b) {
  if (b.empty()) return "an empty file";
  const std::size_t p = b.find_first_not_of(" \t\r\n");
  if (p != std::string::npos && (b[p] == '{' || b[p] == '[')) {
    const std::size_t f = b.find("\"format\"");
    if (f != std::string::npos && f < 4096) {
      const std::size_t q1 = b.find('"', b.find(':', f) + 1);
      const std::size_t q2 = q1 == std::string::npos ? q1 : b.find('"', q1 + 1);
      if (q2 != std::string::npos && q2 - q1 < 64)
        return "a JSON document (" + quote_start(b.substr(q1 + 1, q2 - q1 - 1), 64) + ")";
    }
    return "a JSON document";
  }
  if (starts_with(b, "\x89PNG")) return "a PNG image";
  if (starts_with(b, "\x1f\x8b")) return "a gzip-compressed file (decompress it first)";
  if (starts_with(b, "PK\x03\x04")) return "a zip archive (unpack it first)";
  if (starts_with(b, "solid") || (b.size() >= 84 && b.find('\0') < 80))
    return "not a point cloud (an STL mesh?)";
  if (starts_with(b, "v ") || starts_with(b, "# OBJ") || b.find("\nv ") < 4096)
    return "not a point cloud (an OBJ mesh?)";
  return "not a point cloud canopy reads";
}

// Whether column `c` is float32 and float32 moves one of its finite values by more than the
// tolerance.
bool float32_loses(const PointCloud& cloud, const char* c) {
  if (!cloud.has(c) || !(cloud.type(c) == kFloat32)) return false;
  for (double d : cloud.col(c)) {
    if (std::isfinite(d) &&
        std::fabs(static_cast<double>(static_cast<float>(d)) - d) > kFloat32CoordinateTolerance) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::string describe_content(const std::string& bytes) {
  if (is_laz(bytes)) return "a LAZ file (compressed LAS)";
  if (is_las(bytes)) return "a LAS file";
  if (is_ply(bytes)) {
    const std::size_t end = std::min(bytes.find("end_header"), std::min<std::size_t>(bytes.size(), 1 << 16));
    const std::size_t f = bytes.find("\nelement face ");
    if (f != std::string::npos && f < end) {
      const long long n = std::strtoll(bytes.c_str() + f + 14, nullptr, 10);
      if (n > 0) return "a PLY mesh (" + std::to_string(n) + " faces)";
    }
    return "a PLY point set";
  }
  if (is_pcd(bytes)) return "a PCD point cloud";
  const std::string other = what_else(bytes);
  if (other.rfind("not a point cloud (", 0) == 0)
    return other.substr(19, other.size() - 20);  // "an STL mesh?"
  return other.rfind("not a point cloud", 0) == 0 ? "not a point cloud, mesh or document canopy reads" : other;
}

const char* format_name(PointFormat f) {
  switch (f) {
    case PointFormat::kPcd: return "PCD";
    case PointFormat::kPly: return "PLY";
    default: return "LAS";
  }
}

PointCloud parse_points(const std::string& bytes, const std::string& name, const std::string& tool) {
  if (is_las(bytes)) return parse_las(bytes, name);
  if (is_ply(bytes)) {
    Mesh m = parse_ply(bytes, name);
    if (!m.faces.empty()) {
      throw DataError(name, "this is a PLY mesh with " + std::to_string(m.faces.size()) + " faces; " +
                                (tool.empty() ? std::string("this tool") : tool) +
                                " reads points (PCD, LAS or a PLY point set without faces)");
    }
    return std::move(m.vertices);
  }
  if (is_pcd(bytes)) return parse_pcd(bytes, name);
  if (bytes.empty()) {
    throw DataError(name, "empty file (no points; " + (tool.empty() ? std::string("canopy") : tool) +
                              " reads PCD, PLY point sets and LAS)");
  }
  throw DataError(name, "this is " + what_else(bytes) + ": no PCD, PLY or LAS signature (the file starts '" +
                            quote_start(bytes) + "'); " + (tool.empty() ? std::string("canopy") : tool) +
                            " reads PCD, PLY point sets and LAS");
}

PointCloud read_points(const std::string& path, const std::string& tool) {
  return read_points(path, tool, FieldSelection{});
}

PointCloud read_points(const std::string& path, const std::string& tool, const FieldSelection& fields) {
  return read_points(path, tool, fields, nullptr);
}

PointCloud read_points(const std::string& path, const std::string& tool, const FieldSelection& fields,
                       std::optional<LasHeaderBlock>* las_header) {
  if (las_header != nullptr) las_header->reset();
  LasHeaderBlock block;
  LasHeaderBlock* want = las_header != nullptr ? &block : nullptr;
  // A LAS or LAZ file's cloud, its header block handed back.
  auto las = [&](PointCloud cloud) {
    if (las_header != nullptr) *las_header = std::move(block);
    return cloud;
  };
  // A regular LAS file is read piece by piece by read_las, not copied whole into memory first.
  // Only a regular file is looked into here: a FIFO's first bytes could not be read again.
  // A regular PCD file is read in chunks by read_pcd (DATA binary: only the selected columns
  // made), not copied whole into memory first (docs/decisions/cost.md §17): its header's first
  // 64 KiB say it is one.
  struct stat st {};
  if (path != "-" && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
    std::ifstream f(path, std::ios::binary);
    std::string magic(4, '\0');
    if (f.read(magic.data(), 4) && is_las(magic)) {
      f.close();
      return las(read_las(path, fields, want));
    }
    if (f.gcount() == 4 && !is_ply(magic)) {
      std::string head(1 << 16, '\0');
      std::copy(magic.begin(), magic.end(), head.begin());
      f.read(head.data() + 4, static_cast<std::streamsize>(head.size() - 4));
      head.resize(4 + static_cast<std::size_t>(f.gcount()));
      f.close();
      if (is_pcd(head)) return read_pcd(path, fields);
    }
  }
  const std::string bytes = common::read_file(path);
  if (is_las(bytes)) return las(parse_las(bytes, path, fields, want));
  PointCloud cloud = parse_points(bytes, path, tool);
  if (!fields.all()) {
    const std::vector<std::string> names = cloud.names();
    for (const auto& n : names) {
      if (!fields.wants(n)) cloud.remove(n);
    }
  }
  return cloud;
}

PointFormat output_format(const std::string& path) {
  // "-" and a name without an extension (a FIFO such as /dev/fd/63 from `-o >(…)`, a device,
  // a plain `-o out`) get the default format, PCD, like stdout.
  if (path == "-") return PointFormat::kPcd;
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  std::string ext;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    ext = path.substr(dot + 1);
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (ext.empty() || ext == "pcd") return PointFormat::kPcd;
  if (ext == "ply") return PointFormat::kPly;
  if (ext == "las") return PointFormat::kLas;
  if (ext == "laz") {
    throw common::UsageError("output '" + path +
                             "': canopy cannot write LAZ (Debian 12 has no LAZ encoder); "
                             "write .las and compress it elsewhere (laszip, pdal translate)");
  }
  throw common::UsageError("output '" + path + "': " + "unknown extension '." + ext + "'" +
                           "; the point formats are .pcd, .ply and .las (or - for PCD on stdout)");
}

bool promote_coordinates(PointCloud* cloud) {
  bool changed = false;
  for (const char* c : {"x", "y", "z"}) {
    if (float32_loses(*cloud, c)) {
      cloud->add(c, kFloat64);  // the existing column: only its type changes
      changed = true;
    }
  }
  return changed;
}

void write_points(const PointCloud& cloud, const std::string& path) {
  write_points(cloud, path, PcdWriteOptions{});
}

std::string serialize_points(const PointCloud& cloud, const std::string& path, const PcdWriteOptions& pcd) {
  const PointFormat f = output_format(path);
  if (f == PointFormat::kLas) return serialize_las(cloud, common::display_name(path, true));
  bool promote = false;
  for (const char* c : {"x", "y", "z"}) promote = promote || float32_loses(cloud, c);
  if (f == PointFormat::kPcd && !promote) return serialize_pcd(cloud, pcd);
  if (f == PointFormat::kPly) {
    // What read_ply needs: a PLY without them could not be read back.
    cloud.require({"x", "y", "z"}, common::display_name(path, true), "a PLY canopy writes has x, y, z");
  }
  Mesh m;  // PLY writes a Mesh; the copy also takes any promotion
  m.vertices = cloud;
  promote_coordinates(&m.vertices);
  return f == PointFormat::kPcd ? serialize_pcd(m.vertices, pcd) : serialize_ply(m);
}

void write_points(const PointCloud& cloud, const std::string& path, const PcdWriteOptions& pcd) {
  if (output_format(path) == PointFormat::kPcd) check_coordinates(cloud, path == "-" ? "<stdout>" : path);
  common::write_file_atomic(path, serialize_points(cloud, path, pcd));
}

PcdWriteOptions parse_pcd_encoding(const std::string& name) {
  PcdWriteOptions o;
  if (name == "binary") {
    o.encoding = PcdEncoding::binary;
  } else if (name == "binary_compressed") {
    o.encoding = PcdEncoding::binary_compressed;
  } else if (name == "ascii") {
    o.encoding = PcdEncoding::ascii;
  } else {
    throw common::UsageError("--pcd-encoding must be binary, binary_compressed or ascii, not '" + name + "'");
  }
  return o;
}

}  // namespace canopy::formats
