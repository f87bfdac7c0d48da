// LASzip point-wise items, version 2 (LAS point formats 0-5): one range decoder for the whole
// chunk; the first record of a chunk is stored raw, every later one is predicted from the
// one before. Field models as described in the LASzip specification and Isenburg (2013), see
// laz_coder.h.
#include <cstring>

#include "laz_coder.h"
#include "laz_items.h"

namespace canopy::formats::laz {
namespace {

// Context of a point's (number of returns n, return number r), both 0..7: each valid pair with
// n <= 5 has its own (0..14), the others share; invalid pairs map to the upper contexts.
constexpr std::uint8_t kReturnMap[8][8] = {{15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},
                                           {13, 1, 2, 4, 7, 11, 11, 10},    {12, 3, 4, 5, 8, 12, 12, 11},
                                           {11, 6, 7, 8, 9, 13, 13, 12},    {10, 10, 11, 12, 13, 14, 14, 13},
                                           {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};

// Penetration level |n - r| of a return: the z context.
inline std::uint32_t return_level(std::uint32_t n, std::uint32_t r) { return n > r ? n - r : r - n; }

// Even part of a k (the magnitude class of the last corrector), capped: the next coordinate's
// context.
inline std::uint32_t k_context(std::uint32_t k, std::uint32_t cap) { return k < cap ? (k & ~1u) : cap; }

class PointItem {
 public:
  virtual ~PointItem() = default;
  virtual void decode(RangeDecoder& d, std::uint8_t* out) = 0;
};

// POINT10: x y z intensity, return bits, classification, scan angle, user data, source id
// (the 20 bytes of point format 0).
class Point10 final : public PointItem {
 public:
  explicit Point10(const std::uint8_t* first) {
    std::memcpy(last_, first, 20);
    last_[12] = last_[13] = 0;  // intensity is predicted per return context, from 0
    std::memcpy(&x_, last_, 4);
    std::memcpy(&y_, last_ + 4, 4);
    std::memcpy(&z_, last_ + 8, 4);
  }

  void decode(RangeDecoder& d, std::uint8_t* out) override {
    const std::uint32_t changed = d.symbol(changed_);
    if (changed & 32) last_[14] = static_cast<std::uint8_t>(d.symbol(lazy(bit_byte_[last_[14]], 256)));
    const std::uint32_t r = last_[14] & 7, n = (last_[14] >> 3) & 7;
    const std::uint32_t m = kReturnMap[n][r], l = return_level(n, r);
    if (changed != 0) {
      std::uint16_t intensity = last_intensity_[m];
      if (changed & 16) {
        intensity = static_cast<std::uint16_t>(intensity_.decode(d, intensity, m < 3 ? m : 3));
        last_intensity_[m] = intensity;
      }
      std::memcpy(last_ + 12, &intensity, 2);
      if (changed & 8) last_[15] = static_cast<std::uint8_t>(d.symbol(lazy(classification_[last_[15]], 256)));
      if (changed & 4) {
        const std::uint32_t step = d.symbol(scan_angle_[(last_[14] >> 6) & 1]);
        last_[16] = static_cast<std::uint8_t>(step + last_[16]);
      }
      if (changed & 2) last_[17] = static_cast<std::uint8_t>(d.symbol(lazy(user_data_[last_[17]], 256)));
      if (changed & 1) {
        std::uint16_t source;
        std::memcpy(&source, last_ + 18, 2);
        source = static_cast<std::uint16_t>(source_.decode(d, source, 0));
        std::memcpy(last_ + 18, &source, 2);
      }
    }
    const std::int32_t dx = dx_.decode(d, x_median_[m].get(), n == 1);
    x_ = static_cast<std::int32_t>(static_cast<std::uint32_t>(x_) + static_cast<std::uint32_t>(dx));
    x_median_[m].add(dx);
    const std::int32_t dy = dy_.decode(d, y_median_[m].get(), (n == 1) + k_context(dx_.k(), 20));
    y_ = static_cast<std::int32_t>(static_cast<std::uint32_t>(y_) + static_cast<std::uint32_t>(dy));
    y_median_[m].add(dy);
    const std::uint32_t kz = (dx_.k() + dy_.k()) / 2;
    z_ = z_coder_.decode(d, last_z_[l], (n == 1) + k_context(kz, 18));
    last_z_[l] = z_;
    std::memcpy(last_, &x_, 4);
    std::memcpy(last_ + 4, &y_, 4);
    std::memcpy(last_ + 8, &z_, 4);
    std::memcpy(out, last_, 20);
  }

 private:
  std::uint8_t last_[20];
  std::int32_t x_ = 0, y_ = 0, z_ = 0;
  std::uint16_t last_intensity_[16] = {};
  Median5 x_median_[16], y_median_[16];
  std::int32_t last_z_[8] = {};
  SymbolModel changed_{64};
  IntegerDecoder intensity_{16, 4};
  SymbolModel scan_angle_[2] = {SymbolModel(256), SymbolModel(256)};
  IntegerDecoder source_{16, 1};
  std::unique_ptr<SymbolModel> bit_byte_[256], classification_[256], user_data_[256];
  IntegerDecoder dx_{32, 2}, dy_{32, 22}, z_coder_{32, 20};
};

// GPSTIME11: the GPS time as a 64-bit integer pattern, predicted in up to four interleaved
// sequences (multi-return pulses, several scanners), each with its last time and step.
class GpsTime11 final : public PointItem {
 public:
  explicit GpsTime11(const std::uint8_t* first) { std::memcpy(&time_[0], first, 8); }

  void decode(RangeDecoder& d, std::uint8_t* out) override {
    // A valid stream switches sequence at most once per point; more is a corrupt stream.
    for (int switches = 0;; ++switches) {
      if (switches > 4) throw Corrupt("GPS time sequence switches without end");
      if (step_[last_] == 0) {
        const std::uint32_t s = d.symbol(zero_step_);
        if (s == 1) {  // a 32-bit difference
          step_[last_] = gps_.decode(d, 0, 0);
          time_[last_] += static_cast<std::uint64_t>(static_cast<std::int64_t>(step_[last_]));
          extreme_[last_] = 0;
        } else if (s == 2) {  // a new sequence, coded in full
          new_sequence(d);
        } else if (s > 2) {  // another sequence
          last_ = (last_ + s - 2) & 3;
          continue;
        }
      } else {
        const std::uint32_t s = d.symbol(multiple_);
        if (s == 1) {
          time_[last_] +=
              static_cast<std::uint64_t>(static_cast<std::int64_t>(gps_.decode(d, step_[last_], 1)));
          extreme_[last_] = 0;
        } else if (s < kUnchanged) {
          time_[last_] += static_cast<std::uint64_t>(static_cast<std::int64_t>(multiple_step(d, s)));
        } else if (s == kCodeFull) {
          new_sequence(d);
        } else if (s > kCodeFull) {
          last_ = (last_ + s - kCodeFull) & 3;
          continue;
        }
      }
      break;
    }
    std::memcpy(out, &time_[last_], 8);
  }

 private:
  static constexpr std::uint32_t kMulti = 500;      // largest step multiple coded
  static constexpr std::int32_t kMultiMinus = -10;  // smallest (negative) multiple
  static constexpr std::uint32_t kUnchanged = kMulti - kMultiMinus + 1;
  static constexpr std::uint32_t kCodeFull = kUnchanged + 1;

  void new_sequence(RangeDecoder& d) {
    next_ = (next_ + 1) & 3;
    const auto high =
        static_cast<std::uint32_t>(gps_.decode(d, static_cast<std::int32_t>(time_[last_] >> 32), 8));
    time_[next_] = (static_cast<std::uint64_t>(high) << 32) | d.raw32();
    last_ = next_;
    step_[last_] = 0;
    extreme_[last_] = 0;
  }

  // The difference for multiple symbol s (0, 2..kMulti, or a negative multiple above kMulti).
  std::int32_t multiple_step(RangeDecoder& d, std::uint32_t s) {
    const std::int32_t step = step_[last_];
    auto times = [](std::int32_t a, std::int32_t b) {
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * static_cast<std::uint32_t>(b));
    };
    std::int32_t diff;
    bool extreme = false;
    if (s == 0) {
      diff = gps_.decode(d, 0, 7);
      extreme = true;
    } else if (s < kMulti) {
      diff = gps_.decode(d, times(static_cast<std::int32_t>(s), step), s < 10 ? 2 : 3);
    } else if (s == kMulti) {
      diff = gps_.decode(d, times(kMulti, step), 4);
      extreme = true;
    } else {
      const std::int32_t multi = static_cast<std::int32_t>(kMulti) - static_cast<std::int32_t>(s);
      if (multi > kMultiMinus) {
        diff = gps_.decode(d, times(multi, step), 5);
      } else {
        diff = gps_.decode(d, times(kMultiMinus, step), 6);
        extreme = true;
      }
    }
    if (extreme && ++extreme_[last_] > 3) {  // the step itself has changed
      step_[last_] = diff;
      extreme_[last_] = 0;
    }
    return diff;
  }

  std::uint32_t last_ = 0, next_ = 0;
  std::uint64_t time_[4] = {};
  std::int32_t step_[4] = {};
  std::int32_t extreme_[4] = {};
  SymbolModel multiple_{kMulti - kMultiMinus + 6};
  SymbolModel zero_step_{6};
  IntegerDecoder gps_{32, 9};
};

// RGB12: the six colour bytes, see decode_rgb (laz_items.h).
class Rgb12 final : public PointItem {
 public:
  explicit Rgb12(const std::uint8_t* first) { std::memcpy(last_, first, 6); }
  void decode(RangeDecoder& d, std::uint8_t* out) override {
    std::uint16_t rgb[3];
    decode_rgb(d, models_, last_, rgb);
    std::memcpy(last_, rgb, 6);
    std::memcpy(out, rgb, 6);
  }

 private:
  std::uint16_t last_[3];
  RgbModels models_;
};

// BYTE: extra bytes, each a difference to the same byte of the record before, one model per
// byte position.
class Bytes final : public PointItem {
 public:
  Bytes(const std::uint8_t* first, std::size_t n) : last_(first, first + n) {
    models_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) models_.emplace_back(256);
  }
  void decode(RangeDecoder& d, std::uint8_t* out) override {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = static_cast<std::uint8_t>(last_[i] + d.symbol(models_[i]));
    }
    std::memcpy(out, last_.data(), last_.size());
  }

 private:
  std::vector<std::uint8_t> last_;
  std::vector<SymbolModel> models_;
};

class PointwiseDecoder final : public ChunkDecoder {
 public:
  explicit PointwiseDecoder(std::vector<Item> items) : items_(std::move(items)) {
    for (const Item& it : items_) record_ += it.size;
  }

  void decode(const std::uint8_t* begin, const std::uint8_t* end, std::uint64_t count,
              std::uint8_t* out) override {
    if (count == 0) return;
    if (static_cast<std::size_t>(end - begin) < record_) throw Corrupt("chunk shorter than its first record");
    std::memcpy(out, begin, record_);
    if (count == 1) return;
    // Fresh models for every chunk: chunks decode independently.
    std::vector<std::unique_ptr<PointItem>> items;
    std::vector<std::size_t> at;
    std::size_t offset = 0;
    for (const Item& it : items_) {
      const std::uint8_t* first = begin + offset;
      switch (it.type) {
        case kPoint10: items.push_back(std::make_unique<Point10>(first)); break;
        case kGpsTime11: items.push_back(std::make_unique<GpsTime11>(first)); break;
        case kRgb12: items.push_back(std::make_unique<Rgb12>(first)); break;
        default: items.push_back(std::make_unique<Bytes>(first, it.size)); break;
      }
      at.push_back(offset);
      offset += it.size;
    }
    bool overrun = false;
    RangeDecoder d;
    d.start(begin + record_, end, &overrun);
    for (std::uint64_t i = 1; i < count; ++i) {
      std::uint8_t* rec = out + i * record_;
      for (std::size_t k = 0; k < items.size(); ++k) items[k]->decode(d, rec + at[k]);
      if (overrun) throw Corrupt("compressed data ends before the chunk's last point");
    }
  }

 private:
  std::vector<Item> items_;
  std::size_t record_ = 0;
};

}  // namespace

std::unique_ptr<ChunkDecoder> make_pointwise_decoder(const std::vector<Item>& items, std::string* why) {
  for (const Item& it : items) {
    const bool known = it.type == kPoint10 || it.type == kGpsTime11 || it.type == kRgb12 || it.type == kByte;
    if (!known) {
      *why = "LASzip item type " + std::to_string(it.type) +
             (it.type == kWavePacket13 ? " (waveform packets)" : "") + " is not supported in point-wise LAZ";
      return nullptr;
    }
    const std::size_t size = it.type == kPoint10 ? 20 : it.type == kGpsTime11 ? 8 : it.type == kRgb12 ? 6 : 0;
    if ((size != 0 && it.size != size) || it.size == 0) {
      *why = "LASzip item type " + std::to_string(it.type) + " has size " + std::to_string(it.size);
      return nullptr;
    }
    if (it.version != 2) {
      *why = "LASzip item type " + std::to_string(it.type) + " version " + std::to_string(it.version) +
             " is not supported (canopy decodes version 2, LASzip 2.0 and later" +
             (it.version == 1 ? "; version 1 is from LASzip 1.x, 2011" : "") + ")";
      return nullptr;
    }
  }
  return std::make_unique<PointwiseDecoder>(items);
}

}  // namespace canopy::formats::laz
