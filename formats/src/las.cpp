#include "canopy/formats/las.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <vector>

#include "binary_io.h"
#include "las_header.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/las_crs.h"
#include "canopy/formats/laz.h"
#include "canopy/formats/provenance.h"

namespace canopy::formats {
namespace {

using common::DataError;
using detail::put;

static_assert(std::numeric_limits<double>::is_iec559, "LAS codec assumes IEEE doubles");

using las::get;
using las::kHeader12;
using las::kHeader14;
using las::kMinRecord;
using las::kVlrHeader;
using las::LasHeader;
using las::printable;
constexpr std::size_t kEvlrHeader = 60, kExtraDescriptor = 192;
// Extra Bytes descriptors read (later ones are skipped like undocumented bytes); a normal VLR
// holds at most 341, an EVLR could hold millions of columns.
constexpr std::size_t kMaxExtraFields = 1024;

bool has_prefix(const unsigned char* p, std::size_t n, const char* id) {
  const std::size_t len = std::strlen(id);
  if (len > n || std::memcmp(p, id, len) != 0) return false;
  return len == n || p[len] == 0;
}

// One Extra Bytes descriptor, resolved to the bytes it covers in each record.
struct Extra {
  std::size_t offset = 0;  // from the start of the record
  int base = 0;            // data type 1..10 of each element
  int count = 0;           // elements (1..3)
  double scale[3] = {1, 1, 1}, shift[3] = {0, 0, 0};
  bool scaled = false;
  // Per element: the packed column (a std::vector of the base type, or std::vector<double>
  // for base 10 unscaled), nullptr when the field is not selected.
  std::vector<void*> cols;
};

constexpr int kBaseSize[11] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

FieldType base_field_type(int base) {
  switch (base) {
    case 1: return kUint8;
    case 2: return {'I', 1};
    case 3: return {'U', 2};
    case 4: return {'I', 2};
    case 5: return kUint32;
    case 6: return kInt32;
    case 9: return kFloat32;
    default: return kFloat64;  // 7, 8 (64-bit integers, exact to 2^53), 10
  }
}

// A column name for an Extra Bytes field: letters, digits and '_' only; not in `used` (the
// cloud's names so far), which receives it.
std::string extra_name(const unsigned char* p, std::size_t n, std::set<std::string>* used, int count, int k) {
  std::string s;
  for (std::size_t i = 0; i < n && p[i] != 0; ++i) {
    const unsigned char c = p[i];
    s += (std::isalnum(c) || c == '_') && c < 128 ? static_cast<char>(c) : '_';
  }
  if (s.empty()) s = "extra";
  if (count > 1) s += "_" + std::to_string(k);
  if (used->count(s)) {
    const std::string base = "extra_" + s;
    s = base;
    for (int i = 2; used->count(s); ++i) s = base + "_" + std::to_string(i);
  }
  used->insert(s);
  return s;
}

// The packed column of one Extra Bytes element at its base type (base 10 unscaled: doubles).
void* add_extra_column(PointCloud* cloud, const std::string& name, FieldType t, int base, bool scaled,
                       double scale, double shift) {
  switch (base) {
    case 1: return &cloud->add_packed<std::uint8_t>(name, t, scaled, scale, shift);
    case 2: return &cloud->add_packed<std::int8_t>(name, t, scaled, scale, shift);
    case 3: return &cloud->add_packed<std::uint16_t>(name, t, scaled, scale, shift);
    case 4: return &cloud->add_packed<std::int16_t>(name, t, scaled, scale, shift);
    case 5: return &cloud->add_packed<std::uint32_t>(name, t, scaled, scale, shift);
    case 6: return &cloud->add_packed<std::int32_t>(name, t, scaled, scale, shift);
    case 7: return &cloud->add_packed<std::uint64_t>(name, t, scaled, scale, shift);
    case 8: return &cloud->add_packed<std::int64_t>(name, t, scaled, scale, shift);
    case 9: return &cloud->add_packed<float>(name, t, scaled, scale, shift);
    default:
      if (!scaled) return &cloud->add(name, t);  // already doubles: nothing to unpack
      return &cloud->add_packed<double>(name, t, scaled, scale, shift);
  }
}

// Resolves the Extra Bytes VLR payload against the `extra_len` bytes after the standard
// record of `standard_len` bytes. Descriptors that run past the record or use an unknown data
// type end the description: the remaining bytes are skipped.
std::vector<Extra> parse_extra_bytes(const unsigned char* p, std::size_t len, std::size_t standard_len,
                                     std::size_t extra_len, const std::vector<std::string>& standard,
                                     const FieldSelection& want, PointCloud* cloud) {
  std::vector<Extra> out;
  std::set<std::string> names(standard.begin(), standard.end());  // the format's, selected or not
  std::size_t used = 0;
  const std::size_t max_len = kMaxExtraFields * kExtraDescriptor;  // bounds the column count
  for (std::size_t d = 0; d + kExtraDescriptor <= std::min(len, max_len); d += kExtraDescriptor) {
    const unsigned char* q = p + d;
    const int type = q[2], options = q[3];
    std::size_t bytes = 0;
    Extra e;
    if (type == 0) {
      bytes = static_cast<std::size_t>(options);  // undocumented bytes: skipped
    } else if (type <= 30) {
      e.base = (type - 1) % 10 + 1;
      e.count = (type - 1) / 10 + 1;
      bytes = static_cast<std::size_t>(kBaseSize[e.base] * e.count);
    } else {
      break;
    }
    if (used + bytes > extra_len) break;
    e.offset = standard_len + used;
    used += bytes;
    if (type == 0) continue;
    const bool has_scale = (options & 8) != 0, has_offset = (options & 16) != 0;
    for (int k = 0; k < e.count; ++k) {
      if (has_scale) e.scale[k] = get<double>(q + 112 + 8 * k);
      if (has_offset) e.shift[k] = get<double>(q + 136 + 8 * k);
      if (!std::isfinite(e.scale[k]) || !std::isfinite(e.shift[k])) e.scale[k] = 1, e.shift[k] = 0;
    }
    e.scaled = has_scale || has_offset;
    const FieldType t = e.scaled ? kFloat64 : base_field_type(e.base);
    for (int k = 0; k < e.count; ++k) {
      const std::string name = extra_name(q + 4, 32, &names, e.count, k);
      e.cols.push_back(want.wants(name)
                           ? add_extra_column(cloud, name, t, e.base, e.scaled, e.scale[k], e.shift[k])
                           : nullptr);
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace

bool is_las(const std::string& bytes) { return bytes.size() >= 4 && bytes.compare(0, 4, "LASF") == 0; }

bool is_laz(const std::string& bytes) { return laszip_compressed(bytes); }

namespace {

// The Extra Bytes (E)VLR payload, when there is one.
struct ExtraVlr {
  const unsigned char* data = nullptr;
  std::size_t len = 0;
};

// The XYZ scale and offset of the header, each usable for every int32 coordinate.
void read_las_transform(const unsigned char* b, LasHeader& h, const std::string& name) {
  double* scale = h.scale;
  double* offset = h.offset;
  for (int d = 0; d < 3; ++d) {
    scale[d] = get<double>(b + 131 + 8 * d);
    offset[d] = get<double>(b + 155 + 8 * d);
    // Every int32 times the scale plus the offset must be a finite double.
    if (!std::isfinite(scale[d]) || scale[d] == 0 || !std::isfinite(offset[d]) ||
        !std::isfinite(std::fabs(scale[d]) * 2147483648.0 + std::fabs(offset[d]))) {
      throw DataError(name, std::string("LAS header ") + "XYZ"[d] + " scale " +
                                detail::format_value(scale[d], kFloat64) + " / offset " +
                                detail::format_value(offset[d], kFloat64) +
                                " is not usable (zero, infinite or NaN)");
    }
  }
}

// The point count (las::point_count), checked against the bytes after the point data offset.
void read_las_point_count(const unsigned char* b, std::size_t size, LasHeader& h, const std::string& name) {
  const int minor = h.minor;
  const std::size_t data_offset = h.data_offset, record = h.record;
  const std::uint64_t n = h.n = las::point_count(b, minor, name);
  const std::size_t avail = size - data_offset;
  if (n > avail / record) {
    // Also when nothing follows the offset: a file cut there (or an offset moved to its end)
    // is not an empty cloud (it was read as one, exit 0).
    throw DataError(name, "point data truncated: header says " + std::to_string(n) + " points of " +
                              std::to_string(record) + " bytes, the file holds " + std::to_string(avail) +
                              " bytes after the point data offset" +
                              (avail == 0 ? " (it ends there: truncated?)" : ""));
  }
  // Whole point records beyond the count, up to the EVLRs (1.4) or the waveform data (1.3+)
  // when those follow the points: the count is wrong (a LAS 1.2 with count 0 and 100 records
  // was read as 0 points). Fewer bytes than one record are tolerated as padding.
  std::uint64_t end = size;
  if (minor >= 3) {
    const std::uint64_t waveform = get<std::uint64_t>(b + 227);
    if (waveform >= data_offset && waveform < end) end = waveform;
  }
  if (minor >= 4 && get<std::uint32_t>(b + 243) > 0) {
    const std::uint64_t evlr = get<std::uint64_t>(b + 235);
    if (evlr >= data_offset && evlr < end) end = evlr;
  }
  const std::uint64_t extra = end - data_offset - std::min<std::uint64_t>(end - data_offset, n * record);
  if (extra >= record) {
    throw DataError(name, "LAS header says " + std::to_string(n) + " points of " + std::to_string(record) +
                              " bytes, but " + std::to_string(extra) + " more bytes of point data (" +
                              std::to_string(extra / record) + " records) follow them (a wrong point count?)");
  }
}

}  // namespace

namespace las {

std::string printable(const unsigned char* p, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n && p[i] != 0; ++i) {
    const unsigned char c = p[i];
    if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

LasHeader read_header_fields(const unsigned char* b, std::size_t size, const std::string& name) {
  LasHeader h;
  const int major = b[24], minor = b[25];
  h.minor = minor;
  if (major != 1 || minor > 4) {
    throw DataError(name, "LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                              " is not supported (canopy reads LAS 1.0-1.4)");
  }
  const int format_byte = b[104] & 0x3F;  // LAZ: without LASzip's compression bits
  const std::size_t header_size = h.header_size = get<std::uint16_t>(b + 94);
  const std::size_t need_header = minor >= 4 ? kHeader14 : minor == 3 ? kHeader13 : kHeader12;
  if (header_size < need_header) {
    throw DataError(name, "LAS 1." + std::to_string(minor) + " header size " + std::to_string(header_size) +
                              " is below the " + std::to_string(need_header) + " bytes the version needs");
  }
  if (header_size > size) {
    throw DataError(name, "LAS header size " + std::to_string(header_size) +
                              " is beyond the end of the file (" + std::to_string(size) + " bytes)");
  }
  const std::size_t data_offset = h.data_offset = get<std::uint32_t>(b + 96);
  h.vlr_count = get<std::uint32_t>(b + 100);
  const int format = h.format = format_byte;
  if (format > 10)
    throw DataError(name, "unknown LAS point data format " + std::to_string(format) + " (0-10 exist)");
  const std::size_t record = h.record = get<std::uint16_t>(b + 105);
  if (record < kMinRecord[format]) {
    throw DataError(name, "point record length " + std::to_string(record) + " is below the " +
                              std::to_string(kMinRecord[format]) + " bytes of point format " +
                              std::to_string(format));
  }
  if (data_offset < header_size) {
    throw DataError(name, "offset to point data " + std::to_string(data_offset) + " lies inside the " +
                              std::to_string(header_size) + "-byte header");
  }
  if (data_offset > size) {
    throw DataError(name, "offset to point data " + std::to_string(data_offset) +
                              " is beyond the end of the file (" + std::to_string(size) +
                              " bytes; truncated?)");
  }
  read_las_transform(b, h, name);
  return h;
}

std::uint64_t point_count(const unsigned char* b, int minor, const std::string& name) {
  std::uint64_t n = get<std::uint32_t>(b + 107);
  if (minor >= 4) {
    const std::uint64_t n64 = get<std::uint64_t>(b + 247);
    if (n64 != 0) {
      if (n != 0 && n != n64) {
        throw DataError(name, "LAS header point counts disagree: legacy " + std::to_string(n) + ", LAS 1.4 " +
                                  std::to_string(n64));
      }
      n = n64;
    }
  }
  return n;
}

}  // namespace las

namespace {

LasHeader read_las_header(const unsigned char* b, std::size_t size, const std::string& name) {
  LasHeader h = las::read_header_fields(b, size, name);
  read_las_point_count(b, size, h, name);
  return h;
}

// VLRs: between the header and the point data, every one must fit there. canopy's comments
// VLR fills cloud->comments.
void read_vlrs(const unsigned char* b, const LasHeader& h, const std::string& name, PointCloud* cloud,
               ExtraVlr* extra) {
  for_each_vlr(b, h.data_offset, h, name, [&](const unsigned char* v, std::size_t len) {
    const std::uint16_t id = get<std::uint16_t>(v + 18);
    if (has_prefix(v + 2, 16, "LASF_Spec") && id == 4 && extra->data == nullptr) {
      extra->data = v + kVlrHeader;
      extra->len = len;
    } else if (has_prefix(v + 2, 16, "canopy") && id == 1) {
      std::size_t s = 0;
      const char* t = reinterpret_cast<const char*>(v + kVlrHeader);
      while (s < len) {
        std::size_t e = s;
        while (e < len && t[e] != '\n') ++e;
        cloud->comments.push_back(printable(v + kVlrHeader + s, e - s));
        s = e + 1;
      }
    }
  });
}

// The header block of a LAS/LAZ file whose header `h` was read from `b`: the VLRs that lie in
// b's first `available` bytes (for_each_vlr's checks).
LasHeaderBlock header_block(const unsigned char* b, std::size_t available, const LasHeader& h,
                            const std::string& name) {
  LasHeaderBlock out;
  out.major = b[24];
  out.minor = h.minor;
  out.point_format = h.format;
  out.global_encoding = get<std::uint16_t>(b + 6);
  for_each_vlr(b, available, h, name, [&](const unsigned char* v, std::size_t len) {
    LasVlr vlr;
    const char* user = reinterpret_cast<const char*>(v + 2);
    vlr.user_id.assign(user, strnlen(user, 16));
    vlr.record_id = get<std::uint16_t>(v + 18);
    vlr.payload.assign(reinterpret_cast<const char*>(v + kVlrHeader), len);
    out.vlrs.push_back(std::move(vlr));
  });
  return out;
}

// The bytes of the header block read_las_header_block returns: up to the point data, at most
// max_bytes (the header always whole).
std::size_t header_block_bytes(const LasHeader& h, std::size_t max_bytes) {
  return std::min(h.data_offset, std::max(max_bytes, h.header_size));
}

// The header block of the LAZ file whose first bytes `b` hold its header and VLRs (laz_to_las
// read them: the checks have been made), as read_las_header_block gives it; the CRS EVLRs those
// of `decoded`, the block of the LAS file it decodes to (laz_to_las copies the EVLRs as they
// are).
LasHeaderBlock laz_header_block(const unsigned char* b, std::size_t size, const std::string& name,
                                LasHeaderBlock decoded) {
  const LasHeader h = las::read_header_fields(b, size, name);
  LasHeaderBlock out = header_block(b, header_block_bytes(h, kLasHeaderBlockBytes), h, name);
  out.evlrs = std::move(decoded.evlrs);
  out.evlr_note = std::move(decoded.evlr_note);
  return out;
}

// Where the reader takes a LAS file's bytes from: a whole file in memory (parse_las) or an open
// regular file, read in pieces (read_las). Callers ask only for bytes they checked lie within
// size().
class LasSource {
 public:
  explicit LasSource(std::uint64_t size) : size_(size) {}
  virtual ~LasSource() = default;
  LasSource(const LasSource&) = delete;
  LasSource& operator=(const LasSource&) = delete;
  std::uint64_t size() const { return size_; }
  // The n bytes at `at` (at + n <= size()), valid until `scratch` changes; a file source reads
  // them into `scratch`.
  virtual const unsigned char* bytes(std::uint64_t at, std::size_t n, std::vector<unsigned char>* scratch) = 0;

 private:
  std::uint64_t size_;
};

class MemorySource final : public LasSource {
 public:
  explicit MemorySource(const std::string& bytes)
      : LasSource(bytes.size()), b_(reinterpret_cast<const unsigned char*>(bytes.data())) {}
  const unsigned char* bytes(std::uint64_t at, std::size_t, std::vector<unsigned char>*) override {
    return b_ + at;
  }

 private:
  const unsigned char* b_;
};

class FileSource final : public LasSource {
 public:
  FileSource(int fd, std::uint64_t size, const std::string& name) : LasSource(size), fd_(fd), name_(name) {}
  const unsigned char* bytes(std::uint64_t at, std::size_t n, std::vector<unsigned char>* scratch) override {
    if (scratch->size() < n) scratch->resize(n);
    std::size_t done = 0;
    while (done < n) {
      const ssize_t got = ::pread(fd_, scratch->data() + done, n - done, static_cast<off_t>(at + done));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) throw DataError(name_, std::string("read error: ") + std::strerror(errno));
      if (got == 0) {
        throw DataError(name_, "the file ended at byte " + std::to_string(at + done) +
                                   " while it was read (it had " + std::to_string(size()) +
                                   " bytes when opened: changed meanwhile?)");
      }
      done += static_cast<std::size_t>(got);
    }
    return scratch->data();
  }

 private:
  int fd_;
  const std::string& name_;
};

// Calls visit(at, v, len) for every EVLR (LAS 1.4; v: its 60-byte header at byte `at`, then
// `len` bytes of payload, not read here) of the file whose header is `b`, in order, each checked
// to lie in the file: the first at or after `min_start` (`min_what` names that place in the
// message: the end of the point records; a LAZ file's point data offset, its compressed
// records' end being unknown before they are decoded), none running past the end. Each
// failure is a DataError naming the file.
template <typename Visit>
void for_each_evlr(const unsigned char* b, LasSource& src, int minor, std::uint64_t min_start,
                   const std::string& min_what, const std::string& name, Visit visit) {
  const std::uint64_t size = src.size();
  if (minor < 4) return;
  const std::uint64_t evlr_start = get<std::uint64_t>(b + 235);
  const std::uint32_t evlr_count = get<std::uint32_t>(b + 243);
  if (evlr_count == 0) return;
  if (evlr_start < min_start || evlr_start > size) {
    throw DataError(name, "EVLR start " + std::to_string(evlr_start) + " is not between " + min_what + " (" +
                              std::to_string(min_start) + ") and the end of the file (" +
                              std::to_string(size) + ")");
  }
  std::uint64_t at = evlr_start;
  std::vector<unsigned char> scratch;
  for (std::uint32_t i = 0; i < evlr_count; ++i) {
    if (size - at < kEvlrHeader) {
      throw DataError(name, "LAS header says " + std::to_string(evlr_count) + " EVLRs but EVLR " +
                                std::to_string(i + 1) +
                                " does not fit in the file (truncated or broken count)");
    }
    const unsigned char* v = src.bytes(at, kEvlrHeader, &scratch);
    const std::uint64_t len = get<std::uint64_t>(v + 20);
    if (size - at - kEvlrHeader < len) {
      throw DataError(name, "EVLR " + std::to_string(i + 1) + " of " + std::to_string(len) +
                                " bytes runs past the end of the file");
    }
    visit(at, v, len);
    at += kEvlrHeader + len;
  }
}

// Keeps the CRS records among the EVLRs for_each_evlr walks (LasHeaderBlock::evlrs and
// evlr_note): the first of each kind, its payload read when it is at most kLasCrsEvlrBytes.
class CrsEvlrs {
 public:
  explicit CrsEvlrs(LasSource& src) : src_(src) {}
  void add(std::uint32_t index, std::uint64_t at, const unsigned char* v, std::uint64_t len) {
    const char* u = reinterpret_cast<const char*>(v + 2);
    const std::string user(u, strnlen(u, 16));  // as header_block reads a VLR's
    const auto id = get<std::uint16_t>(v + 18);
    if (!is_crs_record(user, id)) return;
    for (const LasVlr& r : evlrs) {
      if (r.user_id == user && r.record_id == id) return;  // a later one of a kind already kept
    }
    if (len > kLasCrsEvlrBytes) {
      if (note.empty()) {
        note = "EVLR " + std::to_string(index) + " (" + user + " " + std::to_string(id) + ") of " +
               std::to_string(len) + " bytes is over the " + std::to_string(kLasCrsEvlrBytes) +
               " canopy reads of a CRS record: not read";
      }
      return;
    }
    LasVlr r;
    r.user_id = user;
    r.record_id = id;
    const auto n = static_cast<std::size_t>(len);
    std::vector<unsigned char> bytes;
    r.payload.assign(reinterpret_cast<const char*>(src_.bytes(at + kEvlrHeader, n, &bytes)), n);
    evlrs.push_back(std::move(r));
  }
  std::vector<LasVlr> evlrs;
  std::string note;

 private:
  LasSource& src_;
};

// An open std::istream's file, read at offsets (read_las_header_block's EVLRs).
class StreamSource final : public LasSource {
 public:
  StreamSource(std::istream& f, std::uint64_t size, const std::string& name)
      : LasSource(size), f_(f), name_(name) {}
  const unsigned char* bytes(std::uint64_t at, std::size_t n, std::vector<unsigned char>* scratch) override {
    if (scratch->size() < n) scratch->resize(n);
    f_.clear();
    f_.seekg(static_cast<std::streamoff>(at));
    if (!f_.read(reinterpret_cast<char*>(scratch->data()), static_cast<std::streamsize>(n)))
      throw DataError(name_, "read failed");
    return scratch->data();
  }

 private:
  std::istream& f_;
  const std::string& name_;
};

// EVLRs (LAS 1.4): after the point records, each within the file. Extra Bytes: its payload (the
// part parse_extra_bytes reads) is copied into *payload unless a VLR gave one. `crs` (not null):
// also the CRS records.
void read_evlrs(const unsigned char* b, LasSource& src, const LasHeader& h, const std::string& name,
                ExtraVlr* extra, std::vector<unsigned char>* payload, CrsEvlrs* crs) {
  const std::uint64_t data_end = h.data_offset + h.n * h.record;
  std::uint32_t index = 0;
  for_each_evlr(
      b, src, h.minor, data_end, "the end of the point data", name,
      [&](std::uint64_t at, const unsigned char* v, std::uint64_t len) {
        ++index;
        if (has_prefix(v + 2, 16, "LASF_Spec") && get<std::uint16_t>(v + 18) == 4 && extra->data == nullptr) {
          // parse_extra_bytes reads at most kMaxExtraFields descriptors.
          const auto used =
              static_cast<std::size_t>(std::min<std::uint64_t>(len, kMaxExtraFields * kExtraDescriptor));
          extra->data = src.bytes(at + kEvlrHeader, used, payload);  // *payload is not used again
          extra->len = used;
        } else if (crs != nullptr) {
          crs->add(index, at, v, len);
        }
      });
}

// The columns of a point format (standard fields, then Extra Bytes), packed at their width in
// the record (PointCloud's packed columns): x y z the int32 with the header's scale and offset,
// the flags a byte each, gps_time (already a double) unpacked. nullptr: not selected.
struct LasColumns {
  int format = 0;
  bool extended = false, has_rgb = false;
  std::size_t rgb_at = 0, gps_at = 0;
  std::vector<std::int32_t>* xyz[3] = {nullptr, nullptr, nullptr};
  std::vector<std::uint16_t>*intensity{}, *source{}, *nir{};
  std::vector<std::uint16_t>* rgb[3] = {nullptr, nullptr, nullptr};
  std::vector<std::uint8_t>*ret{}, *nret{}, *scan_dir{}, *edge{}, *cls{}, *synthetic{}, *key_point{},
      *withheld{}, *overlap{}, *channel{}, *user{};
  std::vector<std::int8_t>* angle8{};  // formats 0-5: the scan angle rank in degrees
  std::vector<float>* angle{};         // formats 6-10: the scan angle in 0.006 degree steps, as float
  std::vector<double>* gps{};
  std::vector<Extra> extras;
  std::vector<std::string> names;  // every standard field of the format, selected or not
};

LasColumns add_las_columns(int format, const LasHeader& h, const FieldSelection& want, PointCloud& cloud) {
  LasColumns c;
  c.format = format;
  const bool extended = c.extended = format >= 6;
  const bool has_gps = format == 1 || format >= 3;
  c.has_rgb = format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
  const bool has_nir = format == 8 || format == 10;
  c.rgb_at = format == 2 ? 20 : format <= 5 ? 28 : 30;
  c.gps_at = extended ? 22 : 20;
  // Each field in the order of the columns; add() only when selected.
  auto take = [&](auto** slot, const char* name, FieldType t) {
    c.names.push_back(name);
    if (!want.wants(name)) return;
    using T = typename std::remove_pointer_t<std::remove_pointer_t<decltype(slot)>>::value_type;
    *slot = &cloud.add_packed<T>(name, t);
  };
  for (int d = 0; d < 3; ++d) {
    const char* name = d == 0 ? "x" : d == 1 ? "y" : "z";
    c.names.push_back(name);
    if (want.wants(name))
      c.xyz[d] = &cloud.add_packed<std::int32_t>(name, kFloat64, true, h.scale[d], h.offset[d]);
  }
  take(&c.intensity, "intensity", {'U', 2});
  take(&c.ret, "return_number", kUint8);
  take(&c.nret, "number_of_returns", kUint8);
  take(&c.scan_dir, "scan_direction_flag", kUint8);
  take(&c.edge, "edge_of_flight_line", kUint8);
  take(&c.cls, "classification", kUint8);
  take(&c.synthetic, "synthetic", kUint8);
  take(&c.key_point, "key_point", kUint8);
  take(&c.withheld, "withheld", kUint8);
  if (extended) {
    take(&c.overlap, "overlap", kUint8);
    take(&c.channel, "scanner_channel", kUint8);
    take(&c.angle, "scan_angle", kFloat32);
  } else {
    take(&c.angle8, "scan_angle", kFloat32);
  }
  take(&c.user, "user_data", kUint8);
  take(&c.source, "point_source_id", {'U', 2});
  if (has_gps) {
    c.names.push_back("gps_time");
    if (want.wants("gps_time")) c.gps = &cloud.add("gps_time", kFloat64);  // doubles already
  }
  if (c.has_rgb) {
    take(&c.rgb[0], "red", {'U', 2});
    take(&c.rgb[1], "green", {'U', 2});
    take(&c.rgb[2], "blue", {'U', 2});
  }
  if (has_nir) take(&c.nir, "nir", {'U', 2});
  return c;
}

// Appends value(record) of the k records at p (`record` bytes apart) to the column, unless it
// is not selected (nullptr): the column has its room reserved, so nothing is zero-filled first.
template <typename T, typename F>
void append(std::vector<T>* col, const unsigned char* p, std::size_t k, std::size_t record, F value) {
  if (col == nullptr) return;
  // Grown by the piece (within the reserved room), then written through a pointer: no
  // capacity check per value (the whole read: 13-20 % less CPU than push_back, measured).
  const std::size_t at = col->size();
  col->resize(at + k);
  T* out = col->data() + at;
  for (std::size_t i = 0; i < k; ++i, p += record) out[i] = value(p);
}

template <typename T>
void append_raw(void* col, const unsigned char* p, std::size_t k, std::size_t record, std::size_t at) {
  append(static_cast<std::vector<T>*>(col), p, k, record,
         [at](const unsigned char* r) { return get<T>(r + at); });
}

// Decodes k whole records at p, column by column (the records stay in cache meanwhile).
void decode_records(const unsigned char* p, std::size_t k, const LasHeader& h, const LasColumns& c) {
  const std::size_t rec = h.record;
  for (int d = 0; d < 3; ++d) {
    const std::size_t at = 4 * static_cast<std::size_t>(d);
    append(c.xyz[d], p, k, rec, [at](const unsigned char* r) { return get<std::int32_t>(r + at); });
  }
  auto bits = [&](std::vector<std::uint8_t>* col, std::size_t at, unsigned shift, unsigned mask) {
    append(col, p, k, rec,
           [=](const unsigned char* r) { return static_cast<std::uint8_t>((r[at] >> shift) & mask); });
  };
  append_raw<std::uint16_t>(c.intensity, p, k, rec, 12);
  if (!c.extended) {
    bits(c.ret, 14, 0, 7);
    bits(c.nret, 14, 3, 7);
    bits(c.scan_dir, 14, 6, 1);
    bits(c.edge, 14, 7, 1);
    bits(c.cls, 15, 0, 31);
    bits(c.synthetic, 15, 5, 1);
    bits(c.key_point, 15, 6, 1);
    bits(c.withheld, 15, 7, 1);
    append_raw<std::int8_t>(c.angle8, p, k, rec, 16);
    bits(c.user, 17, 0, 255);
    append_raw<std::uint16_t>(c.source, p, k, rec, 18);
  } else {
    bits(c.ret, 14, 0, 15);
    bits(c.nret, 14, 4, 15);
    bits(c.synthetic, 15, 0, 1);
    bits(c.key_point, 15, 1, 1);
    bits(c.withheld, 15, 2, 1);
    bits(c.overlap, 15, 3, 1);
    bits(c.channel, 15, 4, 3);
    bits(c.scan_dir, 15, 6, 1);
    bits(c.edge, 15, 7, 1);
    bits(c.cls, 16, 0, 255);
    bits(c.user, 17, 0, 255);
    append(c.angle, p, k, rec,
           [](const unsigned char* r) { return static_cast<float>(get<std::int16_t>(r + 18) * 0.006); });
    append_raw<std::uint16_t>(c.source, p, k, rec, 20);
  }
  append_raw<double>(c.gps, p, k, rec, c.gps_at);
  if (c.has_rgb) {
    for (std::size_t j = 0; j < 3; ++j) append_raw<std::uint16_t>(c.rgb[j], p, k, rec, c.rgb_at + 2 * j);
  }
  append_raw<std::uint16_t>(c.nir, p, k, rec, 36);
  for (const auto& e : c.extras) {
    const std::size_t step = static_cast<std::size_t>(kBaseSize[e.base]);
    for (int j = 0; j < e.count; ++j) {
      void* col = e.cols[static_cast<std::size_t>(j)];
      if (col == nullptr) continue;
      const std::size_t at = e.offset + step * static_cast<std::size_t>(j);
      switch (e.base) {
        case 1: append_raw<std::uint8_t>(col, p, k, rec, at); break;
        case 2: append_raw<std::int8_t>(col, p, k, rec, at); break;
        case 3: append_raw<std::uint16_t>(col, p, k, rec, at); break;
        case 4: append_raw<std::int16_t>(col, p, k, rec, at); break;
        case 5: append_raw<std::uint32_t>(col, p, k, rec, at); break;
        case 6: append_raw<std::int32_t>(col, p, k, rec, at); break;
        case 7: append_raw<std::uint64_t>(col, p, k, rec, at); break;
        case 8: append_raw<std::int64_t>(col, p, k, rec, at); break;
        case 9: append_raw<float>(col, p, k, rec, at); break;
        default: append_raw<double>(col, p, k, rec, at); break;
      }
    }
  }
}

// Room for n values in every selected column.
void reserve_columns(const LasColumns& c, std::size_t n) {
  auto room = [n](auto* col) {
    if (col != nullptr) col->reserve(n);
  };
  for (auto* col : c.xyz) room(col);
  for (auto* col : {c.intensity, c.source, c.nir, c.rgb[0], c.rgb[1], c.rgb[2]}) room(col);
  for (auto* col : {c.ret, c.nret, c.scan_dir, c.edge, c.cls, c.synthetic, c.key_point, c.withheld, c.overlap,
                    c.channel, c.user})
    room(col);
  room(c.angle8);
  room(c.angle);
  room(c.gps);
  for (const auto& e : c.extras) {
    for (void* col : e.cols) {
      if (col == nullptr) continue;
      switch (e.base) {
        case 1: room(static_cast<std::vector<std::uint8_t>*>(col)); break;
        case 2: room(static_cast<std::vector<std::int8_t>*>(col)); break;
        case 3: room(static_cast<std::vector<std::uint16_t>*>(col)); break;
        case 4: room(static_cast<std::vector<std::int16_t>*>(col)); break;
        case 5: room(static_cast<std::vector<std::uint32_t>*>(col)); break;
        case 6: room(static_cast<std::vector<std::int32_t>*>(col)); break;
        case 7: room(static_cast<std::vector<std::uint64_t>*>(col)); break;
        case 8: room(static_cast<std::vector<std::int64_t>*>(col)); break;
        case 9: room(static_cast<std::vector<float>*>(col)); break;
        default: room(static_cast<std::vector<double>*>(col)); break;
      }
    }
  }
}

// The checks and the decoding after the signature: `b` holds the file's first
// min(size, max(kHeader14, point data offset)) bytes (header and VLRs; at least kHeader12),
// `src` the whole file for the EVLRs and the point records, read `chunk_bytes` at a time.
PointCloud decode_las(const unsigned char* b, LasSource& src, const std::string& name,
                      std::size_t chunk_bytes, const FieldSelection& want, LasHeaderBlock* block) {
  const std::size_t size = static_cast<std::size_t>(src.size());
  const LasHeader h = read_las_header(b, size, name);
  PointCloud cloud;
  ExtraVlr extra;
  std::vector<unsigned char> evlr_payload;
  read_vlrs(b, h, name, &cloud, &extra);
  CrsEvlrs crs(src);
  read_evlrs(b, src, h, name, &extra, &evlr_payload, block != nullptr ? &crs : nullptr);
  if (block != nullptr) {
    *block = header_block(b, header_block_bytes(h, kLasHeaderBlockBytes), h, name);
    block->evlrs = std::move(crs.evlrs);
    block->evlr_note = std::move(crs.note);
  }
  LasColumns columns = add_las_columns(h.format, h, want, cloud);
  if (extra.data != nullptr) {
    columns.extras = parse_extra_bytes(extra.data, extra.len, kMinRecord[h.format],
                                       h.record - kMinRecord[h.format], columns.names, want, &cloud);
  }
  // read_las_header checked that the records fit the file: the columns are bounded by it.
  const auto n = static_cast<std::size_t>(h.n);
  reserve_columns(columns, n);
  // A small file is read in smaller pieces (a sixteenth of its records, at least 64 KiB), so
  // the piece does not add a fifth of the file to the memory of a 1 MiB file.
  const std::size_t piece = chunk_bytes == kLasReadChunk
                                ? std::min(chunk_bytes, std::max<std::size_t>(64 << 10, n / 16 * h.record))
                                : chunk_bytes;
  const std::size_t per = std::max<std::size_t>(1, piece / h.record);
  std::vector<unsigned char> chunk;
  for (std::size_t i = 0; i < n;) {
    const std::size_t k = std::min(per, n - i);
    decode_records(src.bytes(h.data_offset + std::uint64_t(i) * h.record, k * h.record, &chunk), k, h, columns);
    i += k;
  }
  cloud.resize(n);  // every column already holds n values: only the cloud's size is set
  return cloud;
}

// The bytes decode_las needs in `b`: the header, the VLRs up to the point data offset.
std::size_t las_head_size(const unsigned char* b, std::size_t have, std::uint64_t size) {
  std::uint64_t want = std::min<std::uint64_t>(size, kHeader14);
  if (have >= kHeader12)
    want = std::max<std::uint64_t>(want, std::min<std::uint64_t>(size, get<std::uint32_t>(b + 96)));
  return static_cast<std::size_t>(want);
}

// Closes a file descriptor when it goes out of scope.
struct FdCloser {
  int fd;
  ~FdCloser() { ::close(fd); }
};

}  // namespace

PointCloud parse_las(const std::string& bytes, const std::string& name) { return parse_las(bytes, name, {}); }

PointCloud parse_las(const std::string& bytes, const std::string& name, const FieldSelection& fields,
                     LasHeaderBlock* header) {
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();
  if (!is_las(bytes)) throw DataError(name, "not a LAS file (no LASF signature)");
  if (is_laz(bytes)) {  // LAZ: decompressed first; its own header block (LASzip's VLR too)
    LasHeaderBlock decoded;
    PointCloud cloud = parse_las(laz_to_las(bytes, name), name, fields, header != nullptr ? &decoded : nullptr);
    if (header != nullptr) *header = laz_header_block(b, size, name, std::move(decoded));
    return cloud;
  }
  if (size < kHeader12) {
    throw DataError(name, "LAS header truncated: file has " + std::to_string(size) +
                              " bytes, a header needs " + std::to_string(kHeader12));
  }
  MemorySource src(bytes);
  return decode_las(b, src, name, kLasReadChunk, fields, header);
}

PointCloud read_las(const std::string& path, const FieldSelection& fields, LasHeaderBlock* header) {
  return read_las(path, kLasReadChunk, fields, header);
}

PointCloud read_las(const std::string& path, std::size_t chunk_bytes, const FieldSelection& fields,
                    LasHeaderBlock* header) {
  struct stat st {};
  // Standard input, a FIFO or a device cannot be read twice nor at an offset; a missing file
  // or a directory gets read_file's error.
  if (path == "-" || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    return parse_las(common::read_file(path), path, fields, header);
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw DataError(path, std::string("cannot open: ") + std::strerror(errno));
  const FdCloser closer{fd};
  if (::fstat(fd, &st) != 0) throw DataError(path, std::string("cannot open: ") + std::strerror(errno));
  FileSource src(fd, static_cast<std::uint64_t>(st.st_size), path);
  // The header and the VLRs (all LAZ detection needs, laz.h), then the rest piece by piece.
  std::vector<unsigned char> scratch;
  std::size_t have = las_head_size(nullptr, 0, src.size());
  std::string head;
  head.assign(reinterpret_cast<const char*>(src.bytes(0, have, &scratch)), have);
  const std::size_t want = las_head_size(reinterpret_cast<const unsigned char*>(head.data()), have, src.size());
  if (want > have) head.assign(reinterpret_cast<const char*>(src.bytes(0, want, &scratch)), want);
  scratch = std::vector<unsigned char>();
  if (!is_las(head)) throw DataError(path, "not a LAS file (no LASF signature)");
  if (is_laz(head)) {
    // LAZ: decompressed whole, as parse_las does; the compressed bytes are freed before the
    // LAS is decoded.
    const std::string las = laz_to_las(common::read_file(path), path);
    LasHeaderBlock decoded;
    PointCloud cloud = parse_las(las, path, fields, header != nullptr ? &decoded : nullptr);
    if (header != nullptr) {
      *header = laz_header_block(reinterpret_cast<const unsigned char*>(head.data()), src.size(), path,
                                 std::move(decoded));
    }
    return cloud;
  }
  if (head.size() < kHeader12) {
    throw DataError(path, "LAS header truncated: file has " + std::to_string(src.size()) +
                              " bytes, a header needs " + std::to_string(kHeader12));
  }
  return decode_las(reinterpret_cast<const unsigned char*>(head.data()), src, path, chunk_bytes, fields,
                    header);
}

LasHeaderBlock read_las_header_block(const std::string& path, std::size_t max_bytes) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DataError(path, "cannot open: " + std::string(std::strerror(errno)));
  f.seekg(0, std::ios::end);
  const std::streamoff end = f.tellg();
  if (end < 0) throw DataError(path, "cannot tell its size (not a regular file?)");
  const auto size = std::size_t(end);
  std::string bytes(std::min(size, kHeader14), '\0');
  f.seekg(0);
  if (!f.read(bytes.data(), std::streamsize(bytes.size()))) throw DataError(path, "read failed");
  if (!is_las(bytes)) throw DataError(path, "not a LAS file (no LASF signature)");
  if (bytes.size() < kHeader12) {
    throw DataError(path, "LAS header truncated: file has " + std::to_string(size) +
                              " bytes, a header needs " + std::to_string(kHeader12));
  }
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  const LasHeader h = las::read_header_fields(b, size, path);
  // The VLRs: up to the point data, at most max_bytes (the header is read whole).
  const std::size_t available = header_block_bytes(h, max_bytes);
  if (available > bytes.size()) {
    const std::size_t had = bytes.size();
    bytes.resize(available);
    if (!f.read(bytes.data() + had, std::streamsize(available - had))) throw DataError(path, "read failed");
  }
  const auto* block_bytes = reinterpret_cast<const unsigned char*>(bytes.data());
  LasHeaderBlock out = header_block(block_bytes, available, h, path);
  if (h.minor < 4 || get<std::uint32_t>(block_bytes + 243) == 0) return out;
  // The EVLRs: each header read (60 bytes), the CRS records' payloads (at most
  // kLasCrsEvlrBytes each). They follow the point records (LAS: where the point count says
  // they end; LAZ: the compressed records, whose end is known only by decoding them); a
  // problem is a note (the point reader refuses the file).
  StreamSource src(f, size, path);
  CrsEvlrs crs(src);
  try {
    std::uint64_t min_start = h.data_offset;
    std::string min_what = "the point data";
    if (!laszip_compressed(bytes)) {
      const std::uint64_t n = las::point_count(block_bytes, h.minor, path);
      if (n > (size - h.data_offset) / h.record) {
        throw DataError(path, "the point count " + std::to_string(n) + " does not fit the file");
      }
      min_start = h.data_offset + n * h.record;
      min_what = "the end of the point data";
    }
    std::uint32_t index = 0;
    for_each_evlr(
        block_bytes, src, h.minor, min_start, min_what, path,
        [&](std::uint64_t at, const unsigned char* v, std::uint64_t len) { crs.add(++index, at, v, len); });
  } catch (const DataError& e) { crs.note = "EVLRs not read: " + e.cause(); }
  out.evlrs = std::move(crs.evlrs);
  out.evlr_note = std::move(crs.note);
  return out;
}

namespace {

// Standard fields of the written point formats (6, 7, 8); every other column but x y z is
// written as Extra Bytes.
bool standard_field(const std::string& f, int format) {
  static const char* base[] = {"intensity",
                               "return_number",
                               "number_of_returns",
                               "scan_direction_flag",
                               "edge_of_flight_line",
                               "classification",
                               "synthetic",
                               "key_point",
                               "withheld",
                               "overlap",
                               "scanner_channel",
                               "scan_angle",
                               "user_data",
                               "point_source_id",
                               "gps_time"};
  for (const char* s : base) {
    if (f == s) return true;
  }
  if (format >= 7 && (f == "red" || f == "green" || f == "blue")) return true;
  return format >= 8 && f == "nir";
}

int extra_type(FieldType t) {
  if (t.kind == 'U') return t.size == 1 ? 1 : t.size == 2 ? 3 : 5;
  if (t.kind == 'I') return t.size == 1 ? 2 : t.size == 2 ? 4 : 6;
  return t.size == 4 ? 9 : 10;
}

void put_text(std::string* out, const std::string& s, std::size_t n) {
  std::string t = s.substr(0, n);
  t.resize(n, '\0');
  out->append(t);
}

// One Extra Bytes column and the whole set: descriptors and the record length.
struct ExtraColumn {
  const std::vector<double>* data;
  FieldType type;
};
struct ExtraFields {
  std::vector<ExtraColumn> extras;
  std::string descriptors;
  std::size_t record = 0;
};

// Offset: the middle of the extent rounded to whole metres; every coordinate must land on
// the int32 grid of kLasWriteScale steps about it.
void las_offsets(const std::vector<double>* const xyz[3], std::size_t n, const std::string& name,
                 double off[3]) {
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = n ? std::numeric_limits<double>::infinity() : 0;
    hi[d] = n ? -std::numeric_limits<double>::infinity() : 0;
    for (double v : *xyz[d]) {
      if (!std::isfinite(v)) {
        throw DataError(name, std::string("non-finite ") + "xyz"[d] +
                                  " coordinate (NaN or infinite coordinates are not written)");
      }
      lo[d] = std::min(lo[d], v);
      hi[d] = std::max(hi[d], v);
    }
    off[d] = std::round(0.5 * lo[d] + 0.5 * hi[d]);
    const double reach = std::max(off[d] - lo[d], hi[d] - off[d]) / kLasWriteScale;
    if (!(reach < 2147483647.0)) {
      throw DataError(name, std::string("the cloud's ") + "xyz"[d] + " extent (" +
                                detail::format_value(hi[d] - lo[d], kFloat64) +
                                " m) does not fit LAS's 32-bit integer coordinates at " +
                                detail::format_value(kLasWriteScale, kFloat64) + " m resolution");
    }
  }
}

// Every column but x y z and the format's standard fields, as Extra Bytes.
ExtraFields extra_fields(const PointCloud& cloud, int format, const std::string& name) {
  ExtraFields x;
  std::vector<ExtraColumn>& extras = x.extras;
  std::string& descriptors = x.descriptors;
  std::size_t& record = x.record;
  record = kMinRecord[format];
  for (std::size_t c = 0; c < cloud.names().size(); ++c) {
    const std::string& f = cloud.names()[c];
    if (f == "x" || f == "y" || f == "z" || standard_field(f, format)) continue;
    if (f.size() > 32)
      throw DataError(name, "field name '" + f + "' is longer than LAS's 32-character Extra Bytes names");
    const FieldType t = cloud.types()[c];
    extras.push_back({&cloud.col(c), t});
    record += static_cast<std::size_t>(t.size);
    std::string d(kExtraDescriptor, '\0');
    d[2] = static_cast<char>(extra_type(t));
    std::memcpy(&d[4], f.data(), f.size());
    const std::string desc = "canopy field";
    std::memcpy(&d[160], desc.data(), desc.size());
    descriptors += d;
  }
  if (record > 65535 || descriptors.size() > 65535) {
    throw DataError(
        name, "too many fields for one LAS point record (" + std::to_string(extras.size()) + " extra fields)");
  }
  return x;
}

// The VLRs: Extra Bytes descriptors and canopy's comments (provenance).
std::string las_vlrs(const PointCloud& cloud, const ExtraFields& x, std::uint32_t* count) {
  std::string comments;
  for (const auto& line : cloud.comments) {
    const std::string c = header_safe_comment(line);  // one comment, one line of the VLR
    if (comments.size() + c.size() + 1 > 65535) break;
    comments += (comments.empty() ? "" : "\n") + c;
  }

  std::string vlrs;
  auto add_vlr = [&](const std::string& user, std::uint16_t id, const std::string& desc,
                     const std::string& payload) {
    put<std::uint16_t>(&vlrs, 0);
    put_text(&vlrs, user, 16);
    put<std::uint16_t>(&vlrs, id);
    put<std::uint16_t>(&vlrs, static_cast<std::uint16_t>(payload.size()));
    put_text(&vlrs, desc, 32);
    vlrs += payload;
  };
  std::uint32_t& vlr_count = *count;
  vlr_count = 0;
  if (!x.extras.empty()) add_vlr("LASF_Spec", 4, "Extra Bytes Record", x.descriptors), ++vlr_count;
  if (!comments.empty()) add_vlr("canopy", 1, "comments (provenance)", comments), ++vlr_count;
  return vlrs;
}

// The point records (format 6, 7 or 8), with the quantised extent and counts by return.
std::string point_records(const PointCloud& cloud, const std::vector<double>* const xyz[3],
                          const double off[3], int format, const ExtraFields& x, std::uint64_t by_return[15],
                          std::int64_t qmin[3], std::int64_t qmax[3]) {
  const std::size_t n = cloud.size();
  const std::size_t record = x.record;
  const std::vector<ExtraColumn>& extras = x.extras;
  auto column = [&](const char* f) { return cloud.has(f) ? &cloud.col(f) : nullptr; };
  const std::vector<double>* intensity = column("intensity");
  const std::vector<double>* ret = column("return_number");
  const std::vector<double>* nret = column("number_of_returns");
  const std::vector<double>* flags[6] = {
      column("synthetic"), column("key_point"),           column("withheld"),
      column("overlap"),   column("scan_direction_flag"), column("edge_of_flight_line")};
  const std::vector<double>* channel = column("scanner_channel");
  const std::vector<double>* cls = column("classification");
  const std::vector<double>* user = column("user_data");
  const std::vector<double>* angle = column("scan_angle");
  const std::vector<double>* source = column("point_source_id");
  const std::vector<double>* gps = column("gps_time");
  const std::vector<double>* colour[3] = {column("red"), column("green"), column("blue")};
  const std::vector<double>* nir = column("nir");
  auto at = [](const std::vector<double>* c, std::size_t i, double fallback) { return c ? (*c)[i] : fallback; };
  using detail::to_int;

  std::string points;
  points.reserve(n * record);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      const auto q = static_cast<std::int32_t>(std::llround(((*xyz[d])[i] - off[d]) / kLasWriteScale));
      if (i == 0 || q < qmin[d]) qmin[d] = q;
      if (i == 0 || q > qmax[d]) qmax[d] = q;
      put<std::int32_t>(&points, q);
    }
    put(&points, to_int<std::uint16_t>(at(intensity, i, 0), 0, 65535));
    const unsigned r = to_int<std::uint8_t>(at(ret, i, 1), 0, 15);
    const unsigned nr = to_int<std::uint8_t>(at(nret, i, 1), 0, 15);
    if (r >= 1) ++by_return[r - 1];
    points += static_cast<char>(r | (nr << 4));
    unsigned f = 0;
    for (int k = 0; k < 4; ++k) f |= (at(flags[k], i, 0) != 0 ? 1u : 0u) << k;
    f |= static_cast<unsigned>(to_int<std::uint8_t>(at(channel, i, 0), 0, 3)) << 4;
    f |= (at(flags[4], i, 0) != 0 ? 1u : 0u) << 6;
    f |= (at(flags[5], i, 0) != 0 ? 1u : 0u) << 7;
    points += static_cast<char>(f);
    points += static_cast<char>(to_int<std::uint8_t>(at(cls, i, 0), 0, 255));
    points += static_cast<char>(to_int<std::uint8_t>(at(user, i, 0), 0, 255));
    put(&points, to_int<std::int16_t>(at(angle, i, 0) / 0.006, -30000, 30000));
    put(&points, to_int<std::uint16_t>(at(source, i, 0), 0, 65535));
    put<double>(&points, at(gps, i, 0));
    if (format >= 7) {
      for (const auto* c : colour) put(&points, to_int<std::uint16_t>((*c)[i], 0, 65535));
    }
    if (format >= 8) put(&points, to_int<std::uint16_t>((*nir)[i], 0, 65535));
    for (const auto& e : extras) detail::write_scalar(&points, (*e.data)[i], e.type);
  }
  return points;
}

}  // namespace

std::string serialize_las(const PointCloud& cloud, const std::string& name) {
  cloud.require({"x", "y", "z"}, name, "LAS needs coordinates");
  const std::size_t n = cloud.size();
  const std::vector<double>* xyz[3] = {&cloud.col("x"), &cloud.col("y"), &cloud.col("z")};
  const bool rgb = cloud.has("red") && cloud.has("green") && cloud.has("blue");
  const int format = rgb ? (cloud.has("nir") ? 8 : 7) : 6;
  double off[3];
  las_offsets(xyz, n, name, off);
  const ExtraFields x = extra_fields(cloud, format, name);
  std::uint32_t vlr_count = 0;
  const std::string vlrs = las_vlrs(cloud, x, &vlr_count);
  std::uint64_t by_return[15] = {};
  std::int64_t qmin[3] = {0, 0, 0}, qmax[3] = {0, 0, 0};
  const std::string points = point_records(cloud, xyz, off, format, x, by_return, qmin, qmax);
  const std::size_t record = x.record;
  std::string out;
  out.reserve(kHeader14 + vlrs.size() + points.size());
  out += "LASF";
  put<std::uint16_t>(&out, 0);   // file source id
  put<std::uint16_t>(&out, 16);  // global encoding: WKT bit (required for point formats 6-10); no CRS given
  out.append(16, '\0');          // project GUID
  out += '\1';
  out += '\4';
  put_text(&out, "canopy", 32);
  put_text(&out, "canopy " CANOPY_VERSION, 32);
  put<std::uint16_t>(&out, 0);  // creation day and year: 0, so that same input -> same bytes
  put<std::uint16_t>(&out, 0);
  put<std::uint16_t>(&out, static_cast<std::uint16_t>(kHeader14));
  put<std::uint32_t>(&out, static_cast<std::uint32_t>(kHeader14 + vlrs.size()));
  put<std::uint32_t>(&out, vlr_count);
  out += static_cast<char>(format);
  put<std::uint16_t>(&out, static_cast<std::uint16_t>(record));
  put<std::uint32_t>(&out, 0);  // legacy point count and counts by return: 0 for formats 6-10
  for (int k = 0; k < 5; ++k) put<std::uint32_t>(&out, 0);
  for (int d = 0; d < 3; ++d) put<double>(&out, kLasWriteScale);
  for (int d = 0; d < 3; ++d) put<double>(&out, off[d]);
  for (int d = 0; d < 3; ++d) {
    put<double>(&out, static_cast<double>(qmax[d]) * kLasWriteScale + off[d]);
    put<double>(&out, static_cast<double>(qmin[d]) * kLasWriteScale + off[d]);
  }
  put<std::uint64_t>(&out, 0);  // waveform data packet record
  put<std::uint64_t>(&out, 0);  // first EVLR
  put<std::uint32_t>(&out, 0);  // EVLR count
  put<std::uint64_t>(&out, n);
  for (auto c : by_return) put<std::uint64_t>(&out, c);
  out += vlrs;
  out += points;
  return out;
}

void write_las(const PointCloud& cloud, const std::string& path) {
  common::write_file_atomic(path, serialize_las(cloud, common::display_name(path, true)));
}

}  // namespace canopy::formats
