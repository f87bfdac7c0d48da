// Small helpers of the LAS and LAZ tests: the test data's path, a whole file as bytes, and
// little-endian fields read from / written into those bytes.
#pragma once

#include <cstddef>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace canopy::las_test
