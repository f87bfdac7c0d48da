// LAZ entropy decoding, private to formats/: the adaptive range (arithmetic) decoder LASzip
// uses, its bit and multi-symbol models, LASzip's integer corrector decoder and the streaming
// median of five it predicts coordinate steps with.
//
// Written from the published descriptions, not from LASzip's code:
//  - A. Said, "Introduction to Arithmetic Coding - Theory and Practice", HP Labs report
//    HPL-2004-76 (2004), and "Arithmetic coding", ch. 5 of K. Sayood (ed.), Lossless
//    Compression Handbook, Academic Press 2003: the 32-bit range coder with 2^24 minimum range,
//    byte-wise renormalisation, adaptive models updated periodically (counts halved past a
//    limit, update period growing by 5/4 up to a cap) and table-assisted symbol search.
//  - M. Isenburg, "LASzip: lossless compression of LiDAR data", Photogrammetric Engineering &
//    Remote Sensing 79(2), 2013, and the LASzip specification (laszip.org, "LASzip
//    compressed LAS" with the item/version tables): model sizes (bit models with 13-bit
//    probabilities and count limit 2^13, symbol models with 15-bit distributions and count
//    limit 2^15), the integer compressor (corrector magnitude class k coded per context, then
//    the corrector bits: k <= 8 with one model per k, larger k as 8 modelled high bits plus
//    raw low bits) and the median-of-five predictor.
// The exact update arithmetic was checked against files written by LASzip and laz-perf (the
// tests compare every decoded record with an independent decoder's output).
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace canopy::formats::laz {

// Compressed data that cannot be valid (a raw value out of range, a run past the data).
// laz.cpp turns it into a DataError naming the file and the chunk.
class Corrupt : public std::runtime_error {
 public:
  explicit Corrupt(const std::string& what) : std::runtime_error(what) {}
};

constexpr std::uint32_t kRangeMin = 1u << 24;  // renormalise below this range
constexpr std::uint32_t kBitShift = 13;        // bit models: probability bits
constexpr std::uint32_t kBitLimit = 1u << 13;  // bit models: count limit
constexpr std::uint32_t kSymShift = 15;        // symbol models: distribution bits
constexpr std::uint32_t kSymLimit = 1u << 15;  // symbol models: count limit

// Adaptive binary model: probability of a 0 in 1/2^13.
struct BitModel {
  std::uint32_t zeros = 1, total = 2, p0 = 1u << (kBitShift - 1), period = 4, left = 4;

  void adapt() {
    total += period;
    if (total > kBitLimit) {
      total = (total + 1) >> 1;
      zeros = (zeros + 1) >> 1;
      if (zeros == total) ++total;
    }
    p0 = (zeros * (0x80000000u / total)) >> (31 - kBitShift);
    period = (5 * period) >> 2;
    if (period > 64) period = 64;
    left = period;
  }
};

// Adaptive model over `n` symbols (2..2048): cumulative distribution in 1/2^15, and for more
// than 16 symbols a lookup table from the top bits of a scaled value to the first candidate.
class SymbolModel {
 public:
  explicit SymbolModel(std::uint32_t n) : n_(n) {
    if (n > 16) {
      // About four table entries per symbol, at most 2^10 (FastAC uses one half to one): the
      // search after the lookup rarely takes a step. Any resolution finds the same symbol.
      std::uint32_t bits = 5;
      while ((1u << bits) < 4 * n && bits < 10) ++bits;
      table_size_ = 1u << bits;
      table_shift_ = kSymShift - bits;
    }
    // Small models: the distribution padded to 16 entries of 2^15 for a branchless search.
    const std::uint32_t cdf_size = n > 16 ? n : 16;
    mem_.reset(new std::uint32_t[cdf_size + n + (table_size_ ? table_size_ + 2 : 0)]);
    cdf_ = mem_.get();
    for (std::uint32_t k = n; k < cdf_size; ++k) cdf_[k] = 1u << kSymShift;
    count_ = cdf_ + cdf_size;
    table_ = table_size_ ? count_ + n : nullptr;
    for (std::uint32_t k = 0; k < n; ++k) count_[k] = 1;
    period_ = n;
    adapt();
    period_ = left_ = (n + 6) >> 1;
  }

  void adapt() {
    total_ += period_;
    if (total_ > kSymLimit) {
      total_ = 0;
      for (std::uint32_t k = 0; k < n_; ++k) total_ += (count_[k] = (count_[k] + 1) >> 1);
    }
    const std::uint32_t scale = 0x80000000u / total_;
    std::uint32_t sum = 0;
    if (table_ == nullptr) {
      for (std::uint32_t k = 0; k < n_; ++k) {
        cdf_[k] = (scale * sum) >> (31 - kSymShift);
        sum += count_[k];
      }
    } else {
      std::uint32_t s = 0;
      for (std::uint32_t k = 0; k < n_; ++k) {
        cdf_[k] = (scale * sum) >> (31 - kSymShift);
        sum += count_[k];
        const std::uint32_t w = cdf_[k] >> table_shift_;
        while (s < w) table_[++s] = k - 1;
      }
      table_[0] = 0;
      while (s <= table_size_) table_[++s] = n_ - 1;
    }
    period_ = (5 * period_) >> 2;
    const std::uint32_t cap = (n_ + 6) << 3;
    if (period_ > cap) period_ = cap;
    left_ = period_;
  }

  std::uint32_t n_;
  std::uint32_t total_ = 0, period_ = 0, left_ = 0;
  std::uint32_t table_size_ = 0, table_shift_ = 0;
  std::unique_ptr<std::uint32_t[]> mem_;
  std::uint32_t *cdf_ = nullptr, *count_ = nullptr, *table_ = nullptr;
};

// A symbol model created on first use (LASzip creates many context models lazily; a fresh
// model is the same whenever it is created).
inline SymbolModel& lazy(std::unique_ptr<SymbolModel>& slot, std::uint32_t n) {
  if (!slot) slot = std::make_unique<SymbolModel>(n);
  return *slot;
}

// The range decoder over one span of compressed bytes. Reading past the span yields zero
// bytes and sets *overrun (checked by the caller after each point): valid streams end with
// enough padding that the decoder never reads past them.
class RangeDecoder {
 public:
  void start(const std::uint8_t* begin, const std::uint8_t* end, bool* overrun) {
    p_ = begin;
    end_ = end;
    overrun_ = overrun;
    length_ = 0xFFFFFFFFu;
    value_ = 0;
    for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | next();
  }

  std::uint32_t bit(BitModel& m) {
    const std::uint32_t x = m.p0 * (length_ >> kBitShift);
    std::uint32_t sym;
    if (value_ < x) {
      length_ = x;
      ++m.zeros;
      sym = 0;
    } else {
      value_ -= x;
      length_ -= x;
      sym = 1;
    }
    if (length_ < kRangeMin) renormalise();
    if (--m.left == 0) m.adapt();
    return sym;
  }

  std::uint32_t symbol(SymbolModel& m) {
    std::uint32_t sym, x, y = length_;
    length_ >>= kSymShift;
    if (m.table_ != nullptr) {
      const std::uint32_t dv = value_ / length_;
      std::uint32_t t = dv >> m.table_shift_;
      if (t > m.table_size_) t = m.table_size_;  // only a corrupt stream gets here
      sym = m.table_[t];
      std::uint32_t hi = m.table_[t + 1] + 1;
      while (hi > sym + 1) {
        const std::uint32_t k = (sym + hi) >> 1;
        if (m.cdf_[k] > dv) {
          hi = k;
        } else {
          sym = k;
        }
      }
      x = m.cdf_[sym] * length_;
      if (sym != m.n_ - 1) y = m.cdf_[sym + 1] * length_;
    } else {
      // At most 16 symbols: the last k with cdf[k] * length <= value, counted without branches
      // (cdf strictly increases, so the count is that k; the padding counts only where the
      // last symbol is the answer anyway).
      sym = 0;
      for (std::uint32_t k = 1; k < 16; ++k) sym += (length_ * m.cdf_[k] <= value_) ? 1u : 0u;
      if (sym > m.n_ - 1) sym = m.n_ - 1;
      x = length_ * m.cdf_[sym];
      if (sym != m.n_ - 1) y = length_ * m.cdf_[sym + 1];
    }
    value_ -= x;
    length_ = y - x;
    if (length_ < kRangeMin) renormalise();
    ++m.count_[sym];
    if (--m.left_ == 0) m.adapt();
    return sym;
  }

  // `bits` (1..32) equiprobable bits; more than 19 are read as 16 low bits, then the rest.
  std::uint32_t raw(std::uint32_t bits) {
    if (bits > 19) {
      const std::uint32_t low = raw(16);
      return (raw(bits - 16) << 16) | low;
    }
    length_ >>= bits;
    const std::uint32_t sym = value_ / length_;
    value_ -= length_ * sym;
    if (length_ < kRangeMin) renormalise();
    if (sym >> bits) throw Corrupt("raw value out of range");
    return sym;
  }

  // 32 raw bits: the low 16, then the high 16.
  std::uint32_t raw32() {
    const std::uint32_t low = raw(16);
    return (raw(16) << 16) | low;
  }

 private:
  std::uint8_t next() {
    if (p_ < end_) return *p_++;
    *overrun_ = true;
    return 0;
  }
  void renormalise() {
    do { value_ = (value_ << 8) | next(); } while ((length_ <<= 8) < kRangeMin);
  }

  const std::uint8_t* p_ = nullptr;
  const std::uint8_t* end_ = nullptr;
  bool* overrun_ = nullptr;
  std::uint32_t value_ = 0, length_ = 0;
};

// LASzip's integer decoder: value = prediction + corrector, the corrector coded as its
// magnitude class k (one model per context) and its position within the class. `bits` is the
// value width (16 or 32): results wrap into it.
class IntegerDecoder {
 public:
  IntegerDecoder(std::uint32_t bits, std::uint32_t contexts) {
    if (bits > 0 && bits < 32) {
      corr_bits_ = bits;
      mask_ = (1u << bits) - 1;
      corr_min_ = -static_cast<std::int32_t>(1u << (bits - 1));
    } else {
      corr_bits_ = 32;
      mask_ = 0xFFFFFFFFu;
      corr_min_ = INT32_MIN;
    }
    k_models_.reserve(contexts);
    for (std::uint32_t c = 0; c < contexts; ++c) k_models_.emplace_back(corr_bits_ + 1);
  }

  std::int32_t decode(RangeDecoder& d, std::int32_t pred, std::uint32_t context) {
    const std::uint32_t k = k_ = d.symbol(k_models_[context]);
    std::uint32_t c;  // two's complement corrector
    if (k == 0) {
      c = d.bit(corr0_);
    } else if (k < 32) {
      std::uint32_t v;
      if (k <= kHighBits) {
        v = d.symbol(lazy(corr_[k], 1u << k));
      } else {
        const std::uint32_t low_bits = k - kHighBits;
        v = d.symbol(lazy(corr_[k], 1u << kHighBits));
        v = (v << low_bits) | d.raw(low_bits);
      }
      // Class k holds [-(2^k - 1), -2^(k-1)] and [2^(k-1) + 1, 2^k].
      const std::uint32_t negative = 0u - static_cast<std::uint32_t>(v < (1u << (k - 1)));
      c = v + 1 - (negative & (1u << k));
    } else {
      c = static_cast<std::uint32_t>(corr_min_);
    }
    // LASzip folds a 16-bit result into [0, 2^16) by adding or subtracting 2^16 once; callers
    // keep the low 16 bits, which the mask gives for every corrector.
    return static_cast<std::int32_t>((static_cast<std::uint32_t>(pred) + c) & mask_);
  }

  // Magnitude class of the last corrector (a context for the next coordinate).
  std::uint32_t k() const { return k_; }

 private:
  static constexpr std::uint32_t kHighBits = 8;
  std::uint32_t corr_bits_ = 0, mask_ = 0, k_ = 0;
  std::int32_t corr_min_ = 0;
  std::vector<SymbolModel> k_models_;
  BitModel corr0_;
  std::unique_ptr<SymbolModel> corr_[33];
};

// LASzip's running median of the last coordinate steps: five sorted values; each new value
// evicts the largest or the smallest, alternating by which side of the median values arrive.
class Median5 {
 public:
  std::int32_t get() const { return v_[2]; }
  void add(std::int32_t x) {
    const std::int32_t median = v_[2];
    if (high_) {
      int i = 4;  // the largest goes
      while (i > 0 && x < v_[i - 1]) {
        v_[i] = v_[i - 1];
        --i;
      }
      v_[i] = x;
      high_ = x < median;
    } else {
      int i = 0;  // the smallest goes
      while (i < 4 && v_[i + 1] < x) {
        v_[i] = v_[i + 1];
        ++i;
      }
      v_[i] = x;
      high_ = !(median < x);
    }
  }

 private:
  std::int32_t v_[5] = {0, 0, 0, 0, 0};
  bool high_ = true;
};

inline std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

}  // namespace canopy::formats::laz
