#include "canopy/formats/pcd.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <type_traits>

#include "binary_io.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/provenance.h"
#include "lzf.h"

namespace canopy::formats {
namespace {

using common::DataError;
using detail::quote;

// Sane limits (formats/README.md): scalar columns per point (PCL's largest feature
// descriptors have a few hundred), header values.
constexpr std::uint64_t kMaxColumns = 4096;
constexpr std::uint64_t kMaxDimension = std::numeric_limits<std::int64_t>::max();

struct Header {
  std::vector<std::string> fields;
  std::vector<int> sizes;
  std::vector<char> kinds;
  std::vector<std::uint64_t> counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool have_width = false, have_points = false;
  std::string data;
  std::vector<std::string> comments;
  std::size_t data_offset = 0;
};

// Whitespace-separated tokens (space, tab, and any other byte <= ' ' such as NUL or \v).
std::vector<std::string> split_ws(const std::string& line) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && static_cast<unsigned char>(line[i]) <= ' ') ++i;
    const std::size_t s = i;
    while (i < line.size() && static_cast<unsigned char>(line[i]) > ' ') ++i;
    if (i > s) out.push_back(line.substr(s, i - s));
  }
  return out;
}

std::uint64_t to_count(const std::string& text, const std::string& name, const std::string& key,
                       std::uint64_t max = kMaxDimension) {
  std::uint64_t v = 0;
  if (!detail::parse_count(text, max, &v)) {
    throw DataError(
        name, "header " + key + " '" + quote(text) + "' is not an integer from 0 to " + std::to_string(max));
  }
  return v;
}

// Offset just past the DATA line, or npos when `bytes` holds no complete DATA line yet.
// *from: where to resume scanning (the start of the first incomplete line), so reading a long
// header in chunks stays linear.
std::size_t header_end(const std::string& bytes, std::size_t* from) {
  std::size_t pos = *from;
  while (pos < bytes.size()) {
    const std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) break;
    std::size_t s = pos;
    while (s < eol && (bytes[s] == ' ' || bytes[s] == '\t')) ++s;
    if (bytes.compare(s, 4, "DATA") == 0 && s + 4 < bytes.size() &&
        static_cast<unsigned char>(bytes[s + 4]) <= ' ') {
      return eol + 1;
    }
    pos = eol + 1;
  }
  *from = pos;
  return std::string::npos;
}

[[noreturn]] void not_pcd(const std::string& bytes, const std::string& name, const std::string& what) {
  const std::string is = detail::sniff(bytes);
  if (!is.empty() && is != "a PCD file") throw DataError(name, "this is " + is + ", not a PCD file");
  throw DataError(name, what + " (is this a PCD file?)");
}

// The values of one header line other than DATA (VERSION and VIEWPOINT are ignored).
void header_values(const std::string& key, const std::vector<std::string>& tok, Header& h, bool* have_count,
                   const std::string& name) {
  auto one = [&]() -> const std::string& {
    if (tok.size() != 1) throw DataError(name, "header " + key + " needs one value");
    return tok[0];
  };
  if (key == "VERSION" || key == "VIEWPOINT") {
  } else if (key == "FIELDS" || key == "COLUMNS") {
    if (tok.empty()) throw DataError(name, "header FIELDS lists no fields");
    if (tok.size() > kMaxColumns) {
      throw DataError(name, "header FIELDS lists " + std::to_string(tok.size()) + " fields (limit " +
                                std::to_string(kMaxColumns) + ")");
    }
    h.fields = tok;
  } else if (key == "SIZE") {
    for (auto& t : tok) h.sizes.push_back(static_cast<int>(to_count(t, name, "SIZE", 8)));
  } else if (key == "TYPE") {
    for (auto& t : tok) {
      if (t != "F" && t != "U" && t != "I") {
        throw DataError(name, "header TYPE '" + quote(t) + "' is not one of F, U, I");
      }
      h.kinds.push_back(t[0]);
    }
  } else if (key == "COUNT") {
    *have_count = true;
    for (auto& t : tok) {
      const auto c = to_count(t, name, "COUNT", kMaxColumns);
      if (c == 0) throw DataError(name, "header COUNT 0 (every field needs at least one value)");
      h.counts.push_back(c);
    }
  } else if (key == "WIDTH") {
    h.width = to_count(one(), name, "WIDTH");
    h.have_width = true;
  } else if (key == "HEIGHT") {
    h.height = to_count(one(), name, "HEIGHT");
  } else if (key == "POINTS") {
    h.points = to_count(one(), name, "POINTS");
    h.have_points = true;
  }
}

// The header's fields, counts and dimensions agree and are within the limits.
void check_header(Header& h, bool have_count, const std::string& name) {
  if (h.fields.empty()) throw DataError(name, "PCD header has no FIELDS line");
  if (!have_count) h.counts.assign(h.fields.size(), 1);
  if (h.sizes.size() != h.fields.size() || h.kinds.size() != h.fields.size() ||
      h.counts.size() != h.fields.size()) {
    throw DataError(name, "PCD header lists " + std::to_string(h.fields.size()) + " FIELDS but " +
                              std::to_string(h.sizes.size()) + " SIZE, " + std::to_string(h.kinds.size()) +
                              " TYPE and " + std::to_string(h.counts.size()) + " COUNT entries");
  }
  std::uint64_t columns = 0;
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    if (!detail::valid_type({h.kinds[i], h.sizes[i]})) {
      throw DataError(name, "field '" + quote(h.fields[i]) + "' has unsupported TYPE " + h.kinds[i] +
                                " SIZE " + std::to_string(h.sizes[i]));
    }
    columns += h.counts[i];
  }
  if (columns > kMaxColumns) {
    throw DataError(name, "header COUNT gives " + std::to_string(columns) + " values per point (limit " +
                              std::to_string(kMaxColumns) + ")");
  }
  if (!h.have_width) throw DataError(name, "PCD header has no WIDTH");
  std::uint64_t wh = 0;
  if (__builtin_mul_overflow(h.width, h.height, &wh) || wh > kMaxDimension) {
    throw DataError(name, "header WIDTH " + std::to_string(h.width) + " x HEIGHT " +
                              std::to_string(h.height) + " overflows");
  }
  if (!h.have_points) h.points = wh;
  if (h.points != wh) {
    throw DataError(
        name, "PCD header POINTS " + std::to_string(h.points) + " != WIDTH x HEIGHT " + std::to_string(wh));
  }
  if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed") {
    throw DataError(name,
                    "unknown DATA type '" + quote(h.data) + "' (want ascii, binary or binary_compressed)");
  }
}

Header parse_header(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw DataError(name, "empty file (not a PCD file)");
  Header h;
  std::size_t pos = 0;
  bool have_count = false;
  std::set<std::string> seen;
  while (true) {
    if (pos >= bytes.size()) not_pcd(bytes, name, "PCD header has no DATA line (truncated?)");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '#') {
      std::string c = line.substr(1);
      if (!c.empty() && c[0] == ' ') c.erase(0, 1);
      if (c.rfind(".PCD v", 0) != 0) h.comments.push_back(c);
      continue;
    }
    auto tok = split_ws(line);
    if (tok.empty()) continue;  // blank or whitespace-only line
    const std::string key = tok[0];
    tok.erase(tok.begin());
    static const char* const kKeys[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE",      "TYPE", "COUNT",
                                        "WIDTH",   "HEIGHT", "POINTS",  "VIEWPOINT", "DATA"};
    if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return key == k; }) ==
        std::end(kKeys)) {
      not_pcd(bytes, name, "unknown PCD header line '" + quote(line) + "'");
    }
    const std::string canon = key == "COLUMNS" ? "FIELDS" : key;
    if (!seen.insert(canon).second) throw DataError(name, "header line " + canon + " appears twice");
    if (key == "DATA") {
      if (tok.size() != 1) throw DataError(name, "header " + key + " needs one value");
      h.data = tok[0];
      h.data_offset = std::min(pos, bytes.size());
      break;
    }
    header_values(key, tok, h, &have_count, name);
  }
  check_header(h, have_count, name);
  return h;
}

// One entry per stored scalar of a point; column < 0 for padding fields ("_").
struct Slot {
  FieldType type;
  int column;
  std::size_t offset;  // byte offset in a binary row
};

struct Layout {
  std::vector<Slot> slots;
  std::size_t step = 0;  // bytes per point in binary data
};

Layout make_layout(const Header& h) {
  Layout l;
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    const FieldType t{h.kinds[f], h.sizes[f]};
    for (std::uint64_t k = 0; k < h.counts[f]; ++k) {
      l.slots.push_back({t, h.fields[f] == "_" ? -1 : 0, l.step});
      l.step += static_cast<std::size_t>(t.size);
    }
  }
  return l;
}

// The column name of every slot (empty for padding fields "_"): a COUNT > 1 field becomes
// name_0, name_1, ...; a name given twice, or only padding, is refused.
std::vector<std::string> column_names(const Header& h, const Layout& l, const std::string& name) {
  std::vector<std::string> out(l.slots.size());
  std::set<std::string> names;
  std::size_t s = 0;
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    for (std::uint64_t k = 0; k < h.counts[f]; ++k, ++s) {
      if (l.slots[s].column < 0) continue;
      const std::string col = h.counts[f] == 1 ? h.fields[f] : h.fields[f] + "_" + std::to_string(k);
      if (!names.insert(col).second) throw DataError(name, "duplicate field '" + quote(col) + "'");
      out[s] = col;
    }
  }
  if (names.empty()) throw DataError(name, "PCD header has only padding fields '_'");
  return out;
}

// Adds the columns (after the data size was checked against the header), empty with room
// for every point: decoding appends, so no page is written twice.
std::vector<std::vector<double>*> make_columns(const Header& h, Layout* l, PointCloud* cloud,
                                               const std::string& name) {
  const std::vector<std::string> names = column_names(h, *l, name);
  for (std::size_t s = 0; s < l->slots.size(); ++s) {
    if (l->slots[s].column < 0) continue;
    cloud->add(names[s], l->slots[s].type);
    l->slots[s].column = static_cast<int>(cloud->names().size()) - 1;
  }
  std::vector<std::vector<double>*> cols;
  for (std::size_t c = 0; c < cloud->names().size(); ++c) {
    cols.push_back(&cloud->col(c));
    cols.back()->reserve(static_cast<std::size_t>(h.points));
  }
  return cols;
}

std::string too_big(const std::string& what, std::uint64_t n, std::size_t per, std::size_t avail) {
  return "data truncated: header POINTS " + std::to_string(n) + " needs " + std::to_string(per) + " " + what +
         " per point, the file holds " + std::to_string(avail) +
         " bytes of data (truncated file or wrong POINTS)";
}

// Checks that `n` binary points of `step` bytes fit in `avail` bytes.
void check_binary_size(std::uint64_t n, std::size_t step, std::size_t avail, const std::string& name) {
  if (n > avail / step) throw DataError(name, too_big("bytes", n, step, avail));
}

// n values of T at src (little-endian), `stride` bytes apart, appended to dst.
template <typename T>
void gather(const unsigned char* src, std::size_t stride, std::size_t n, std::vector<T>* dst) {
  const std::size_t old = dst->size();
  dst->resize(old + n);
  T* out = dst->data() + old;
  for (std::size_t i = 0; i < n; ++i) std::memcpy(out + i, src + i * stride, sizeof(T));
}

// Binary (row-major) points appended to the cloud's columns, each kept packed at its width in
// the file (PointCloud: turned into doubles only when a tool asks for the column).
class RowPacker {
 public:
  // Only the columns `fields` wants are made (the others' bytes are skipped).
  RowPacker(const Header& h, const Layout& l, PointCloud* cloud, const std::string& name,
            const FieldSelection& fields = FieldSelection{})
      : step_(l.step) {
    const std::vector<std::string> names = column_names(h, l, name);
    const auto n = static_cast<std::size_t>(h.points);
    for (std::size_t s = 0; s < l.slots.size(); ++s) {
      if (l.slots[s].column < 0 || !fields.wants(names[s])) continue;
      const FieldType t = l.slots[s].type;
      const std::size_t off = l.slots[s].offset;
      detail::with_type(t, [&](auto tag) { add<decltype(tag)>(names[s], t, off, n, cloud); });
    }
  }
  // Appends `rows` points of the layout's step from src.
  void append(const unsigned char* src, std::size_t rows) const {
    for (const auto& sink : sinks_) sink(src, rows);
  }

 private:
  template <typename T>
  void add(const std::string& col, FieldType t, std::size_t off, std::size_t n, PointCloud* cloud) {
    std::vector<T>* v = &cloud->add_packed<T>(col, t);
    v->reserve(n);  // decoding appends: no page is written twice
    const std::size_t step = step_;
    sinks_.push_back(
        [v, off, step](const unsigned char* src, std::size_t rows) { gather(src + off, step, rows, v); });
  }
  std::size_t step_;
  std::vector<std::function<void(const unsigned char*, std::size_t)>> sinks_;
};

bool all_zero(const unsigned char* p, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (p[i] != 0) return false;
  }
  return true;
}

[[noreturn]] void trailing_data(std::uint64_t n, std::size_t step, const std::string& name) {
  throw DataError(name, "data longer than the header says: non-zero bytes after the " + std::to_string(n) +
                            " points of " + std::to_string(step) +
                            " bytes (wrong POINTS?; zero padding, as PCL writes, is accepted)");
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

void parse_ascii(const std::string& bytes, const Header& h, Layout& l, PointCloud* cloud,
                 const std::string& name) {
  const char* p = bytes.c_str() + h.data_offset;
  const char* end = bytes.c_str() + bytes.size();
  const std::size_t avail = static_cast<std::size_t>(end - p);
  // Every value takes at least two bytes ("0 ") but the last.
  const std::size_t per = l.slots.size();
  if (h.points > 0 && h.points > (avail + 1) / 2 / per)
    throw DataError(name, too_big("ascii values", h.points, per, avail));
  const auto cols = make_columns(h, &l, cloud, name);
  const std::size_t n = static_cast<std::size_t>(h.points);
  for (std::size_t i = 0; i < n; ++i) {
    for (const auto& s : l.slots) {
      while (p < end && is_space(*p)) ++p;
      if (p >= end) {
        throw DataError(name, "data truncated: header says " + std::to_string(n) +
                                  " points, ascii data ends in point " + std::to_string(i));
      }
      // strtod needs a terminator: bytes.c_str() has one at the end, and a value stops at the
      // first byte that cannot continue a number.
      char* q = nullptr;
      const double v = std::strtod(p, &q);
      if (q == p || (q < end && !is_space(*q))) {
        const char* e = p;
        while (e < end && !is_space(*e)) ++e;
        throw DataError(name, "point " + std::to_string(i) + ": '" +
                                  quote(p, static_cast<std::size_t>(e - p), 16) + "' is not a number");
      }
      p = q;
      // A float32 field holds the float nearest to the text, as in binary files.
      if (s.column >= 0)
        cols[static_cast<std::size_t>(s.column)]->push_back(s.type == kFloat32 ? static_cast<float>(v) : v);
    }
  }
  while (p < end && (is_space(*p) || *p == '\0')) ++p;
  if (p < end) throw DataError(name, "more ascii data than the header's " + std::to_string(n) + " points");
}

// LZF encodes at most 264 bytes in 3 (a long back-reference), so a block of c bytes decodes
// to fewer than 89 c bytes: a bound on the allocation before decoding.
constexpr std::uint64_t kLzfMaxRatio = 89;

// The decompressed (field-major) data of a binary_compressed body, checked against the header.
std::vector<unsigned char> decompress(const std::string& bytes, const Header& h, const Layout& l,
                                      const std::string& name) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data()) + h.data_offset;
  const std::size_t avail = bytes.size() - h.data_offset;
  if (avail < 8) throw DataError(name, "data truncated: binary_compressed block header missing");
  std::uint32_t csize, usize;
  std::memcpy(&csize, data, 4);
  std::memcpy(&usize, data + 4, 4);
  if (avail - 8 < csize) {
    throw DataError(name, "data truncated: compressed block of " + std::to_string(csize) +
                              " bytes, file holds " + std::to_string(avail - 8));
  }
  if (h.points > usize / l.step || h.points * l.step != usize) {
    throw DataError(name, "header POINTS " + std::to_string(h.points) + " x " + std::to_string(l.step) +
                              " bytes disagrees with the compressed block's size " + std::to_string(usize));
  }
  if (usize > kLzfMaxRatio * static_cast<std::uint64_t>(csize) + 1) {
    throw DataError(name, "data truncated: a compressed block of " + std::to_string(csize) +
                              " bytes cannot hold the header's POINTS " + std::to_string(h.points));
  }
  std::vector<unsigned char> raw(usize);
  if (usize > 0 && !detail::lzf_decompress(data + 8, csize, raw.data(), usize)) {
    throw DataError(name, "corrupt binary_compressed data (LZF decompression failed)");
  }
  return raw;
}

// n values of `type` at src (little-endian, contiguous) as a packed column (PointCloud: turned
// into doubles only when a tool asks for the column).
template <typename T>
void pack(const unsigned char* src, std::size_t n, const std::string& col, FieldType type, PointCloud* cloud) {
  std::vector<T>& v = cloud->add_packed<T>(col, type);
  v.resize(n);
  if (n > 0) std::memcpy(v.data(), src, n * sizeof(T));
}

// The field-major block of binary_compressed: every column is one contiguous run of values,
// kept packed at its width.
void gather_compressed(const std::vector<unsigned char>& raw, const Header& h, const Layout& l,
                       PointCloud* cloud, const std::string& name) {
  const std::vector<std::string> names = column_names(h, l, name);
  const std::size_t n = static_cast<std::size_t>(h.points);
  std::size_t off = 0;  // field-major: all values of slot 0, then slot 1, ...
  for (std::size_t s = 0; s < l.slots.size(); ++s) {
    const FieldType t = l.slots[s].type;
    const unsigned char* src = raw.data() + off;
    off += static_cast<std::size_t>(t.size) * n;
    if (l.slots[s].column < 0) continue;
    const std::string& col = names[s];
    detail::with_type(t, [&](auto tag) { pack<decltype(tag)>(src, n, col, t, cloud); });
  }
}

PointCloud parse_body(const std::string& bytes, const Header& h, const std::string& name) {
  PointCloud cloud;
  cloud.comments = h.comments;
  Layout l = make_layout(h);
  if (h.data == "ascii") {
    parse_ascii(bytes, h, l, &cloud, name);
  } else if (h.data == "binary") {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data()) + h.data_offset;
    const std::size_t avail = bytes.size() - h.data_offset;
    check_binary_size(h.points, l.step, avail, name);
    const std::size_t used = static_cast<std::size_t>(h.points) * l.step;
    if (!all_zero(data + used, avail - used)) trailing_data(h.points, l.step, name);
    RowPacker(h, l, &cloud, name).append(data, static_cast<std::size_t>(h.points));
  } else {
    gather_compressed(decompress(bytes, h, l, name), h, l, &cloud, name);
  }
  cloud.resize(static_cast<std::size_t>(h.points));  // sets the size; the columns are full
  check_coordinates(cloud, name);
  return cloud;
}

// Reads up to n bytes at the file's current position; fewer only at end of file.
std::size_t read_some(int fd, void* buf, std::size_t n, const std::string& name) {
  std::size_t got = 0;
  auto* p = static_cast<char*>(buf);
  while (got < n) {
    const ssize_t r = ::read(fd, p + got, n - got);
    if (r < 0) {
      if (errno == EINTR) continue;
      throw DataError(name, std::string("read error: ") + std::strerror(errno));
    }
    if (r == 0) break;
    got += static_cast<std::size_t>(r);
  }
  return got;
}

struct Fd {
  int fd;
  ~Fd() { ::close(fd); }
};

}  // namespace

PointCloud parse_pcd(const std::string& bytes, const std::string& name) {
  return parse_body(bytes, parse_header(bytes, name), name);
}

// Regular files are read in chunks: binary data is decoded as it arrives (no copy of the
// whole file in memory), other encodings are read whole and parsed like parse_pcd.
namespace {

constexpr std::size_t kHeadChunk = 1 << 16;

// The file's first bytes up to and including the DATA line (*end: its end, npos when the file
// has none), read in chunks of 64 KiB; may hold data bytes after it.
std::string read_head(int fd, const std::string& path, std::size_t* end) {
  std::string head;
  std::size_t scanned = 0;
  *end = std::string::npos;
  while (*end == std::string::npos) {
    const std::size_t old = head.size();
    head.resize(old + kHeadChunk);
    const std::size_t got = read_some(fd, &head[old], kHeadChunk, path);
    head.resize(old + got);
    *end = header_end(head, &scanned);
    if (got == 0) break;
  }
  return head;
}

// ascii and binary_compressed: the rest of the file is read whole, then parsed.
PointCloud read_unstreamed(int fd, std::string head, const Header& h, std::size_t file_size,
                           const std::string& path) {
  const std::size_t old = head.size();
  head.resize(std::max(old, file_size));
  head.resize(old + read_some(fd, &head[old], head.size() - old, path));
  while (true) {  // the file grew since fstat
    const std::size_t at = head.size();
    head.resize(at + kHeadChunk);
    head.resize(at + read_some(fd, &head[at], kHeadChunk, path));
    if (head.size() == at) break;
  }
  if (h.data == "ascii") return parse_body(head, h, path);
  // binary_compressed: the file's bytes are let go before the columns are made.
  PointCloud cloud;
  cloud.comments = h.comments;
  Layout l = make_layout(h);
  std::vector<unsigned char> raw = decompress(head, h, l, path);
  std::string().swap(head);
  gather_compressed(raw, h, l, &cloud, path);
  cloud.resize(static_cast<std::size_t>(h.points));
  check_coordinates(cloud, path);
  return cloud;
}

}  // namespace

PointCloud read_pcd(const std::string& path) { return read_pcd(path, FieldSelection{}); }

PointCloud read_pcd(const std::string& path, const FieldSelection& fields) {
  // The columns `fields` does not want, dropped after a whole read (checks as without them).
  auto keep = [&fields](PointCloud cloud) {
    if (!fields.all()) {
      const std::vector<std::string> names = cloud.names();
      for (const auto& n : names) {
        if (!fields.wants(n)) cloud.remove(n);
      }
    }
    return cloud;
  };
  if (path == "-") return keep(parse_pcd(common::read_file(path), path));
  const int raw_fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (raw_fd < 0) return keep(parse_pcd(common::read_file(path), path));  // read_file words the error
  Fd fd{raw_fd};
  struct stat st {};
  if (fstat(fd.fd, &st) != 0 || !S_ISREG(st.st_mode)) return keep(parse_pcd(common::read_file(path), path));
  const auto file_size = static_cast<std::size_t>(st.st_size);

  std::size_t end = std::string::npos;
  std::string head = read_head(fd.fd, path, &end);
  if (end == std::string::npos) return keep(parse_pcd(head, path));  // no DATA line: parse_header says why
  const Header h = parse_header(head.substr(0, end), path);
  if (h.data != "binary") return keep(read_unstreamed(fd.fd, std::move(head), h, file_size, path));
  // A selection without x, y or z: read whole (check_coordinates checks every coordinate
  // the file has, wanted or not).
  const FieldSelection streamed =
      fields.wants("x") && fields.wants("y") && fields.wants("z") ? fields : FieldSelection{};

  PointCloud cloud;
  cloud.comments = h.comments;
  Layout l = make_layout(h);
  const std::size_t avail = file_size - std::min(file_size, h.data_offset);
  check_binary_size(h.points, l.step, avail, path);
  const RowPacker rows_to(h, l, &cloud, path, streamed);
  const std::size_t n = static_cast<std::size_t>(h.points);
  // Chunks of whole rows (~1 MiB), starting with the data bytes already read with the header.
  const std::size_t chunk_rows = std::max<std::size_t>(1, (std::size_t{1} << 20) / l.step);
  std::vector<unsigned char> buf(chunk_rows * l.step);
  std::size_t head_pos = h.data_offset, have = 0, row = 0;
  bool eof = false;
  auto fill = [&] {
    const std::size_t take = std::min(head.size() - head_pos, buf.size() - have);
    std::memcpy(buf.data() + have, head.data() + head_pos, take);
    head_pos += take;
    have += take;
    if (have < buf.size() && !eof) {
      const std::size_t want = buf.size() - have;
      const std::size_t got = read_some(fd.fd, buf.data() + have, want, path);
      eof = got < want;
      have += got;
    }
  };
  while (row < n) {
    fill();
    const std::size_t rows = std::min(have / l.step, n - row);
    if (rows == 0) break;  // end of file inside a point
    rows_to.append(buf.data(), rows);
    row += rows;
    const std::size_t used = rows * l.step;
    std::memmove(buf.data(), buf.data() + used, have - used);
    have -= used;
  }
  if (row < n) {
    throw DataError(path, "data truncated: header says " + std::to_string(n) +
                              " points, the file ends in point " + std::to_string(row));
  }
  // Whatever follows the points must be zero padding (PCL's writer adds up to a page).
  while (true) {
    if (!all_zero(buf.data(), have)) trailing_data(h.points, l.step, path);
    if (eof && head_pos == head.size()) break;
    have = 0;
    fill();
    if (have == 0) break;
  }
  cloud.resize(n);  // sets the size; the columns are full
  check_coordinates(cloud, path);
  return keep(std::move(cloud));
}

namespace {

// k values as `type` (little-endian), `stride` bytes apart: write_scalar's conversions
// (detail::to_field).
void put_values(const double* v, std::size_t k, FieldType type, unsigned char* out, std::size_t stride) {
  detail::with_type(type, [&](auto tag) {
    using T = decltype(tag);
    for (std::size_t i = 0; i < k; ++i) {
      const T t = detail::to_field<T>(v[i]);
      std::memcpy(out + i * stride, &t, sizeof t);
    }
  });
}

// The points' bytes (size() x the fields' sizes) at out: row-major as DATA binary stores them,
// or field-major as binary_compressed's block holds them before compression.
void put_points(const PointCloud& cloud, bool field_major, unsigned char* out) {
  const auto& types = cloud.types();
  std::vector<std::size_t> offset(types.size());  // bytes before column c in a row
  std::size_t step = 0;
  for (std::size_t c = 0; c < types.size(); ++c) {
    offset[c] = step;
    step += static_cast<std::size_t>(types[c].size);
  }
  const std::size_t n = cloud.size();
  for_each_block(cloud, [&](std::size_t first, std::size_t k, const std::vector<const double*>& col) {
    for (std::size_t c = 0; c < types.size(); ++c) {
      const auto size = static_cast<std::size_t>(types[c].size);
      if (field_major)
        put_values(col[c], k, types[c], out + offset[c] * n + first * size, size);
      else
        put_values(col[c], k, types[c], out + first * step + offset[c], step);
    }
  });
}

}  // namespace

std::string serialize_pcd(const PointCloud& cloud) { return serialize_pcd(cloud, PcdWriteOptions{}); }

std::string serialize_pcd(const PointCloud& cloud, const PcdWriteOptions& options) {
  std::string out = "# .PCD v0.7 - Point Cloud Data file format\n";
  // A comment never ends its line early (a newline in an input path): header_safe_comment.
  for (const auto& c : cloud.comments) out += "# " + header_safe_comment(c) + "\n";
  std::string fields, sizes, types, counts;
  for (std::size_t i = 0; i < cloud.names().size(); ++i) {
    const auto t = cloud.types()[i];
    fields += " " + cloud.names()[i];
    sizes += " " + std::to_string(t.size);
    types += std::string(" ") + t.kind;
    counts += " 1";
  }
  const char* data = options.encoding == PcdEncoding::ascii               ? "ascii"
                     : options.encoding == PcdEncoding::binary_compressed ? "binary_compressed"
                                                                          : "binary";
  const std::string n = std::to_string(cloud.size());
  out += "VERSION 0.7\nFIELDS" + fields + "\nSIZE" + sizes + "\nTYPE" + types + "\nCOUNT" + counts +
         "\nWIDTH " + n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA " + data + "\n";
  std::size_t step = 0;
  for (const auto& t : cloud.types()) step += static_cast<std::size_t>(t.size);
  const std::size_t nc = cloud.names().size();
  switch (options.encoding) {
    case PcdEncoding::binary: {
      // Into the buffer in place, block by block (packed columns are not unpacked).
      const std::size_t head = out.size();
      out.resize(head + step * cloud.size());
      put_points(cloud, false, reinterpret_cast<unsigned char*>(&out[head]));
      break;
    }
    case PcdEncoding::ascii:
      for_each_block(cloud, [&](std::size_t, std::size_t k, const std::vector<const double*>& col) {
        for (std::size_t i = 0; i < k; ++i) {
          for (std::size_t c = 0; c < nc; ++c) {
            out += detail::format_value(col[c][i], cloud.types()[c]);
            out += c + 1 < nc ? " " : "\n";
          }
        }
      });
      break;
    case PcdEncoding::binary_compressed: {
      // PCL's layout: uint32 compressed size, uint32 raw size, LZF block of the field-major data.
      const std::size_t raw_size = step * cloud.size();
      if (raw_size > std::numeric_limits<std::uint32_t>::max()) {
        throw common::Error("binary_compressed PCD holds at most 4 GiB of data (" + std::to_string(raw_size) +
                            " bytes); write DATA binary");
      }
      std::unique_ptr<unsigned char[]> raw(new unsigned char[std::max<std::size_t>(raw_size, 1)]);
      put_points(cloud, true, raw.get());
      const std::size_t head = out.size();
      out.resize(head + 8 + detail::lzf_bound(raw_size));
      auto* block = reinterpret_cast<unsigned char*>(&out[head]);
      const auto csize = static_cast<std::uint32_t>(detail::lzf_compress(raw.get(), raw_size, block + 8));
      const auto usize = static_cast<std::uint32_t>(raw_size);
      std::memcpy(block, &csize, 4);
      std::memcpy(block + 4, &usize, 4);
      out.resize(head + 8 + csize);
      break;
    }
  }
  return out;
}

void write_pcd(const PointCloud& cloud, const std::string& path) {
  write_pcd(cloud, path, PcdWriteOptions{});
}

void write_pcd(const PointCloud& cloud, const std::string& path, const PcdWriteOptions& options) {
  check_coordinates(cloud, path == "-" ? "<stdout>" : path);
  common::write_file_atomic(path, serialize_pcd(cloud, options));
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

}  // namespace canopy::formats
