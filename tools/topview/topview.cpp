#include "topview/topview.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/math.h"
#include "topview/draw.h"

namespace canopy::topview {

namespace {

constexpr float kEmpty = std::numeric_limits<float>::quiet_NaN();
constexpr double kGroundCell = 1.0;          // m: the cells of the ground minima and of the density
constexpr int kGroundRadius = 6;             // cells: the opening's window is 13 m (objects narrower go)
constexpr double kMaxGroundCells = 1 << 22;  // 4 km² of 1 m cells (16 MB); a wider scan gets coarser cells

bool finite_point(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs,
                  std::size_t i) {
  return std::isfinite(xs[i]) && std::isfinite(ys[i]) && std::isfinite(zs[i]);
}

struct Box {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  void add(double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
};

// The box holding the scan's finite points (empty: x1 < x0 when there is none).
Box finite_points_box(const formats::PointCloud& scan) {
  const auto& xs = scan.col("x");
  const auto& ys = scan.col("y");
  const auto& zs = scan.col("z");
  Box b;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (finite_point(xs, ys, zs, i)) b.add(xs[i], ys[i]);
  }
  return b;
}

// The box holding the finite points (`points`) and that box with the shapes (`all`).
struct Extent {
  Box points, all;
};
Extent extent(const formats::PointCloud& scan, const std::vector<Shape>& shapes) {
  Extent e;
  e.points = finite_points_box(scan);
  e.all = e.points;
  for (const Shape& s : shapes) {
    for (const auto& p : s.ring) e.all.add(p[0], p[1]);
  }
  if (!(e.all.x1 >= e.all.x0 && e.all.y1 >= e.all.y0))
    throw common::Error("topview: nothing to draw (no finite point, no footprint)");
  return e;
}

// A raster of floats (kEmpty = no value), row 0 at y0 for the ground grid.
struct Grid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, cell = 1;
  std::vector<float> v;
  float& at(int i, int j) { return v[static_cast<std::size_t>(j) * nx + i]; }
  float at(int i, int j) const { return v[static_cast<std::size_t>(j) * nx + i]; }

  // Bilinear between cell centres, over the corners that have a value (a point's own cell
  // always has one).
  double bilinear(double x, double y) const {
    const double fx = (x - x0) / cell - 0.5, fy = (y - y0) / cell - 0.5;
    const int i0 = static_cast<int>(std::floor(fx)), j0 = static_cast<int>(std::floor(fy));
    const double tx = fx - i0, ty = fy - j0;
    double sum = 0, weight = 0;
    for (int dj = 0; dj <= 1; ++dj) {
      for (int di = 0; di <= 1; ++di) {
        const int i = std::clamp(i0 + di, 0, nx - 1), j = std::clamp(j0 + dj, 0, ny - 1);
        const float g = at(i, j);
        if (std::isnan(g)) continue;
        const double w = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty) + 1e-9;
        sum += w * g;
        weight += w;
      }
    }
    return weight > 0 ? sum / weight : 0;
  }
};

// One pass of a sliding minimum (or maximum) of radius r along rows (or columns), cells without
// a value skipped (the window cut at the edges).
void slide(Grid& g, int r, bool along_rows, bool maximum) {
  const int n = along_rows ? g.nx : g.ny, lines = along_rows ? g.ny : g.nx;
  std::vector<float> line(n), out(n);
  for (int l = 0; l < lines; ++l) {
    for (int k = 0; k < n; ++k) line[k] = along_rows ? g.at(k, l) : g.at(l, k);
    for (int k = 0; k < n; ++k) {
      float best = kEmpty;
      for (int m = std::max(0, k - r); m <= std::min(n - 1, k + r); ++m) {
        if (std::isnan(line[m])) continue;
        if (std::isnan(best) || (maximum ? line[m] > best : line[m] < best)) best = line[m];
      }
      out[k] = best;
    }
    for (int k = 0; k < n; ++k) (along_rows ? g.at(k, l) : g.at(l, k)) = out[k];
  }
}

// The least-squares plane z = a + b i + c j through the cells that have a value (i, j: cell
// indices); {0, 0, 0} when they do not fix one.
std::array<double, 3> plane(const Grid& g) {
  double m[3][3] = {}, v[3] = {};
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const float z = g.at(i, j);
      if (std::isnan(z)) continue;
      const double p[3] = {1.0, static_cast<double>(i), static_cast<double>(j)};
      for (int r = 0; r < 3; ++r) {
        v[r] += p[r] * z;
        for (int c = 0; c < 3; ++c) m[r][c] += p[r] * p[c];
      }
    }
  }
  auto det = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const double d = det(m);
  if (!(std::abs(d) > 1e-9 * (1 + std::abs(m[1][1] * m[2][2] * m[0][0])))) return {0, 0, 0};
  std::array<double, 3> x{};
  for (int k = 0; k < 3; ++k) {  // Cramer's rule
    double a[3][3];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) a[r][c] = c == k ? v[r] : m[r][c];
    }
    x[k] = det(a) / d;
  }
  return x;
}

// The ground: the lowest point per 1 m cell, opened (a square min filter, then max filter) so
// that objects narrower than the window go and slopes stay (a plane is kept as it is). Sets `density` to the
// finite points per occupied cell area.
Grid ground(const formats::PointCloud& scan, const Box& b, double* density) {
  Grid g;
  if (!(b.x1 >= b.x0 && b.y1 >= b.y0)) {  // no finite point
    g.nx = g.ny = 1;
    g.v.assign(1, kEmpty);
    *density = 0;
    return g;
  }
  g.x0 = std::floor(b.x0);  // cells on whole metres, as detect's density
  g.y0 = std::floor(b.y0);
  g.cell = kGroundCell;
  // A scan wider than the grid's bound (a stray point km away) doubles the cell until it fits.
  while ((b.x1 - g.x0) / g.cell * ((b.y1 - g.y0) / g.cell) > kMaxGroundCells) g.cell *= 2;
  g.nx = static_cast<int>((b.x1 - g.x0) / g.cell) + 1;
  g.ny = static_cast<int>((b.y1 - g.y0) / g.cell) + 1;
  g.v.assign(static_cast<std::size_t>(g.nx) * g.ny, kEmpty);
  const auto& xs = scan.col("x");
  const auto& ys = scan.col("y");
  const auto& zs = scan.col("z");
  std::size_t points = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!finite_point(xs, ys, zs, i)) continue;
    ++points;
    const int ci = std::min(g.nx - 1, static_cast<int>((xs[i] - g.x0) / g.cell));
    const int cj = std::min(g.ny - 1, static_cast<int>((ys[i] - g.y0) / g.cell));
    float& m = g.at(ci, cj);
    if (std::isnan(m) || zs[i] < m) m = static_cast<float>(zs[i]);
  }
  const auto occupied = std::count_if(g.v.begin(), g.v.end(), [](float z) { return !std::isnan(z); });
  *density = occupied > 0 ? static_cast<double>(points) / (occupied * g.cell * g.cell) : 0;
  // Opened with the tile's mean slope taken out: a window cut at an edge of a slope would take
  // the slope's lowest value from the inside (by 0.5 m at 6 cells on a 10% slope); a plane
  // comes out exact at the edges too.
  const std::array<double, 3> p = plane(g);
  auto tilt = [&g, &p](double sign) {
    for (int j = 0; j < g.ny; ++j) {
      for (int i = 0; i < g.nx; ++i) g.at(i, j) += static_cast<float>(sign * (p[0] + p[1] * i + p[2] * j));
    }
  };
  tilt(-1);
  slide(g, kGroundRadius, true, false);
  slide(g, kGroundRadius, false, false);
  slide(g, kGroundRadius, true, true);
  slide(g, kGroundRadius, false, true);
  tilt(1);
  return g;
}

// Empty values of a w x h raster take the mean of their filled 8-neighbours, `passes` times.
void fill_gaps(std::vector<float>& v, int w, int h, int passes) {
  std::vector<float> next;
  for (int pass = 0; pass < passes; ++pass) {
    next = v;
    bool changed = false;
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) {
        if (!std::isnan(v[static_cast<std::size_t>(r) * w + c])) continue;
        double sum = 0;
        int n = 0;
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if (rr < 0 || cc < 0 || rr >= h || cc >= w) continue;
            const float x = v[static_cast<std::size_t>(rr) * w + cc];
            if (!std::isnan(x)) sum += x, ++n;
          }
        }
        if (n > 0) next[static_cast<std::size_t>(r) * w + c] = static_cast<float>(sum / n), changed = true;
      }
    }
    v.swap(next);
    if (!changed) break;
  }
}

// The legend's text scale for a map this tall.
int text_scale(int map_height) { return std::clamp(map_height / 450, 1, 4); }

// The picture's size for a data pixel and zoom: map and legend; false beyond the bound.
bool fits(const Box& b, const Footprints& fp, bool legend, double data_pixel, int zoom, Image& img) {
  // (1e-9: 9.95 / (9.95 / 100) is 100.00000000000001, one spurious column at --size 100)
  const double w = std::ceil((b.x1 - b.x0) / data_pixel - 1e-9) + 1,
               h = std::ceil((b.y1 - b.y0) / data_pixel - 1e-9) + 1;
  const double mw = w * zoom, mh = h * zoom;
  const Panel panel = legend ? legend_size(fp, text_scale(static_cast<int>(std::min(mh, 1e6)))) : Panel{};
  const double width = mw + panel.width, height = std::max<double>(mh, panel.height);
  if (width > kMaxSide || height > kMaxSide || width * height > static_cast<double>(kMaxPixels)) return false;
  img.pixel = data_pixel / zoom;
  img.data_pixel = data_pixel;
  img.zoom = zoom;
  img.map_width = static_cast<int>(mw);
  img.map_height = static_cast<int>(mh);
  img.width = static_cast<int>(width);
  img.height = static_cast<int>(height);
  return true;
}

// Sets the data pixel (one height value), the zoom (screen pixels a data pixel along a side)
// and the picture's size within the bound. --size: that many map pixels along the longer side,
// no zoom. --pixel or the density's pixel: zoomed so that the map's longer side has about
// kReadable pixels (at most 8 times); the zoom is lowered to keep the bound, then an automatic
// data pixel is coarsened, a given one is refused.
// `raster` > 0: a height raster's data pixel, taken as it is (never coarsened: beyond the bound
// an Error).
// The data pixels' grid is anchored at the points' top-left corner (`points`; the whole box
// when there is no finite point) and widened by whole data pixels to hold the footprints (`b`:
// the points and the footprints), so that a height raster of the points alone (raster()) is
// the same grid (docs/decisions/topview.md, "A raster for the tile workflow").
void size_picture(const Box& points, const Box& b, const Footprints& fp, const Params& p, Image& img,
                  double raster = 0) {
  const Box& corner = points.x1 >= points.x0 && points.y1 >= points.y0 ? points : b;
  auto anchored = [&corner, &b, &img](double data_pixel) {
    const int kx = std::max(0, static_cast<int>(std::ceil((corner.x0 - b.x0) / data_pixel - 1e-9)));
    const int ky = std::max(0, static_cast<int>(std::ceil((b.y1 - corner.y1) / data_pixel - 1e-9)));
    Box a = b;
    a.x0 = kx > 0 ? corner.x0 - kx * data_pixel : corner.x0;
    a.y1 = ky > 0 ? corner.y1 + ky * data_pixel : corner.y1;
    img.x0 = a.x0;
    img.y1 = a.y1;
    img.grid_x0 = corner.x0;
    img.grid_y1 = corner.y1;
    img.grid_col = kx;
    img.grid_row = ky;
    return a;
  };
  constexpr double kReadable = 1000;
  const double longer = std::max({b.x1 - b.x0, b.y1 - b.y0, 1e-3});
  double data_pixel =
      raster > 0    ? raster
      : p.pixel > 0 ? p.pixel
      : p.size > 0  ? longer / p.size
                   : std::clamp(std::round(100 * std::sqrt(2 / std::max(img.density, 1e-6))) / 100, 0.01, 2.0);
  for (;;) {
    const int most = p.size > 0 && raster == 0
                         ? 1
                         : std::clamp(static_cast<int>(std::ceil(kReadable / (longer / data_pixel + 1))), 1, 8);
    for (int zoom = most; zoom >= 1; --zoom) {
      if (fits(anchored(data_pixel), fp, p.legend, data_pixel, zoom, img)) return;
    }
    if (raster > 0) {
      throw common::Error("the height raster's " + std::to_string(data_pixel) +
                          " m pixel makes a picture beyond the bound (" + std::to_string(kMaxSide) +
                          " a side, " + std::to_string(kMaxPixels) +
                          " in all with the legend): make the raster with a larger --pixel");
    }
    if (p.pixel > 0 || p.size > 0) {
      throw common::UsageError(
          "a " + std::to_string(data_pixel) + " m pixel makes a map of " +
          std::to_string(static_cast<long long>(std::ceil((b.x1 - b.x0) / data_pixel) + 1)) + " x " +
          std::to_string(static_cast<long long>(std::ceil((b.y1 - b.y0) / data_pixel) + 1)) +
          " pixels, beyond the bound (" + std::to_string(kMaxSide) + " a side, " + std::to_string(kMaxPixels) +
          " in all with the legend): give a larger --pixel "
          "or a smaller --size");
    }
    data_pixel *= 1.25;
    if (!(data_pixel < 1e30)) throw common::Error("topview: no picture within the bound");  // cannot happen
  }
}

// The highest height above ground per data pixel (kEmpty where no point), gaps filled; data
// pixels are zoom x zoom map pixels.
std::vector<float> raw_heights(const formats::PointCloud& scan, const Grid& g, const Image& img) {
  const auto& xs = scan.col("x");
  const auto& ys = scan.col("y");
  const auto& zs = scan.col("z");
  const int w = img.map_width / img.zoom, h = img.map_height / img.zoom;
  const double dp = img.pixel * img.zoom;
  std::vector<float> top(static_cast<std::size_t>(w) * h, kEmpty);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!finite_point(xs, ys, zs, i)) continue;
    const int c = std::min(w - 1, img.grid_col + static_cast<int>((xs[i] - img.grid_x0) / dp));
    const int r = std::min(h - 1, img.grid_row + static_cast<int>((img.grid_y1 - ys[i]) / dp));
    float& t = top[static_cast<std::size_t>(r) * w + c];
    const auto z = static_cast<float>(zs[i] - g.bilinear(xs[i], ys[i]));
    if (std::isnan(t) || z > t) t = z;
  }
  return top;
}

// Empty data pixels filled: passes enough to close the gaps between points (spacing / pixel),
// at least 2, at most 8.
void fill_heights(std::vector<float>& top, const Image& img) {
  const int w = img.map_width / img.zoom, h = img.map_height / img.zoom;
  const double dp = img.pixel * img.zoom;
  const double spacing = img.density > 0 ? 1 / std::sqrt(img.density) : dp;
  fill_gaps(top, w, h, std::clamp(static_cast<int>(std::ceil(spacing / dp)), 2, 8));
}

// The highest height above ground per data pixel (kEmpty where no point), gaps filled; data
// pixels are zoom x zoom map pixels.
std::vector<float> heights(const formats::PointCloud& scan, const Grid& g, const Image& img) {
  std::vector<float> top = raw_heights(scan, g, img);
  fill_heights(top, img);
  return top;
}

// The map's pixels: height colour times a hillshade of the height surface (light from the
// north-west, 45° up; flat = 1), kNoData where empty; each data pixel zoom x zoom map pixels.
void paint(const std::vector<float>& top, Image& img) {
  const int w = img.map_width / img.zoom, h = img.map_height / img.zoom, z = img.zoom;
  const double dp = img.pixel * z;
  const double sun = std::sin(common::kPi / 4);
  auto value = [&](int c, int r, float fallback) {
    c = std::clamp(c, 0, w - 1);
    r = std::clamp(r, 0, h - 1);
    const float v = top[static_cast<std::size_t>(r) * w + c];
    return std::isnan(v) ? fallback : v;
  };
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const float t = top[static_cast<std::size_t>(r) * w + c];
      if (std::isnan(t)) {
        fill_rect(img, c * z, r * z, z, z, kNoData);
        continue;
      }
      const double dx = (value(c + 1, r, t) - value(c - 1, r, t)) / (2 * dp);
      const double dy = (value(c, r - 1, t) - value(c, r + 1, t)) / (2 * dp);  // north is up
      const double lambert = (dx * 0.5 - dy * 0.5 + sun) / std::sqrt(dx * dx + dy * dy + 1);
      const double shade = 0.4 + 0.6 * std::clamp(lambert / sun, 0.0, 1.5);
      const Rgb base = height_colour(t);
      Rgb col;
      for (int k = 0; k < 3; ++k)
        col[k] = static_cast<std::uint8_t>(std::min(255.0, std::round(base[k] * shade)));
      fill_rect(img, c * z, r * z, z, z, col);
    }
  }
}

// A size x size pixel dot centred on pixel coordinates (px, py), clipped to the map.
void plot(Image& img, double px, double py, int size, const Rgb& c) {
  const int c0 = static_cast<int>(std::floor(px - size / 2.0 + 0.5)),
            r0 = static_cast<int>(std::floor(py - size / 2.0 + 0.5));
  for (int row = r0; row < r0 + size; ++row) {
    for (int col = c0; col < c0 + size; ++col) {
      if (col < 0 || row < 0 || col >= img.map_width || row >= img.map_height) continue;
      const std::size_t i = 3 * (static_cast<std::size_t>(row) * img.width + col);
      std::copy(c.begin(), c.end(), img.rgb.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
}

// Outlines two pixels wide in their kind's colour over a black border one pixel wide: every
// border first, then the colours in the given order (later ones on top). Candidates the chain
// turned down (none, rejected) are drawn one pixel wide without a border: there are many, and
// the detections and the truth must stay readable among them.
void draw_outlines(const std::vector<Shape>& shapes, Image& img) {
  for (const bool border : {true, false}) {
    for (const Shape& s : shapes) {
      const bool thin = s.kind == Kind::none || s.kind == Kind::rejected;
      if (thin && border) continue;
      for (std::size_t k = 0; k < s.ring.size(); ++k) {
        const auto& a = s.ring[k];
        const auto& b = s.ring[(k + 1) % s.ring.size()];
        const double ax = (a[0] - img.x0) / img.pixel, ay = (img.y1 - a[1]) / img.pixel;
        const double bx = (b[0] - img.x0) / img.pixel, by = (img.y1 - b[1]) / img.pixel;
        const int steps = std::max(1, static_cast<int>(std::ceil(2 * std::hypot(bx - ax, by - ay))));
        for (int t = 0; t <= steps; ++t) {
          const double f = static_cast<double>(t) / steps;
          if (border)
            plot(img, ax + f * (bx - ax), ay + f * (by - ay), 4, Rgb{0, 0, 0});
          else
            plot(img, ax + f * (bx - ax), ay + f * (by - ay), thin ? 1 : 2, colour_of(s.kind));
        }
      }
    }
  }
}

// The picture of a sized image: the heights painted (data pixels, gaps filled), the footprints
// outlined, the legend.
void draw(const std::vector<float>& top, const Footprints& footprints, const Params& params, Image& img) {
  img.rgb.assign(3 * static_cast<std::size_t>(img.width) * img.height, 250);
  paint(top, img);
  draw_outlines(footprints.shapes, img);
  if (params.legend) draw_legend(img, footprints, text_scale(img.map_height));
}

}  // namespace

Rgb height_colour(double height) {
  // viridis at 0, 1/4, 1/2, 3/4, 1
  static constexpr double stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  const double f = std::clamp(height / kRampTop, 0.0, 1.0) * 4;
  const int k = std::min(3, static_cast<int>(f));
  const double t = f - k;
  Rgb c;
  for (int i = 0; i < 3; ++i)
    c[i] = static_cast<std::uint8_t>(std::round(stops[k][i] + t * (stops[k + 1][i] - stops[k][i])));
  return c;
}

Rgb colour_of(Kind kind) {
  static constexpr Rgb colours[kKinds] = {kTruth, kMissed, kNone,  kRejected, kFailed,
                                          kClass, kModel,  kRight, kWrong,    kFalseAlarm};
  return colours[static_cast<int>(kind)];
}

const char* label_of(Kind kind) {
  static constexpr const char* labels[kKinds] = {
      "true vehicle", "true, missed", "none (no vehicle)", "rejected (reason)", "failed",
      "found: class", "found: model", "right answer",      "wrong answer",      "false alarm"};
  return labels[static_cast<int>(kind)];
}

void validate(const Params& params) {
  if (params.size != 0 && (params.size < 16 || params.size > kMaxSide))
    throw common::UsageError("--size must be in [16, 8192]");
  if (params.pixel != 0 && !(params.pixel >= 0.005 && params.pixel <= 100))
    throw common::UsageError("--pixel must be in [0.005, 100] m");
  if (params.pixel != 0 && params.size != 0) throw common::UsageError("give --pixel or --size, not both");
  if (params.tile < -1) throw common::UsageError("--tile must be >= 0");
}

std::optional<std::array<double, 4>> points_box(const formats::PointCloud& scan) {
  const Box b = finite_points_box(scan);
  if (!(b.x1 >= b.x0 && b.y1 >= b.y0)) return std::nullopt;
  return std::array<double, 4>{b.x0, b.y0, b.x1, b.y1};
}

Image render(const formats::PointCloud& scan, const Footprints& footprints, const Params& params) {
  validate(params);
  const Extent e = extent(scan, footprints.shapes);
  const Box& b = e.all;
  Image img;
  const Grid g = ground(scan, e.points, &img.density);
  size_picture(e.points, b, footprints, params, img);
  draw(heights(scan, g, img), footprints, params, img);
  return img;
}

formats::HeightRaster raster(const formats::PointCloud& scan, const Params& params) {
  validate(params);
  const Extent e = extent(scan, {});
  Image img;
  const Grid g = ground(scan, e.points, &img.density);
  size_picture(e.points, e.points, Footprints{}, params, img);
  formats::HeightRaster r;
  r.width = img.map_width / img.zoom;
  r.height = img.map_height / img.zoom;
  r.pixel = img.data_pixel;
  r.x0 = img.x0;
  r.y1 = img.y1;
  r.box_x0 = e.points.x0;
  r.box_y0 = e.points.y0;
  r.box_x1 = e.points.x1;
  r.box_y1 = e.points.y1;
  r.density = img.density;
  r.values = raw_heights(scan, g, img);
  return r;
}

Image render(const formats::HeightRaster& r, const Footprints& footprints, const Params& params) {
  validate(params);
  if (params.pixel > 0 || params.size > 0)
    throw common::UsageError("--pixel and --size are the raster's (topview --raster-out): not with --raster");
  Box points;
  points.add(r.box_x0, r.box_y0);
  points.add(r.box_x1, r.box_y1);
  Box b = points;
  for (const Shape& s : footprints.shapes) {
    for (const auto& p : s.ring) b.add(p[0], p[1]);
  }
  Image img;
  img.density = r.density;
  size_picture(points, b, footprints, params, img, r.pixel);
  if (img.grid_x0 != r.x0 || img.grid_y1 != r.y1)
    throw common::Error(
        "the height raster's corner is not its points' top-left corner (not written by topview)");
  // The raster's pixels where render() bins the points: shifted by the whole data pixels the
  // footprints widened the map by (the highest where the map's edge clamps two together).
  const int w = img.map_width / img.zoom, h = img.map_height / img.zoom;
  std::vector<float> top(static_cast<std::size_t>(w) * h, kEmpty);
  for (int row = 0; row < r.height; ++row) {
    const int rr = std::min(h - 1, img.grid_row + row);
    for (int col = 0; col < r.width; ++col) {
      const float v = r.at(col, row);
      if (std::isnan(v)) continue;
      float& t = top[static_cast<std::size_t>(rr) * w + std::min(w - 1, img.grid_col + col)];
      if (std::isnan(t) || v > t) t = v;
    }
  }
  fill_heights(top, img);
  draw(top, footprints, params, img);
  return img;
}

std::string encode_png(const Image& image, bool fast) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  if (fast) png.flags |= PNG_IMAGE_FLAG_FAST;
  // One pass into a buffer of libpng's bound (the default's size query compressed it twice).
  png_alloc_size_t bytes = PNG_IMAGE_PNG_SIZE_MAX(png);
  std::string out(bytes, '\0');
  if (!png_image_write_to_memory(&png, out.data(), &bytes, 0, image.rgb.data(), 0, nullptr)) {
    throw common::Error(std::string("PNG encoding failed: ") + png.message);
  }
  out.resize(bytes);
  return out;
}

}  // namespace canopy::topview
