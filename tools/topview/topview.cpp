#include "topview/topview.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "canopy/common/error.h"

namespace canopy::topview {

namespace {

bool finite_point(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs,
                  std::size_t i) {
  return std::isfinite(xs[i]) && std::isfinite(ys[i]) && std::isfinite(zs[i]);
}

// The picture's frame: the box holding the finite points and the shapes, `size` pixels along
// its longer side; no pixels yet.
Image frame(const formats::PointCloud& scan, const std::vector<Shape>& shapes, int size) {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  const auto& xs = scan.col("x");
  const auto& ys = scan.col("y");
  const auto& zs = scan.col("z");
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!finite_point(xs, ys, zs, i)) continue;
    x0 = std::min(x0, xs[i]);
    x1 = std::max(x1, xs[i]);
    y0 = std::min(y0, ys[i]);
    y1 = std::max(y1, ys[i]);
  }
  for (const Shape& s : shapes) {
    for (const auto& p : s.ring) {
      x0 = std::min(x0, p[0]);
      x1 = std::max(x1, p[0]);
      y0 = std::min(y0, p[1]);
      y1 = std::max(y1, p[1]);
    }
  }
  if (!(x1 >= x0 && y1 >= y0))
    throw common::Error("topview: nothing to draw (no finite point, no footprint)");
  Image img;
  img.pixel = std::max({x1 - x0, y1 - y0, 1e-3}) / size;
  img.width = std::max(1, static_cast<int>(std::ceil((x1 - x0) / img.pixel)) + 1);
  img.height = std::max(1, static_cast<int>(std::ceil((y1 - y0) / img.pixel)) + 1);
  img.x0 = x0;
  img.y1 = y1;
  return img;
}

// The highest point per pixel (-inf where none), grey from the 2nd to the 98th percentile of
// those heights, near black where no point.
void paint_heights(const formats::PointCloud& scan, Image& img) {
  const auto& xs = scan.col("x");
  const auto& ys = scan.col("y");
  const auto& zs = scan.col("z");
  const std::size_t n = static_cast<std::size_t>(img.width) * img.height;
  std::vector<double> top(n, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!finite_point(xs, ys, zs, i)) continue;
    const int c = std::min(img.width - 1, static_cast<int>((xs[i] - img.x0) / img.pixel));
    const int r = std::min(img.height - 1, static_cast<int>((img.y1 - ys[i]) / img.pixel));
    double& t = top[static_cast<std::size_t>(r) * img.width + c];
    t = std::max(t, zs[i]);
  }
  std::vector<double> seen;
  for (double t : top) {
    if (std::isfinite(t)) seen.push_back(t);
  }
  double lo = 0, hi = 1;
  if (!seen.empty()) {
    std::sort(seen.begin(), seen.end());
    lo = seen[seen.size() * 2 / 100];
    hi = seen[std::min(seen.size() - 1, seen.size() * 98 / 100)];
    if (hi <= lo) hi = lo + 1;
  }
  img.rgb.assign(3 * n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    std::uint8_t g = 30;  // no point: near black
    if (std::isfinite(top[k]))
      g = static_cast<std::uint8_t>(60 + 150 * std::clamp((top[k] - lo) / (hi - lo), 0.0, 1.0));
    img.rgb[3 * k] = img.rgb[3 * k + 1] = img.rgb[3 * k + 2] = g;
  }
}

// A 2 x 2 pixel dot with its top-left corner at pixel coordinates (px, py).
void plot(Image& img, double px, double py, const Rgb& c) {
  for (int dr = 0; dr <= 1; ++dr) {
    for (int dc = 0; dc <= 1; ++dc) {
      const int col = static_cast<int>(std::floor(px)) + dc, row = static_cast<int>(std::floor(py)) + dr;
      if (col < 0 || row < 0 || col >= img.width || row >= img.height) continue;
      const std::size_t i = 3 * (static_cast<std::size_t>(row) * img.width + col);
      img.rgb[i] = c[0];
      img.rgb[i + 1] = c[1];
      img.rgb[i + 2] = c[2];
    }
  }
}

// Outlines, two pixels wide, in the given order (later ones on top).
void draw_outlines(const std::vector<Shape>& shapes, Image& img) {
  const double x0 = img.x0, y1 = img.y1;
  for (const Shape& s : shapes) {
    for (std::size_t k = 0; k < s.ring.size(); ++k) {
      const auto& a = s.ring[k];
      const auto& b = s.ring[(k + 1) % s.ring.size()];
      const double ax = (a[0] - x0) / img.pixel, ay = (y1 - a[1]) / img.pixel;
      const double bx = (b[0] - x0) / img.pixel, by = (y1 - b[1]) / img.pixel;
      const int steps = std::max(1, static_cast<int>(std::ceil(2 * std::hypot(bx - ax, by - ay))));
      for (int t = 0; t <= steps; ++t) {
        const double f = static_cast<double>(t) / steps;
        plot(img, ax + f * (bx - ax) - 0.5, ay + f * (by - ay) - 0.5, s.colour);
      }
    }
  }
}

}  // namespace

void validate(const Params& params) {
  if (params.size < 16 || params.size > 8192) throw common::UsageError("--size must be in [16, 8192]");
  if (params.tile < 0) throw common::UsageError("--tile must be >= 0");
}

Image run(const formats::PointCloud& scan, const std::vector<Shape>& shapes, const Params& params) {
  validate(params);
  return render(scan, shapes, params.size);
}

Image render(const formats::PointCloud& scan, const std::vector<Shape>& shapes, int size) {
  Image img = frame(scan, shapes, size);
  paint_heights(scan, img);
  draw_outlines(shapes, img);
  return img;
}

std::string encode_png(const Image& image) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t bytes = 0;
  if (!png_image_write_to_memory(&png, nullptr, &bytes, 0, image.rgb.data(), 0, nullptr)) {
    throw common::Error(std::string("PNG encoding failed: ") + png.message);
  }
  std::string out(bytes, '\0');
  if (!png_image_write_to_memory(&png, out.data(), &bytes, 0, image.rgb.data(), 0, nullptr)) {
    throw common::Error(std::string("PNG encoding failed: ") + png.message);
  }
  out.resize(bytes);
  return out;
}

}  // namespace canopy::topview
