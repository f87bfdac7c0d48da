// LASzip layered items, versions 3 and 4 (LAS 1.4 point formats 6-8): every field group has
// its own range-coded layer in the chunk, so a reader could skip layers; canopy decodes them
// all. Chunk layout (LASzip specification, "LAS 1.4 compatible LASzip"): the first record
// raw, a u32 point count, the u32 byte size of every layer (POINT14: 9 layers, RGB14: 1,
// RGBNIR14: 2, BYTE14: one per byte), then the layers in that order. A layer of 0 bytes
// means the field does not change within the chunk. Each of the up to four scanner channels
// has its own models and last point ("contexts"). Sources: laz_coder.h.
#include <cstring>

#include "laz_coder.h"
#include "laz_items.h"

namespace canopy::formats::laz {
namespace {

// Context of a point's (number of returns n, return number r), both 0..15, among 6.
constexpr std::uint8_t kReturnMap6[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5}};

// Penetration level |n - r| of a return, capped at 7: the z context.
inline std::uint32_t return_level(std::uint32_t n, std::uint32_t r) {
  const std::uint32_t l = n > r ? n - r : r - n;
  return l < 7 ? l : 7;
}

inline std::uint32_t k_context(std::uint32_t k, std::uint32_t cap) { return k < cap ? (k & ~1u) : cap; }

inline std::int32_t wrap_add(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}

// The fields of a point format 6 record (bytes 0-29).
struct Point14 {
  std::int32_t x = 0, y = 0, z = 0;
  std::uint16_t intensity = 0;
  std::uint32_t ret = 0, nret = 0;  // 4 bits each
  std::uint32_t flags = 0;          // classification flags: synthetic, key point, withheld, overlap
  std::uint32_t channel = 0, scan_dir = 0, edge = 0;
  std::uint32_t classification = 0, user = 0;
  std::int16_t angle = 0;
  std::uint16_t source = 0;
  std::uint64_t gps = 0;
  bool gps_changed = false;  // whether this point's GPS time changed (a context for the next)

  void load(const std::uint8_t* r) {
    std::memcpy(&x, r, 4);
    std::memcpy(&y, r + 4, 4);
    std::memcpy(&z, r + 8, 4);
    std::memcpy(&intensity, r + 12, 2);
    ret = r[14] & 15;
    nret = r[14] >> 4;
    flags = r[15] & 15;
    channel = (r[15] >> 4) & 3;
    scan_dir = (r[15] >> 6) & 1;
    edge = r[15] >> 7;
    classification = r[16];
    user = r[17];
    std::memcpy(&angle, r + 18, 2);
    std::memcpy(&source, r + 20, 2);
    std::memcpy(&gps, r + 22, 8);
  }

  void store(std::uint8_t* r) const {
    std::memcpy(r, &x, 4);
    std::memcpy(r + 4, &y, 4);
    std::memcpy(r + 8, &z, 4);
    std::memcpy(r + 12, &intensity, 2);
    r[14] = static_cast<std::uint8_t>(ret | (nret << 4));
    r[15] = static_cast<std::uint8_t>(flags | (channel << 4) | (scan_dir << 6) | (edge << 7));
    r[16] = static_cast<std::uint8_t>(classification);
    r[17] = static_cast<std::uint8_t>(user);
    std::memcpy(r + 18, &angle, 2);
    std::memcpy(r + 20, &source, 2);
    std::memcpy(r + 22, &gps, 8);
  }
};

// One layer of a chunk: its bytes and its decoder (started only when the layer has bytes).
struct Layer {
  const std::uint8_t* begin = nullptr;
  std::uint32_t size = 0;
  RangeDecoder d;
  bool on() const { return size > 0; }
};

// Models and state of POINT14 for one scanner channel.
struct Point14Context {
  explicit Point14Context(const Point14& from) : last(from) {
    last.gps_changed = false;
    for (auto& z : last_z) z = from.z;
    for (auto& i : last_intensity) i = from.intensity;
    time[0] = from.gps;
  }

  Point14 last;
  // channel_returns_XY layer
  SymbolModel changed[8] = {SymbolModel(128), SymbolModel(128), SymbolModel(128), SymbolModel(128),
                            SymbolModel(128), SymbolModel(128), SymbolModel(128), SymbolModel(128)};
  SymbolModel channel{3};
  std::unique_ptr<SymbolModel> nret[16], ret[16];
  SymbolModel ret_same_time{13};
  IntegerDecoder dx{32, 2}, dy{32, 22};
  Median5 x_median[12], y_median[12];
  // other layers
  IntegerDecoder z{32, 20};
  std::int32_t last_z[8];
  std::unique_ptr<SymbolModel> classification[64], flags[64], user[64];
  IntegerDecoder intensity{16, 4};
  std::uint16_t last_intensity[8];
  IntegerDecoder angle{16, 2};
  IntegerDecoder source{16, 1};
  // GPS time: up to four interleaved sequences, as in GPSTIME11 (laz_pointwise.cpp)
  SymbolModel multiple{515};
  SymbolModel zero_step{5};
  IntegerDecoder gps{32, 9};
  std::uint32_t seq = 0, next = 0;
  std::uint64_t time[4] = {};
  std::int32_t step[4] = {};
  std::int32_t extreme[4] = {};
};

class Point14Item {
 public:
  enum { kXY, kZ, kClass, kFlags, kIntensity, kAngle, kUser, kSource, kGps, kLayers };

  Point14Item(const std::uint8_t* first, Layer* layers, bool* overrun) : layers_(layers) {
    Point14 p;
    p.load(first);
    current_ = p.channel;
    contexts_[current_] = std::make_unique<Point14Context>(p);
    for (int i = 0; i < kLayers; ++i) {
      if (i == kXY || layers_[i].on())
        layers_[i].d.start(layers_[i].begin, layers_[i].begin + layers_[i].size, overrun);
    }
  }

  std::uint32_t channel() const { return current_; }

  // Decodes the next record; returns whether the scanner channel changed.
  bool decode(std::uint8_t* out) {
    RangeDecoder& xy = layers_[kXY].d;
    Point14Context* c = contexts_[current_].get();
    const Point14& prev = c->last;
    // Previous point single / first / last / intermediate return, and its GPS time change.
    const std::uint32_t lpr =
        (prev.ret == 1 ? 1u : 0u) + (prev.ret >= prev.nret ? 2u : 0u) + (prev.gps_changed ? 4u : 0u);
    const std::uint32_t changed = xy.symbol(c->changed[lpr]);
    bool switched = false;
    if (changed & 64) {
      const std::uint32_t ch = (current_ + xy.symbol(c->channel) + 1) & 3;
      if (!contexts_[ch]) contexts_[ch] = std::make_unique<Point14Context>(c->last);
      current_ = ch;
      c = contexts_[ch].get();
      c->last.channel = ch;
      switched = true;
    }
    Point14& p = c->last;
    const bool source_changed = changed & 32, gps_changed = changed & 16, angle_changed = changed & 8;
    if (changed & 4) p.nret = xy.symbol(lazy(c->nret[p.nret], 16));
    switch (changed & 3) {
      case 1: p.ret = (p.ret + 1) & 15; break;
      case 2: p.ret = (p.ret + 15) & 15; break;
      case 3:
        if (gps_changed) {
          p.ret = xy.symbol(lazy(c->ret[p.ret], 16));
        } else {
          p.ret = (p.ret + xy.symbol(c->ret_same_time) + 2) & 15;
        }
        break;
      default: break;
    }
    const std::uint32_t n = p.nret, r = p.ret;
    const std::uint32_t m = kReturnMap6[n][r], l = return_level(n, r);
    const std::uint32_t cpr = (r == 1 ? 2u : 0u) + (r >= n ? 1u : 0u);  // this point's return kind
    const std::uint32_t mi = (m << 1) | (gps_changed ? 1u : 0u);
    const std::int32_t dx = c->dx.decode(xy, c->x_median[mi].get(), n == 1);
    p.x = wrap_add(p.x, dx);
    c->x_median[mi].add(dx);
    const std::int32_t dy = c->dy.decode(xy, c->y_median[mi].get(), (n == 1) + k_context(c->dx.k(), 20));
    p.y = wrap_add(p.y, dy);
    c->y_median[mi].add(dy);
    if (layers_[kZ].on()) {
      const std::uint32_t k = (c->dx.k() + c->dy.k()) / 2;
      p.z = c->z.decode(layers_[kZ].d, c->last_z[l], (n == 1) + k_context(k, 18));
      c->last_z[l] = p.z;
    }
    if (layers_[kClass].on()) {
      const std::uint32_t ctx = ((p.classification & 0x1F) << 1) + (cpr == 3 ? 1u : 0u);
      p.classification = layers_[kClass].d.symbol(lazy(c->classification[ctx], 256));
    }
    if (layers_[kFlags].on()) {
      const std::uint32_t ctx = (p.edge << 5) | (p.scan_dir << 4) | p.flags;
      const std::uint32_t f = layers_[kFlags].d.symbol(lazy(c->flags[ctx], 64));
      p.edge = (f >> 5) & 1;
      p.scan_dir = (f >> 4) & 1;
      p.flags = f & 15;
    }
    if (layers_[kIntensity].on()) {
      const std::uint32_t ctx = (cpr << 1) | (gps_changed ? 1u : 0u);
      p.intensity =
          static_cast<std::uint16_t>(c->intensity.decode(layers_[kIntensity].d, c->last_intensity[ctx], cpr));
      c->last_intensity[ctx] = p.intensity;
    }
    if (layers_[kAngle].on() && angle_changed) {
      p.angle = static_cast<std::int16_t>(
          static_cast<std::uint16_t>(c->angle.decode(layers_[kAngle].d, p.angle, gps_changed ? 1 : 0)));
    }
    if (layers_[kUser].on()) p.user = layers_[kUser].d.symbol(lazy(c->user[p.user / 4], 256));
    if (layers_[kSource].on() && source_changed) {
      p.source = static_cast<std::uint16_t>(c->source.decode(layers_[kSource].d, p.source, 0));
    }
    if (layers_[kGps].on() && gps_changed) {
      decode_time(*c, layers_[kGps].d);
      p.gps = c->time[c->seq];
    }
    p.store(out);
    p.gps_changed = gps_changed;
    return switched;
  }

 private:
  static constexpr std::uint32_t kMulti = 500;
  static constexpr std::int32_t kMultiMinus = -10;
  static constexpr std::uint32_t kCodeFull = kMulti - kMultiMinus + 1;

  static void decode_time(Point14Context& c, RangeDecoder& d) {
    for (int switches = 0;; ++switches) {
      if (switches > 4) throw Corrupt("GPS time sequence switches without end");
      if (c.step[c.seq] == 0) {
        const std::uint32_t s = d.symbol(c.zero_step);
        if (s == 0) {  // a 32-bit difference
          c.step[c.seq] = c.gps.decode(d, 0, 0);
          c.time[c.seq] += static_cast<std::uint64_t>(static_cast<std::int64_t>(c.step[c.seq]));
          c.extreme[c.seq] = 0;
        } else if (s == 1) {  // a new sequence, coded in full
          new_sequence(c, d);
        } else {  // another sequence
          c.seq = (c.seq + s - 1) & 3;
          continue;
        }
      } else {
        const std::uint32_t s = d.symbol(c.multiple);
        if (s == 1) {
          c.time[c.seq] +=
              static_cast<std::uint64_t>(static_cast<std::int64_t>(c.gps.decode(d, c.step[c.seq], 1)));
          c.extreme[c.seq] = 0;
        } else if (s < kCodeFull) {
          c.time[c.seq] += static_cast<std::uint64_t>(static_cast<std::int64_t>(multiple_step(c, d, s)));
        } else if (s == kCodeFull) {
          new_sequence(c, d);
        } else {
          c.seq = (c.seq + s - kCodeFull) & 3;
          continue;
        }
      }
      return;
    }
  }

  static void new_sequence(Point14Context& c, RangeDecoder& d) {
    c.next = (c.next + 1) & 3;
    const auto high =
        static_cast<std::uint32_t>(c.gps.decode(d, static_cast<std::int32_t>(c.time[c.seq] >> 32), 8));
    c.time[c.next] = (static_cast<std::uint64_t>(high) << 32) | d.raw32();
    c.seq = c.next;
    c.step[c.seq] = 0;
    c.extreme[c.seq] = 0;
  }

  static std::int32_t multiple_step(Point14Context& c, RangeDecoder& d, std::uint32_t s) {
    const std::int32_t step = c.step[c.seq];
    auto times = [](std::int32_t a, std::int32_t b) {
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * static_cast<std::uint32_t>(b));
    };
    std::int32_t diff;
    bool extreme = false;
    if (s == 0) {
      diff = c.gps.decode(d, 0, 7);
      extreme = true;
    } else if (s < kMulti) {
      diff = c.gps.decode(d, times(static_cast<std::int32_t>(s), step), s < 10 ? 2 : 3);
    } else if (s == kMulti) {
      diff = c.gps.decode(d, times(kMulti, step), 4);
      extreme = true;
    } else {
      const std::int32_t multi = static_cast<std::int32_t>(kMulti) - static_cast<std::int32_t>(s);
      if (multi > kMultiMinus) {
        diff = c.gps.decode(d, times(multi, step), 5);
      } else {
        diff = c.gps.decode(d, times(kMultiMinus, step), 6);
        extreme = true;
      }
    }
    if (extreme && ++c.extreme[c.seq] > 3) {
      c.step[c.seq] = diff;
      c.extreme[c.seq] = 0;
    }
    return diff;
  }

  Layer* layers_;
  std::uint32_t current_ = 0;
  std::unique_ptr<Point14Context> contexts_[4];
};

// The items after POINT14 keep one context per scanner channel too. Version 3 hands them the
// channel only for a point where it changed (channel 0 otherwise), and on a switch to a
// channel already seen it keeps predicting from the previous channel's last values; version 4
// fixed both (LASzip 3.5). Decoding must repeat what the encoder did.
template <typename Context>
class ChannelContexts {
 public:
  template <typename Values>
  ChannelContexts(std::uint32_t channel, bool v4, const Values& first) : current_(channel), v4_(v4) {
    slots_[channel] = std::make_unique<Context>(first);
  }

  // The context to decode with for `channel`; *last is set to the values to predict from
  // (and to update).
  template <typename Values>
  Context& select(std::uint32_t channel, Values** last) {
    *last = &slots_[current_]->last;
    if (channel != current_) {
      current_ = channel;
      if (!slots_[channel]) {
        slots_[channel] = std::make_unique<Context>(**last);
        *last = &slots_[channel]->last;
      } else if (v4_) {
        *last = &slots_[channel]->last;
      }
    }
    return *slots_[current_];
  }

 private:
  std::unique_ptr<Context> slots_[4];
  std::uint32_t current_ = 0;
  bool v4_ = false;
};

struct Rgb14Context {
  struct Values {
    std::uint16_t v[4] = {0, 0, 0, 0};  // red green blue (nir)
  };
  explicit Rgb14Context(const Values& from) : last(from) {}
  Values last;
  RgbModels rgb;
  SymbolModel nir_used{4};
  SymbolModel nir_diff[2] = {SymbolModel(256), SymbolModel(256)};
};

class LayeredItem {
 public:
  virtual ~LayeredItem() = default;
  virtual void decode(std::uint8_t* out, std::uint32_t channel) = 0;
};

// RGB14 (6 bytes) and RGBNIR14 (8 bytes): colour layer, and for RGBNIR14 a NIR layer.
class Rgb14Item final : public LayeredItem {
 public:
  Rgb14Item(const std::uint8_t* first, bool nir, std::uint32_t channel, bool v4, Layer* layers, bool* overrun)
      : nir_(nir), layers_(layers), contexts_(channel, v4, values(first, nir)) {
    for (int i = 0; i < (nir ? 2 : 1); ++i) {
      if (layers_[i].on()) layers_[i].d.start(layers_[i].begin, layers_[i].begin + layers_[i].size, overrun);
    }
  }

  void decode(std::uint8_t* out, std::uint32_t channel) override {
    Rgb14Context::Values* values = nullptr;
    Rgb14Context& c = contexts_.select(channel, &values);
    std::uint16_t* last = values->v;
    if (layers_[0].on()) {
      std::uint16_t rgb[3];
      decode_rgb(layers_[0].d, c.rgb, last, rgb);
      std::memcpy(last, rgb, 6);
    }
    std::memcpy(out, last, 6);
    if (!nir_) return;
    if (layers_[1].on()) {
      RangeDecoder& d = layers_[1].d;
      const std::uint32_t sym = d.symbol(c.nir_used);
      std::uint32_t lo = last[3] & 0xFFu, hi = last[3] >> 8;
      if (sym & 1) lo = (d.symbol(c.nir_diff[0]) + lo) & 0xFF;
      if (sym & 2) hi = (d.symbol(c.nir_diff[1]) + hi) & 0xFF;
      last[3] = static_cast<std::uint16_t>(lo | (hi << 8));
    }
    std::memcpy(out + 6, &last[3], 2);
  }

 private:
  static Rgb14Context::Values values(const std::uint8_t* first, bool nir) {
    Rgb14Context::Values v;
    std::memcpy(v.v, first, nir ? 8 : 6);
    return v;
  }
  bool nir_;
  Layer* layers_;
  ChannelContexts<Rgb14Context> contexts_;
};

struct Byte14Context {
  explicit Byte14Context(const std::vector<std::uint8_t>& from) : last(from), models(from.size()) {}
  std::vector<std::uint8_t> last;
  std::vector<std::unique_ptr<SymbolModel>> models;
};

// BYTE14: extra bytes, one layer per byte.
class Byte14Item final : public LayeredItem {
 public:
  Byte14Item(const std::uint8_t* first, std::size_t n, std::uint32_t channel, bool v4, Layer* layers,
             bool* overrun)
      : layers_(layers), contexts_(channel, v4, std::vector<std::uint8_t>(first, first + n)) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!layers_[i].on()) continue;  // a byte that does not change in this chunk
      layers_[i].d.start(layers_[i].begin, layers_[i].begin + layers_[i].size, overrun);
      active_.push_back(i);
    }
  }

  void decode(std::uint8_t* out, std::uint32_t channel) override {
    std::vector<std::uint8_t>* values = nullptr;
    Byte14Context& c = contexts_.select(channel, &values);
    std::vector<std::uint8_t>& last = *values;
    for (const std::size_t i : active_) {
      last[i] = static_cast<std::uint8_t>(last[i] + layers_[i].d.symbol(lazy(c.models[i], 256)));
    }
    std::memcpy(out, last.data(), last.size());
  }

 private:
  Layer* layers_;
  std::vector<std::size_t> active_;
  ChannelContexts<Byte14Context> contexts_;
};

class LayeredDecoder final : public ChunkDecoder {
 public:
  explicit LayeredDecoder(std::vector<Item> items) : items_(std::move(items)) {
    for (const Item& it : items_) {
      record_ += it.size;
      layer_count_ += layers_of(it);
    }
  }

  void decode(const std::uint8_t* begin, const std::uint8_t* end, std::uint64_t count,
              std::uint8_t* out) override {
    if (count == 0) return;
    const auto size = static_cast<std::size_t>(end - begin);
    if (size < record_) throw Corrupt("chunk shorter than its first record");
    std::memcpy(out, begin, record_);
    if (count == 1) return;
    const std::size_t head = record_ + 4 + 4 * layer_count_;
    if (size < head) throw Corrupt("chunk shorter than its first record and layer sizes");
    // More points than needed: the header counts fewer than the chunks hold (LASzip reads the
    // header's count). Fewer: the layers cannot hold the points asked for.
    const std::uint32_t stated = get_u32(begin + record_);
    if (stated < count) {
      throw Corrupt("it holds " + std::to_string(stated) + " points, the chunk table and header ask for " +
                    std::to_string(count));
    }
    std::vector<Layer> layers(layer_count_);
    std::size_t at = head;
    for (std::size_t i = 0; i < layer_count_; ++i) {
      layers[i].size = get_u32(begin + record_ + 4 + 4 * i);
      if (layers[i].size > size - at) throw Corrupt("a layer runs past the end of the chunk");
      layers[i].begin = begin + at;
      at += layers[i].size;
    }
    // Fresh models for every chunk: chunks decode independently.
    bool overrun = false;
    Point14Item point(begin, layers.data(), &overrun);
    std::vector<std::unique_ptr<LayeredItem>> others;
    std::vector<std::size_t> offsets;
    std::size_t offset = items_[0].size, layer = Point14Item::kLayers;
    const bool v4 = items_[0].version == 4;
    for (std::size_t k = 1; k < items_.size(); ++k) {
      const Item& it = items_[k];
      if (it.type == kByte14) {
        others.push_back(std::make_unique<Byte14Item>(begin + offset, it.size, point.channel(),
                                                      it.version == 4, &layers[layer], &overrun));
      } else {
        others.push_back(std::make_unique<Rgb14Item>(begin + offset, it.type == kRgbNir14, point.channel(),
                                                     it.version == 4, &layers[layer], &overrun));
      }
      offsets.push_back(offset);
      offset += it.size;
      layer += layers_of(it);
    }
    for (std::uint64_t i = 1; i < count; ++i) {
      std::uint8_t* rec = out + i * record_;
      const bool switched = point.decode(rec);
      const std::uint32_t channel = v4 || switched ? point.channel() : 0;
      for (std::size_t k = 0; k < others.size(); ++k) others[k]->decode(rec + offsets[k], channel);
      if (overrun) throw Corrupt("a layer's compressed data ends before the chunk's last point");
    }
  }

 private:
  static std::size_t layers_of(const Item& it) {
    switch (it.type) {
      case kPoint14: return Point14Item::kLayers;
      case kRgb14: return 1;
      case kRgbNir14: return 2;
      default: return it.size;  // BYTE14
    }
  }

  std::vector<Item> items_;
  std::size_t record_ = 0, layer_count_ = 0;
};

}  // namespace

std::unique_ptr<ChunkDecoder> make_layered_decoder(const std::vector<Item>& items, std::string* why) {
  for (std::size_t k = 0; k < items.size(); ++k) {
    const Item& it = items[k];
    const bool known = it.type == kPoint14 || it.type == kRgb14 || it.type == kRgbNir14 || it.type == kByte14;
    if (!known || (it.type == kPoint14) != (k == 0)) {
      *why = "LASzip item type " + std::to_string(it.type) +
             (it.type == kWavePacket14 ? " (waveform packets)" : "") + " at position " + std::to_string(k + 1) +
             " is not supported in layered LAZ (POINT14 first, then RGB14, RGBNIR14, BYTE14)";
      return nullptr;
    }
    const std::size_t size = it.type == kPoint14 ? 30 : it.type == kRgb14 ? 6 : it.type == kRgbNir14 ? 8 : 0;
    if ((size != 0 && it.size != size) || it.size == 0) {
      *why = "LASzip item type " + std::to_string(it.type) + " has size " + std::to_string(it.size);
      return nullptr;
    }
    if (it.version < 2 || it.version > 4) {
      *why = "LASzip item type " + std::to_string(it.type) + " version " + std::to_string(it.version) +
             " is not supported (canopy decodes layered versions 3 and 4)";
      return nullptr;
    }
  }
  return std::make_unique<LayeredDecoder>(items);
}

}  // namespace canopy::formats::laz
