#include "canopy/formats/height_raster.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"

namespace canopy::formats {
namespace {

using common::DataError;

constexpr const char* kMagic = "canopy.height_raster 1\n";
constexpr int kMaxSide = 8192;
constexpr long long kMaxPixels = 1LL << 24;

std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

bool valid_size(int w, int h) {
  return w >= 1 && h >= 1 && w <= kMaxSide && h <= kMaxSide && 1LL * w * h <= kMaxPixels;
}

// Reads the header's lines one by one: `key` then numbers separated by one space.
class Header {
 public:
  Header(const std::string& bytes, const std::string& name) : b_(bytes), name_(name) {}
  std::vector<double> line(const char* key, std::size_t count) {
    const std::size_t end = b_.find('\n', at_);
    const std::string want = std::string(key) + " ";
    if (end == std::string::npos || b_.compare(at_, want.size(), want) != 0) {
      throw DataError(name_,
                      std::string("height raster header: line '") + key + " ...' missing or out of order");
    }
    std::vector<double> out;
    std::size_t p = at_ + want.size();
    for (std::size_t k = 0; k < count; ++k) {
      if (k > 0) {
        if (p >= end || b_[p] != ' ') bad(key);
        ++p;
      }
      const std::string text = b_.substr(p, std::min(end, b_.find(' ', p)) - p);
      char* stop = nullptr;
      const double v = std::strtod(text.c_str(), &stop);
      if (text.empty() || stop != text.c_str() + text.size() || !std::isfinite(v)) bad(key);
      out.push_back(v);
      p += text.size();
    }
    if (p != end) bad(key);
    at_ = end + 1;
    return out;
  }
  std::string word(const char* key) {
    const std::size_t end = b_.find('\n', at_);
    const std::string want = std::string(key) + " ";
    if (end == std::string::npos || b_.compare(at_, want.size(), want) != 0) {
      throw DataError(name_,
                      std::string("height raster header: line '") + key + " ...' missing or out of order");
    }
    const std::string w = b_.substr(at_ + want.size(), end - at_ - want.size());
    at_ = end + 1;
    return w;
  }
  std::size_t at() const { return at_; }
  void skip(std::size_t n) { at_ += n; }
  [[noreturn]] void bad(const char* key) const {
    throw DataError(name_, std::string("height raster header: malformed '") + key + "' line");
  }

 private:
  const std::string& b_;
  const std::string& name_;
  std::size_t at_ = 0;
};

int whole(double v, const char* key, const std::string& name) {
  if (v != std::floor(v) || v < 1 || v > kMaxSide) {
    throw DataError(name, std::string("height raster: ") + key + " " + number(v) +
                              " is not a whole number in [1, " + std::to_string(kMaxSide) + "]");
  }
  return static_cast<int>(v);
}

}  // namespace

bool is_height_raster(const std::string& bytes) { return bytes.compare(0, std::strlen(kMagic), kMagic) == 0; }

std::string serialize_height_raster(const HeightRaster& r) {
  if (!valid_size(r.width, r.height) || r.values.size() != static_cast<std::size_t>(r.width) * r.height ||
      !(r.pixel > 0) || !std::isfinite(r.pixel) || !std::isfinite(r.x0) || !std::isfinite(r.y1) ||
      !(r.box_x0 <= r.box_x1) || !(r.box_y0 <= r.box_y1) || !std::isfinite(r.box_x1 - r.box_x0) ||
      !std::isfinite(r.box_y1 - r.box_y0) || !(r.density >= 0) || !std::isfinite(r.density)) {
    throw common::Error("height raster: internal: size, pixel, corner, box or density out of range");
  }
  std::string out = kMagic;
  out += "width " + std::to_string(r.width) + "\n";
  out += "height " + std::to_string(r.height) + "\n";
  out += "pixel " + number(r.pixel) + "\n";
  out += "corner " + number(r.x0) + " " + number(r.y1) + "\n";
  out += "points " + number(r.box_x0) + " " + number(r.box_y0) + " " + number(r.box_x1) + " " +
         number(r.box_y1) + "\n";
  out += "density " + number(r.density) + "\n";
  out += "data float32_le\n";
  const std::size_t head = out.size();
  out.resize(head + 4 * r.values.size());
  for (std::size_t i = 0; i < r.values.size(); ++i) {
    if (std::isinf(r.values[i])) throw common::Error("height raster: internal: an infinite value");
    std::uint32_t u;
    std::memcpy(&u, &r.values[i], 4);
    for (int k = 0; k < 4; ++k) out[head + 4 * i + k] = static_cast<char>((u >> (8 * k)) & 0xff);
  }
  return out;
}

void write_height_raster(const HeightRaster& raster, const std::string& path) {
  common::write_file_atomic(path, serialize_height_raster(raster));
}

HeightRaster parse_height_raster(const std::string& bytes, const std::string& name) {
  if (!is_height_raster(bytes)) {
    if (bytes.compare(0, 21, "canopy.height_raster ") == 0)
      throw DataError(name, "height raster of another version (this canopy reads version 1)");
    throw DataError(name, "not a height raster (the file does not start 'canopy.height_raster 1')");
  }
  Header h(bytes, name);
  h.skip(std::strlen(kMagic));
  HeightRaster r;
  r.width = whole(h.line("width", 1)[0], "width", name);
  r.height = whole(h.line("height", 1)[0], "height", name);
  if (!valid_size(r.width, r.height))
    throw DataError(name, "height raster: " + std::to_string(r.width) + " x " + std::to_string(r.height) +
                              " pixels, more than 2^24");
  r.pixel = h.line("pixel", 1)[0];
  if (!(r.pixel > 0)) throw DataError(name, "height raster: pixel must be > 0");
  const auto corner = h.line("corner", 2);
  r.x0 = corner[0];
  r.y1 = corner[1];
  const auto box = h.line("points", 4);
  r.box_x0 = box[0];
  r.box_y0 = box[1];
  r.box_x1 = box[2];
  r.box_y1 = box[3];
  if (!(r.box_x0 <= r.box_x1 && r.box_y0 <= r.box_y1))
    throw DataError(name, "height raster: the points' box must have x0 <= x1 and y0 <= y1");
  r.density = h.line("density", 1)[0];
  if (r.density < 0) throw DataError(name, "height raster: density must be >= 0");
  if (h.word("data") != "float32_le") throw DataError(name, "height raster: data must be float32_le");
  const std::size_t n = static_cast<std::size_t>(r.width) * r.height;
  const std::size_t avail = bytes.size() - h.at();
  if (avail != 4 * n) {
    throw DataError(name, "height raster: " + std::to_string(r.width) + " x " + std::to_string(r.height) +
                              " pixels need " + std::to_string(4 * n) + " bytes of data, the file holds " +
                              std::to_string(avail) + (avail < 4 * n ? " (truncated file)" : ""));
  }
  r.values.resize(n);
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + h.at());
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t u = p[4 * i] | (std::uint32_t{p[4 * i + 1]} << 8) |
                            (std::uint32_t{p[4 * i + 2]} << 16) | (std::uint32_t{p[4 * i + 3]} << 24);
    std::memcpy(&r.values[i], &u, 4);
    if (std::isinf(r.values[i]))
      throw DataError(name, "height raster: pixel " + std::to_string(i) + " holds an infinite value");
  }
  return r;
}

HeightRaster read_height_raster(const std::string& path) {
  return parse_height_raster(common::read_file(path), path);
}

}  // namespace canopy::formats
