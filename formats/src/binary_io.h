// Typed little/big-endian scalar access shared by the PCD and PLY codecs. Private to formats/.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats::detail {

template <typename T>
void put(std::string* out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out->append(b, sizeof(T));
}

// Integer conversion: round to nearest and clamp to the type's range (NaN -> 0).
template <typename T>
T to_int(double v, double lo, double hi) {
  if (std::isnan(v)) return 0;
  v = std::nearbyint(v);
  if (v < lo) v = lo;
  if (v > hi) v = hi;
  return static_cast<T>(v);
}

// Calls f(T{}) with T the C++ type of a field type (float, double, the integers; a size
// other than 1 or 2 is the 4-byte integer, a float of size other than 4 the double).
template <typename F>
void with_type(FieldType t, F f) {
  switch (t.kind) {
    case 'F':
      if (t.size == 4) return f(float{});
      return f(double{});
    case 'U':
      if (t.size == 1) return f(std::uint8_t{});
      if (t.size == 2) return f(std::uint16_t{});
      return f(std::uint32_t{});
    default:
      if (t.size == 1) return f(std::int8_t{});
      if (t.size == 2) return f(std::int16_t{});
      return f(std::int32_t{});
  }
}

// Reads one scalar of `type` at `p`; `swap` reverses byte order (big-endian files).
inline double read_scalar(const unsigned char* p, FieldType type, bool swap = false) {
  unsigned char b[8] = {};
  std::memcpy(b, p, static_cast<std::size_t>(type.size));
  if (swap) {
    for (int i = 0; i < type.size / 2; ++i) std::swap(b[i], b[type.size - 1 - i]);
  }
  double out = 0;
  with_type(type, [&](auto tag) {
    decltype(tag) v;
    std::memcpy(&v, b, sizeof v);
    out = static_cast<double>(v);
  });
  return out;
}

// v as a T: a float field rounds to float, an integer field rounds to nearest and clamps to
// the type's range (to_int).
template <typename T>
T to_field(double v) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(v);
  } else {
    return to_int<T>(v, static_cast<double>(std::numeric_limits<T>::min()),
                     static_cast<double>(std::numeric_limits<T>::max()));
  }
}

// Appends `v` as `type`, little-endian.
inline void write_scalar(std::string* out, double v, FieldType type) {
  with_type(type, [&](auto tag) { put(out, to_field<decltype(tag)>(v)); });
}

// Shortest decimal text that reads back to the same value at the type's precision.
std::string format_value(double v, FieldType type);

// File text made safe for a message: printable ASCII kept, every other byte (NUL, control,
// non-ASCII) shown as \xNN, cut to `max` bytes with "..." so a message is never cut at a NUL
// and never holds megabytes of a binary file.
inline std::string quote(const char* p, std::size_t n, std::size_t max = 40) {
  std::string out;
  const std::size_t m = n < max ? n : max;
  for (std::size_t i = 0; i < m; ++i) {
    const auto c = static_cast<unsigned char>(p[i]);
    if (c >= 0x20 && c < 0x7f) {
      out.push_back(static_cast<char>(c));
    } else {
      static const char kHex[] = "0123456789abcdef";
      out += "\\x";
      out.push_back(kHex[c >> 4]);
      out.push_back(kHex[c & 15]);
    }
  }
  if (m < n) out += "...";
  return out;
}
inline std::string quote(const std::string& s, std::size_t max = 40) {
  return quote(s.data(), s.size(), max);
}

// Parses a whole token as a non-negative decimal integer (no sign, no exponent, no spaces).
// Returns false on anything else or a value above `max`.
inline bool parse_count(const std::string& text, std::uint64_t max, std::uint64_t* out) {
  if (text.empty() || text.size() > 20) return false;
  std::uint64_t v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    const auto d = static_cast<std::uint64_t>(c - '0');
    if (v > (max - d) / 10) return false;
    v = v * 10 + d;
  }
  *out = v;
  return true;
}

// What a file looks like from its first bytes, for "this is a ... file" messages: "a PLY
// file", "a PCD file", "a LAS file", "a JSON document", ...; "" when not recognised.
inline std::string sniff(const std::string& bytes) {
  auto starts = [&](const char* m) { return bytes.compare(0, std::strlen(m), m) == 0; };
  if (starts("ply\n") || starts("ply\r\n")) return "a PLY file";
  if (starts("LASF")) return "a LAS file";
  if (starts("# .PCD") || starts("VERSION 0.") || starts("FIELDS ")) return "a PCD file";
  if (starts("\x89PNG")) return "a PNG image";
  if (starts("\x1f\x8b")) return "a gzip-compressed file";
  if (starts("PK\x03\x04")) return "a zip archive";
  if (starts("solid ")) return "an STL file";
  std::size_t i = 0;
  while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\n' || bytes[i] == '\r' || bytes[i] == '\t'))
    ++i;
  if (i < bytes.size() && bytes[i] == '{') return "a JSON document";
  if (starts("v ") || starts("# OBJ") || starts("mtllib ")) return "an OBJ file";
  return "";
}

inline bool valid_type(FieldType t) {
  if (t.kind == 'F') return t.size == 4 || t.size == 8;
  if (t.kind == 'U' || t.kind == 'I') return t.size == 1 || t.size == 2 || t.size == 4;
  return false;
}

}  // namespace canopy::formats::detail
