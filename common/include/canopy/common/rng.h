// Seeded, platform-independent random numbers. Same seed -> same sequence on every
// compiler and standard library (std::*_distribution are implementation-defined, so
// the distributions are implemented here).
#pragma once

#include <cstdint>
#include <string>

namespace canopy::common {

class Rng {
 public:
  explicit Rng(std::uint64_t seed);
  std::uint64_t next_u64();              // xoshiro256** step
  double uniform();                      // [0, 1)
  double uniform(double lo, double hi);  // [lo, hi)
  double normal();                       // N(0, 1), Marsaglia polar method
  std::uint64_t below(std::uint64_t n);  // uniform integer in [0, n), n > 0

 private:
  std::uint64_t s_[4];
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// The splitmix64 finaliser: a bijective 64-bit mix of z + golden ratio (Steele, Lea, Flood
// 2014). Stateless, so draws keyed by (seed, i, j) are the same in any order or thread count.
std::uint64_t mix64(std::uint64_t z);

// Stable 64-bit seed derived from a base seed and a text key (FNV-1a + splitmix64),
// e.g. derive_seed(7, "foliage") or derive_seed(0, "sedan/circle/noise-8").
std::uint64_t derive_seed(std::uint64_t base, const std::string& key);

}  // namespace canopy::common
