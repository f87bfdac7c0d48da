// PCD reading speed and peak memory: canopy's read_pcd against PCL's loadPCDFile; LAZ reading
// against reading the same points as LAS.
//   formats_bench make <file.pcd> <points> [binary|binary_compressed|ascii]
//       writes a scan-like cloud (x y z sensor_x sensor_y sensor_z F4, view_idx I4, label U4)
//   formats_bench read <canopy|pcl-blob|pcl-xyzl> <file.pcd>
//       reads it once and prints "reader cpu_s wall_s peak_rss_MB points"
//   formats_bench unlaz <file.laz> <file.las>
//       writes the LAS a LAZ file decompresses to (canopy's laz_to_las)
//   formats_bench read <las|laz|points> <file>
//       reads a LAS or LAZ file once with read_points (every field, as detect and pcd2ply do)
//       into a PointCloud; the checksum is taken with PointCloud::values, so packed columns
//       stay packed: the memory is the read's. Prints "reader cpu_s wall_s peak_rss_MB points
//       base_MB checksum" (base_MB: the process's peak RSS before reading; checksum: see
//       cloud_checksum)
//   formats_bench read xyz <file>
//       topview's read: read_points with the fields x y z only, then col("x"), col("y"),
//       col("z") as doubles (what topview works on); the checksum's second sum is 0
//   formats_bench read detect <file>
//       detect's read: read_points (every field: its crops keep them), then col() of x y z
//       and return_number as doubles, the columns detect asks for before its own work
//   formats_bench read plain <file.las>
//       the plainest correct read of the same LAS file, for comparison (issue 31): the public
//       header (LAS 1.0-1.4, 1.4's 64-bit point count), then every point record in one read
//       into one block (all fields kept, nothing converted); x y z intensity classification
//       are decoded from it on the fly for the checksum. Same output, same checksum
//   formats_bench read compact <file.las>
//       the records read in 1 MiB chunks into a std::vector of a 16-byte struct (int32 x y z,
//       uint16 intensity, uint8 classification and return bits); the rest is dropped
//   formats_bench read typed <file.las>
//       the records in 1 MiB chunks into one column per field at its LAS width (x y z int32):
//       what a typed PointCloud would hold (docs/decisions/cost.md section 5)
//   formats_bench read bytes <file>
//       common::read_file alone (the copy of the file read_points starts with)
//   formats_bench make-las <file.las> <points>
//       writes a scan-like LAS 1.4 point format 6 tile with write_las: the standard fields plus
//       4 Extra Bytes fields (sensor_x/y/z float32, view_idx uint32): 46-byte records
// Run each read in its own process (bench/formats/run.sh) so peak RSS is the reader's own.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "canopy/common/atomic_file.h"
#include "canopy/formats/las.h"
#include "canopy/formats/laz.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/points_io.h"

namespace {

double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

double peak_rss_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // kB on Linux
}

int make(const std::string& path, std::size_t n, const std::string& enc) {
  using namespace canopy::formats;
  PointCloud c;
  c.resize(n);
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  auto& sx = c.add("sensor_x");
  auto& sy = c.add("sensor_y");
  auto& sz = c.add("sensor_z");
  auto& v = c.add("view_idx", kInt32);
  auto& l = c.add("label", kUint32);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    x[i] = static_cast<float>(std::fmod(t * 0.0137, 20.0) - 10.0);
    y[i] = static_cast<float>(std::fmod(t * 0.0071, 20.0) - 10.0);
    z[i] = static_cast<float>(std::sin(t * 1e-3));
    sx[i] = 0.0;
    sy[i] = static_cast<float>(std::sin(t * 1e-5));
    sz[i] = static_cast<float>(std::cos(t * 1e-5));
    v[i] = static_cast<double>(i / 500000);
    l[i] = static_cast<double>(i % 4);
  }
  PcdWriteOptions o;
  if (enc == "binary_compressed")
    o.encoding = PcdEncoding::binary_compressed;
  else if (enc == "ascii")
    o.encoding = PcdEncoding::ascii;
  write_pcd(c, path, o);
  return 0;
}

// A LAS scan-like tile: 3 flight-line-like strips in UTM-sized coordinates, the standard
// fields of point format 6 and 4 Extra Bytes fields.
int make_las(const std::string& path, std::size_t n) {
  using namespace canopy::formats;
  PointCloud c;
  c.resize(n);
  auto& x = c.add("x", kFloat64);
  auto& y = c.add("y", kFloat64);
  auto& z = c.add("z", kFloat64);
  auto& in = c.add("intensity", {'U', 2});
  auto& ret = c.add("return_number", kUint8);
  auto& nret = c.add("number_of_returns", kUint8);
  auto& cls = c.add("classification", kUint8);
  auto& angle = c.add("scan_angle", kFloat32);
  auto& source = c.add("point_source_id", {'U', 2});
  auto& gps = c.add("gps_time", kFloat64);
  auto& sx = c.add("sensor_x");
  auto& sy = c.add("sensor_y");
  auto& sz = c.add("sensor_z");
  auto& v = c.add("view_idx", kUint32);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    x[i] = 500000.0 + std::fmod(t * 0.0137, 500.0);
    y[i] = 6600000.0 + std::fmod(t * 0.00071, 500.0);
    z[i] = 120.0 + 15.0 * std::sin(t * 1e-3) + std::fmod(t * 0.37, 3.0);
    in[i] = static_cast<double>((i * 2654435761u) % 4096);
    nret[i] = static_cast<double>(1 + i % 3);
    ret[i] = static_cast<double>(1 + (i / 3) % static_cast<std::size_t>(nret[i]));
    cls[i] = static_cast<double>(i % 7 == 0 ? 6 : i % 3 == 0 ? 2 : 5);
    angle[i] = std::round((std::fmod(t * 0.01, 60.0) - 30.0) / 0.006) * 0.006;
    source[i] = static_cast<double>(i / 1000000);
    gps[i] = 3.0e8 + t * 1e-5;
    sx[i] = static_cast<float>(500250.0 - x[i]);
    sy[i] = static_cast<float>(std::sin(t * 1e-5));
    sz[i] = static_cast<float>(1000.0 - z[i]);
    v[i] = static_cast<double>(i / 500000);
  }
  write_las(c, path);
  return 0;
}

// Sum over the points of (x + y + z) (scaled, in double, in file order) and of intensity +
// classification: every reader below computes the same numbers the same way, so equal
// checksums show they read the same values.
struct Checksum {
  double xyz = 0;
  std::uint64_t ic = 0;
};

// Through PointCloud::values, 4096 rows at a time: a packed column is not unpacked. Without
// intensity (the xyz read) the second sum is 0.
Checksum cloud_checksum(const canopy::formats::PointCloud& c) {
  Checksum s;
  auto index = [&](const char* f) {
    for (std::size_t i = 0; i < c.names().size(); ++i) {
      if (c.names()[i] == f) return i;
    }
    return c.names().size();
  };
  const std::size_t x = index("x"), y = index("y"), z = index("z"), in = index("intensity"),
                    cls = index("classification");
  const bool ic = in < c.names().size() && cls < c.names().size();
  constexpr std::size_t kBlock = 4096;
  std::vector<double> b[5];
  for (auto& v : b) v.resize(kBlock);
  for (std::size_t first = 0; first < c.size(); first += kBlock) {
    const std::size_t k = std::min(kBlock, c.size() - first);
    c.values(x, first, k, b[0].data());
    c.values(y, first, k, b[1].data());
    c.values(z, first, k, b[2].data());
    if (ic) {
      c.values(in, first, k, b[3].data());
      c.values(cls, first, k, b[4].data());
    }
    for (std::size_t i = 0; i < k; ++i) {
      s.xyz += b[0][i] + b[1][i] + b[2][i];
      if (ic) s.ic += static_cast<std::uint64_t>(b[3][i]) + static_cast<std::uint64_t>(b[4][i]);
    }
  }
  return s;
}

template <typename T>
T get(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// What the plain readers take from the public header (ASPRS LAS 1.4 R15, Table 3).
struct PlainHeader {
  std::uint64_t data_offset = 0, record = 0, n = 0;
  int format = 0;
  double scale[3] = {1, 1, 1}, offset[3] = {0, 0, 0};
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Reads and checks the public header: signature, version 1.0-1.4, not LAZ, point format 0-10,
// record length, scale/offset; the 64-bit count of LAS 1.4 when set; the records fit the file.
bool plain_header(std::FILE* f, const std::string& path, PlainHeader* h) {
  static constexpr std::uint64_t kMinRecord[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  unsigned char b[375] = {};
  const std::size_t got = std::fread(b, 1, sizeof b, f);
  auto fail = [&](const char* why) {
    std::fprintf(stderr, "formats_bench: %s: %s\n", path.c_str(), why);
    return false;
  };
  if (got < 227 || std::memcmp(b, "LASF", 4) != 0) return fail("not LAS (or header truncated)");
  const int minor = b[25];
  if (b[24] != 1 || minor > 4) return fail("LAS version is not 1.0-1.4");
  if ((b[104] & 0xC0) != 0) return fail("LAZ (compressed): the plain reader reads LAS only");
  h->format = b[104];
  if (h->format > 10) return fail("unknown point format");
  h->data_offset = get<std::uint32_t>(b + 96);
  h->record = get<std::uint16_t>(b + 105);
  if (h->record < kMinRecord[h->format]) return fail("record shorter than its point format");
  h->n = get<std::uint32_t>(b + 107);
  if (minor >= 4) {
    if (got < 375) return fail("LAS 1.4 header truncated");
    const std::uint64_t n64 = get<std::uint64_t>(b + 247);
    if (n64 != 0) h->n = n64;
  }
  for (int d = 0; d < 3; ++d) {
    h->scale[d] = get<double>(b + 131 + 8 * d);
    h->offset[d] = get<double>(b + 155 + 8 * d);
    if (!std::isfinite(h->scale[d]) || h->scale[d] == 0 || !std::isfinite(h->offset[d]))
      return fail("unusable scale or offset");
  }
  if (std::fseek(f, 0, SEEK_END) != 0) return fail("cannot seek");
  const auto size = static_cast<std::uint64_t>(std::ftell(f));
  if (h->data_offset > size || h->n > (size - h->data_offset) / h->record)
    return fail("point data truncated");
  if (std::fseek(f, static_cast<long>(h->data_offset), SEEK_SET) != 0) return fail("cannot seek");
  return true;
}

// x y z intensity classification of one record, into the checksum.
void add_record(const unsigned char* r, const PlainHeader& h, Checksum* s) {
  const double x = get<std::int32_t>(r) * h.scale[0] + h.offset[0];
  const double y = get<std::int32_t>(r + 4) * h.scale[1] + h.offset[1];
  const double z = get<std::int32_t>(r + 8) * h.scale[2] + h.offset[2];
  s->xyz += x + y + z;
  const unsigned cls = h.format >= 6 ? r[16] : r[15] & 31u;
  s->ic += get<std::uint16_t>(r + 12) + cls;
}

// Every point record in one block (the whole point data, all fields kept), read in one fread;
// the checksum decodes x y z intensity classification from it.
bool read_plain(const std::string& path, std::size_t* n, Checksum* s) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) return false;
  PlainHeader h;
  if (!plain_header(f.get(), path, &h)) return false;
  std::vector<unsigned char> records(static_cast<std::size_t>(h.n * h.record));
  if (std::fread(records.data(), 1, records.size(), f.get()) != records.size()) return false;
  for (std::size_t i = 0; i < h.n; ++i) add_record(records.data() + i * h.record, h, s);
  *n = static_cast<std::size_t>(h.n);
  return true;
}

// The records in 1 MiB chunks into a compact struct array (x y z int32, scaled on use).
struct CompactPoint {
  std::int32_t x, y, z;
  std::uint16_t intensity;
  std::uint8_t classification, returns;  // returns: return number | number of returns << 4
};
static_assert(sizeof(CompactPoint) == 16, "packed");

bool read_compact(const std::string& path, std::size_t* n, Checksum* s) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) return false;
  PlainHeader h;
  if (!plain_header(f.get(), path, &h)) return false;
  std::vector<CompactPoint> pts(static_cast<std::size_t>(h.n));
  const std::size_t per_chunk = std::max<std::size_t>(1, (std::size_t(1) << 20) / h.record);
  std::vector<unsigned char> chunk(per_chunk * h.record);
  const bool ext = h.format >= 6;
  for (std::size_t at = 0; at < h.n;) {
    const std::size_t k = std::min<std::size_t>(per_chunk, h.n - at);
    if (std::fread(chunk.data(), h.record, k, f.get()) != k) return false;
    for (std::size_t j = 0; j < k; ++j) {
      const unsigned char* r = chunk.data() + j * h.record;
      CompactPoint& p = pts[at + j];
      p.x = get<std::int32_t>(r);
      p.y = get<std::int32_t>(r + 4);
      p.z = get<std::int32_t>(r + 8);
      p.intensity = get<std::uint16_t>(r + 12);
      p.classification = ext ? r[16] : static_cast<std::uint8_t>(r[15] & 31u);
      p.returns = ext ? r[14] : static_cast<std::uint8_t>((r[14] & 7u) | ((r[14] >> 3) & 7u) << 4);
    }
    at += k;
  }
  for (const CompactPoint& p : pts) {
    s->xyz +=
        (p.x * h.scale[0] + h.offset[0]) + (p.y * h.scale[1] + h.offset[1]) + (p.z * h.scale[2] + h.offset[2]);
    s->ic += p.intensity + p.classification;
  }
  *n = pts.size();
  return true;
}

// What a typed PointCloud (each column at its LAS width, x y z as int32 with the header's scale
// and offset) would hold: every standard field in its own column, the flags unpacked one byte
// each as read_points does, Extra Bytes as they are in the record. Read in 1 MiB chunks, so the
// file is never held whole. A sketch of the design in docs/decisions/cost.md section 5, to
// measure it; not a reader.
struct TypedColumns {
  std::vector<std::int32_t> x, y, z;
  std::vector<std::uint16_t> intensity, source, rgb[3], nir;
  std::vector<std::uint8_t> ret, nret, flags[7], cls,
      user;  // flags: scan_dir edge synthetic key withheld overlap channel
  std::vector<std::int16_t> angle;
  std::vector<double> gps;
  std::vector<std::uint8_t> extra;  // the bytes after the standard record, per point
};

bool read_typed(const std::string& path, std::size_t* n, Checksum* s) {
  static constexpr std::size_t kMinRecord[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) return false;
  PlainHeader h;
  if (!plain_header(f.get(), path, &h)) return false;
  const std::size_t np = static_cast<std::size_t>(h.n), fmt = static_cast<std::size_t>(h.format);
  const bool ext = h.format >= 6, gps = h.format == 1 || h.format >= 3;
  const bool rgb =
      h.format == 2 || h.format == 3 || h.format == 5 || h.format == 7 || h.format == 8 || h.format == 10;
  const bool nir = h.format == 8 || h.format == 10;
  const std::size_t rgb_at = h.format == 2 ? 20 : h.format <= 5 ? 28 : 30, gps_at = ext ? 22 : 20;
  const std::size_t extra = static_cast<std::size_t>(h.record) - kMinRecord[fmt];
  TypedColumns c;
  for (auto* v : {&c.x, &c.y, &c.z}) v->resize(np);
  c.intensity.resize(np);
  c.source.resize(np);
  for (auto* v : {&c.ret, &c.nret, &c.cls, &c.user}) v->resize(np);
  for (int k = 0; k < (ext ? 7 : 5); ++k) c.flags[k].resize(np);
  c.angle.resize(np);
  if (gps) c.gps.resize(np);
  if (rgb)
    for (auto& v : c.rgb) v.resize(np);
  if (nir) c.nir.resize(np);
  c.extra.resize(np * extra);
  const std::size_t per_chunk = std::max<std::size_t>(1, (std::size_t(1) << 20) / h.record);
  std::vector<unsigned char> chunk(per_chunk * h.record);
  for (std::size_t at = 0; at < np;) {
    const std::size_t k = std::min<std::size_t>(per_chunk, np - at);
    if (std::fread(chunk.data(), h.record, k, f.get()) != k) return false;
    for (std::size_t j = 0; j < k; ++j) {
      const unsigned char* r = chunk.data() + j * h.record;
      const std::size_t i = at + j;
      c.x[i] = get<std::int32_t>(r);
      c.y[i] = get<std::int32_t>(r + 4);
      c.z[i] = get<std::int32_t>(r + 8);
      c.intensity[i] = get<std::uint16_t>(r + 12);
      const unsigned bits = r[14];
      if (!ext) {
        c.ret[i] = bits & 7u;
        c.nret[i] = (bits >> 3) & 7u;
        c.flags[0][i] = (bits >> 6) & 1u;
        c.flags[1][i] = (bits >> 7) & 1u;
        const unsigned q = r[15];
        c.cls[i] = q & 31u;
        for (int b = 0; b < 3; ++b) c.flags[2 + b][i] = (q >> (5 + b)) & 1u;
        c.angle[i] = get<std::int8_t>(r + 16);
        c.user[i] = r[17];
        c.source[i] = get<std::uint16_t>(r + 18);
      } else {
        c.ret[i] = bits & 15u;
        c.nret[i] = static_cast<std::uint8_t>(bits >> 4);
        const unsigned q = r[15];
        c.flags[0][i] = (q >> 6) & 1u;
        c.flags[1][i] = (q >> 7) & 1u;
        for (int b = 0; b < 4; ++b) c.flags[2 + b][i] = (q >> b) & 1u;
        c.flags[6][i] = (q >> 4) & 3u;
        c.cls[i] = r[16];
        c.user[i] = r[17];
        c.angle[i] = get<std::int16_t>(r + 18);
        c.source[i] = get<std::uint16_t>(r + 20);
      }
      if (gps) c.gps[i] = get<double>(r + gps_at);
      if (rgb)
        for (int b = 0; b < 3; ++b)
          c.rgb[b][i] = get<std::uint16_t>(r + rgb_at + 2 * static_cast<std::size_t>(b));
      if (nir) c.nir[i] = get<std::uint16_t>(r + 36);
      if (extra > 0) std::memcpy(c.extra.data() + i * extra, r + kMinRecord[fmt], extra);
    }
    at += k;
  }
  for (std::size_t i = 0; i < np; ++i) {
    s->xyz += (c.x[i] * h.scale[0] + h.offset[0]) + (c.y[i] * h.scale[1] + h.offset[1]) +
              (c.z[i] * h.scale[2] + h.offset[2]);
    s->ic += c.intensity[i] + c.cls[i];
  }
  *n = np;
  return true;
}

int read(const std::string& reader, const std::string& path) {
  const double base = peak_rss_mb();
  const double c0 = cpu_seconds();
  const auto w0 = std::chrono::steady_clock::now();
  std::size_t n = 0;
  Checksum sum;
  bool las = true;
  if (reader == "canopy") {
    n = canopy::formats::read_pcd(path).size();
    las = false;
  } else if (reader == "las" || reader == "laz" || reader == "points") {
    const canopy::formats::PointCloud c = canopy::formats::read_points(path);
    n = c.size();
    sum = cloud_checksum(c);
  } else if (reader == "xyz") {
    const canopy::formats::PointCloud c =
        canopy::formats::read_points(path, "", canopy::formats::FieldSelection::only({"x", "y", "z"}));
    for (const char* f : {"x", "y", "z"}) (void)c.col(f);  // topview's doubles
    n = c.size();
    sum = cloud_checksum(c);
  } else if (reader == "detect") {
    const canopy::formats::PointCloud c = canopy::formats::read_points(path);
    for (const char* f : {"x", "y", "z", "return_number"}) (void)c.col(f);  // detect's doubles
    n = c.size();
    sum = cloud_checksum(c);
  } else if (reader == "plain") {
    if (!read_plain(path, &n, &sum)) return 1;
  } else if (reader == "typed") {
    if (!read_typed(path, &n, &sum)) return 1;
  } else if (reader == "compact") {
    if (!read_compact(path, &n, &sum)) return 1;
  } else if (reader == "bytes") {
    n = canopy::common::read_file(path).size();
    las = false;
  } else if (reader == "pcl-blob") {
    pcl::PCLPointCloud2 blob;
    if (pcl::io::loadPCDFile(path, blob) != 0) return 1;
    n = blob.width * blob.height;
    las = false;
  } else if (reader == "pcl-xyzl") {
    pcl::PointCloud<pcl::PointXYZL> cloud;
    if (pcl::io::loadPCDFile(path, cloud) != 0) return 1;
    n = cloud.size();
    las = false;
  } else {
    std::fprintf(stderr, "formats_bench: unknown reader %s\n", reader.c_str());
    return 2;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  std::printf("%-9s %6.3f %6.3f %8.1f %zu", reader.c_str(), cpu_seconds() - c0, wall, peak_rss_mb(), n);
  if (las) std::printf(" %6.1f %.6f+%llu", base, sum.xyz, static_cast<unsigned long long>(sum.ic));
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string cmd = argc > 1 ? argv[1] : "";
  if (cmd == "make" && argc >= 4)
    return make(argv[2], std::strtoull(argv[3], nullptr, 10), argc > 4 ? argv[4] : "binary");
  if (cmd == "make-las" && argc == 4) return make_las(argv[2], std::strtoull(argv[3], nullptr, 10));
  if (cmd == "read" && argc == 4) return read(argv[2], argv[3]);
  if (cmd == "unlaz" && argc == 4) {
    canopy::common::write_file_atomic(
        argv[3], canopy::formats::laz_to_las(canopy::common::read_file(argv[2]), argv[2]));
    return 0;
  }
  std::fprintf(stderr,
               "usage: formats_bench make <file.pcd> <points> [binary|binary_compressed|ascii]\n"
               "       formats_bench read <canopy|pcl-blob|pcl-xyzl> <file.pcd>\n"
               "       formats_bench unlaz <file.laz> <file.las>\n"
               "       formats_bench read <las|laz|points|xyz|detect|plain|compact|typed|bytes> <file>\n"
               "       formats_bench make-las <file.las> <points>\n");
  return 2;
}
