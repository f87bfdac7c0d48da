// LAZ chunk decoders, private to formats/: one chunk of compressed points -> the LAS point
// records it encodes. laz.cpp finds the chunks; laz_pointwise.cpp decodes LASzip's
// point-wise items (LAS point formats 0-5, item version 2), laz_layered.cpp its layered
// LAS 1.4 items (point formats 6-10, item versions 3 and 4). See laz_coder.h for sources.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "laz_coder.h"

namespace canopy::formats::laz {

// LASzip item types (the "laszip encoded" VLR lists the items making up a point record).
enum ItemType : std::uint16_t {
  kByte = 0,
  kPoint10 = 6,
  kGpsTime11 = 7,
  kRgb12 = 8,
  kWavePacket13 = 9,
  kPoint14 = 10,
  kRgb14 = 11,
  kRgbNir14 = 12,
  kWavePacket14 = 13,
  kByte14 = 14,
};

struct Item {
  std::uint16_t type = 0, size = 0, version = 0;
};

// Decodes whole chunks. `decode` writes `count` records of `record` bytes (the sum of the
// item sizes) to `out`, from the chunk's bytes [begin, end). Throws Corrupt (laz_coder.h).
class ChunkDecoder {
 public:
  virtual ~ChunkDecoder() = default;
  virtual void decode(const std::uint8_t* begin, const std::uint8_t* end, std::uint64_t count,
                      std::uint8_t* out) = 0;
};

// Point-wise items (LASzip compressors 1 and 2): POINT10, GPSTIME11, RGB12, BYTE, version 2.
// Returns nullptr and sets *why for items it cannot decode.
std::unique_ptr<ChunkDecoder> make_pointwise_decoder(const std::vector<Item>& items, std::string* why);
// Layered items (compressor 3): POINT14 first, then RGB14, RGBNIR14, BYTE14; versions 2-4
// (2 is LASzip's alias of 3).
std::unique_ptr<ChunkDecoder> make_layered_decoder(const std::vector<Item>& items, std::string* why);

// Colour (RGB12, and the colour of RGB14 and RGBNIR14): a symbol says which of the six bytes
// changed; each changed byte is coded as a difference; green's and blue's predictions add
// red's (and green's) change to their last value.
struct RgbModels {
  SymbolModel used{128};
  SymbolModel diff[6] = {SymbolModel(256), SymbolModel(256), SymbolModel(256),
                         SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

inline void decode_rgb(RangeDecoder& d, RgbModels& m, const std::uint16_t last[3], std::uint16_t out[3]) {
  auto lo = [](std::uint16_t v) { return static_cast<std::int32_t>(v & 0xFF); };
  auto hi = [](std::uint16_t v) { return static_cast<std::int32_t>(v >> 8); };
  auto clamp = [](std::int32_t v) { return v <= 0 ? 0 : v >= 255 ? 255 : v; };
  auto add = [&](int model, std::int32_t pred) {
    return static_cast<std::int32_t>((d.symbol(m.diff[model]) + static_cast<std::uint32_t>(pred)) & 0xFF);
  };
  const std::uint32_t sym = d.symbol(m.used);
  const std::int32_t r_lo = sym & 1 ? add(0, lo(last[0])) : lo(last[0]);
  const std::int32_t r_hi = sym & 2 ? add(1, hi(last[0])) : hi(last[0]);
  out[0] = static_cast<std::uint16_t>(r_lo | (r_hi << 8));
  if ((sym & 64) == 0) {  // grey: green and blue equal red
    out[1] = out[2] = out[0];
    return;
  }
  std::int32_t diff = r_lo - lo(last[0]);
  const std::int32_t g_lo = sym & 4 ? add(2, clamp(diff + lo(last[1]))) : lo(last[1]);
  std::int32_t b_lo = lo(last[2]);
  if (sym & 16) {
    diff = (diff + (g_lo - lo(last[1]))) / 2;
    b_lo = add(4, clamp(diff + lo(last[2])));
  }
  diff = r_hi - hi(last[0]);
  const std::int32_t g_hi = sym & 8 ? add(3, clamp(diff + hi(last[1]))) : hi(last[1]);
  std::int32_t b_hi = hi(last[2]);
  if (sym & 32) {
    diff = (diff + (g_hi - hi(last[1]))) / 2;
    b_hi = add(5, clamp(diff + hi(last[2])));
  }
  out[1] = static_cast<std::uint16_t>(g_lo | (g_hi << 8));
  out[2] = static_cast<std::uint16_t>(b_lo | (b_hi << 8));
}

}  // namespace canopy::formats::laz
