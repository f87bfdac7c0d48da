// Typed little/big-endian scalar access shared by the PCD and PLY codecs. Private to formats/.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats::detail {

// Reads one scalar of `type` at `p`; `swap` reverses byte order (big-endian files).
inline double read_scalar(const unsigned char* p, FieldType type, bool swap = false) {
  unsigned char b[8];
  std::memcpy(b, p, static_cast<std::size_t>(type.size));
  if (swap) {
    for (int i = 0; i < type.size / 2; ++i) std::swap(b[i], b[type.size - 1 - i]);
  }
  switch (type.kind) {
    case 'F':
      if (type.size == 4) { float f; std::memcpy(&f, b, 4); return f; }
      { double d; std::memcpy(&d, b, 8); return d; }
    case 'U':
      if (type.size == 1) return b[0];
      if (type.size == 2) { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
    default:
      if (type.size == 1) { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      if (type.size == 2) { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      { std::int32_t v; std::memcpy(&v, b, 4); return v; }
  }
}

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

// Appends `v` as `type`, little-endian.
inline void write_scalar(std::string* out, double v, FieldType type) {
  switch (type.kind) {
    case 'F':
      if (type.size == 4) put(out, static_cast<float>(v));
      else put(out, v);
      return;
    case 'U':
      if (type.size == 1) put(out, to_int<std::uint8_t>(v, 0, 255));
      else if (type.size == 2) put(out, to_int<std::uint16_t>(v, 0, 65535));
      else put(out, to_int<std::uint32_t>(v, 0, 4294967295.0));
      return;
    default:
      if (type.size == 1) put(out, to_int<std::int8_t>(v, -128, 127));
      else if (type.size == 2) put(out, to_int<std::int16_t>(v, -32768, 32767));
      else put(out, to_int<std::int32_t>(v, -2147483648.0, 2147483647.0));
      return;
  }
}

// Shortest decimal text that reads back to the same value at the type's precision.
std::string format_value(double v, FieldType type);

inline bool valid_type(FieldType t) {
  if (t.kind == 'F') return t.size == 4 || t.size == 8;
  if (t.kind == 'U' || t.kind == 'I') return t.size == 1 || t.size == 2 || t.size == 4;
  return false;
}

}  // namespace canopy::formats::detail
