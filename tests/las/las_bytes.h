// Small helpers of the LAS and LAZ tests: the test data's path, a whole file as bytes, and
// little-endian fields read from / written into those bytes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <utility>

namespace canopy::las_test {

inline std::string data(const std::string& file) {
  return std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/" + file;
}

// The real tiles committed once for the experiment and the tests (share/real/, its README).
inline std::string real(const std::string& file) {
  return std::string(CANOPY_SOURCE_DIR) + "/share/real/" + file;
}

inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

template <typename T>
T get(const std::string& b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

template <typename T>
void set(std::string* b, std::size_t at, T v) {
  std::memcpy(&(*b)[at], &v, sizeof v);
}

// `las` (a LAS file's bytes, no EVLRs) with one more VLR at the end of its VLRs: the VLR count
// and the point data offset moved on, the points unchanged.
inline std::string with_vlr(std::string las, const std::string& user_id, std::uint16_t record_id,
                            const std::string& payload) {
  const auto offset = get<std::uint32_t>(las, 96);
  std::string v(54, '\0');
  std::memcpy(&v[2], user_id.data(), std::min<std::size_t>(user_id.size(), 16));
  set<std::uint16_t>(&v, 18, record_id);
  set<std::uint16_t>(&v, 20, static_cast<std::uint16_t>(payload.size()));
  las.insert(offset, v + payload);
  set<std::uint32_t>(&las, 96, static_cast<std::uint32_t>(offset + v.size() + payload.size()));
  set<std::uint32_t>(&las, 100, get<std::uint32_t>(las, 100) + 1);
  return las;
}

// `las` (a LAS 1.4 file's bytes, LAS or LAZ, whose EVLRs, if any, end the file) with one more
// EVLR (LAS 1.4 R15 §2.6: a 60-byte header, a 64-bit length) at its end: the EVLR count moved
// on, the first EVLR's offset set when it had none. `length`: the length the header says, when
// not the payload's (a lying one).
inline std::string with_evlr(std::string las, const std::string& user_id, std::uint16_t record_id,
                             const std::string& payload, std::uint64_t length = ~std::uint64_t(0)) {
  const auto count = get<std::uint32_t>(las, 243);
  if (count == 0) set<std::uint64_t>(&las, 235, las.size());
  set<std::uint32_t>(&las, 243, count + 1);
  std::string v(60, '\0');
  std::memcpy(&v[2], user_id.data(), std::min<std::size_t>(user_id.size(), 16));
  set<std::uint16_t>(&v, 18, record_id);
  set<std::uint64_t>(&v, 20, length == ~std::uint64_t(0) ? payload.size() : length);
  return las + v + payload;
}

// A GeoTIFF GeoKeyDirectoryTag payload: header 1, 1, 0, key count, then the keys, each
// {key id, location 0, count 1, value}.
inline std::string geokeys(std::initializer_list<std::pair<std::uint16_t, std::uint16_t>> keys) {
  std::string out;
  auto put = [&](std::uint16_t v) { out.append(reinterpret_cast<const char*>(&v), 2); };
  put(1);
  put(1);
  put(0);
  put(static_cast<std::uint16_t>(keys.size()));
  for (const auto& [id, value] : keys) {
    put(id);
    put(0);
    put(1);
    put(value);
  }
  return out;
}

}  // namespace canopy::las_test
