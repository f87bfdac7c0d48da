// A tile's images: flight-line views and the nadir canopy view, their sizes fitted to the tile,
// and the pixel budget checked before anything renders. No terrain, POV-Ray or file here, so
// that the recipe reader (and its fuzzer) can check the budget.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/geometry.h"
#include "canopy/common/math.h"
#include "canopy/common/units.h"
#include "canopy/sim/tile.h"

namespace canopy::sim {

using common::Error;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// Area of the convex polygon `poly` clipped to the half-plane n . p <= d.
std::vector<Vector2d> clip(const std::vector<Vector2d>& poly, const Vector2d& n, double d) {
  std::vector<Vector2d> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
    const double da = n.dot(a) - d, db = n.dot(b) - d;
    if (da <= 0) out.push_back(a);
    if ((da < 0) != (db < 0) && da != db) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

double area(const std::vector<Vector2d>& poly) {
  double a = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vector2d p = poly[i], q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return std::abs(a) / 2;
}

// Fits the orthographic image of `corners` seen along -toward, with the image plane through
// `anchor` (which must lie beyond every corner along toward).
TileView fit_view(const Vector3d& toward, const Vector3d& right, const Vector3d& anchor,
                  const std::vector<Vector3d>& corners, double spacing) {
  TileView v;
  v.toward = toward;
  v.right = right;
  v.up = toward.cross(right).normalized();
  v.spacing = spacing;
  double r0 = 1e18, r1 = -1e18, u0 = 1e18, u1 = -1e18, d0 = 1e18, d1 = -1e18;
  for (const auto& c : corners) {
    const Vector3d d = c - anchor;
    r0 = std::min(r0, d.dot(v.right));
    r1 = std::max(r1, d.dot(v.right));
    u0 = std::min(u0, d.dot(v.up));
    u1 = std::max(u1, d.dot(v.up));
    d0 = std::min(d0, -d.dot(toward));
    d1 = std::max(d1, -d.dot(toward));
  }
  const double w = std::ceil((r1 - r0) / spacing), h = std::ceil((u1 - u0) / spacing);
  // The size asked for; check_tile_budget refuses it before anything renders when too large.
  v.pixels_x = std::max(1.0, w);
  v.pixels_y = std::max(1.0, h);
  v.width = static_cast<int>(std::min(v.pixels_x, kMaxImageSide));
  v.height = static_cast<int>(std::min(v.pixels_y, kMaxImageSide));
  v.origin = anchor + (r0 + r1) / 2 * v.right + (u0 + u1) / 2 * v.up;
  if (!(d0 > 0.5)) throw Error("internal: the image plane does not lie above the tile");
  v.depth_lo = d0 - 0.5;
  v.depth_span = d1 - d0 + 1.0;
  return v;
}

}  // namespace

std::vector<TileView> tile_views(const TileRecipe& r, double ground_lo, double top) {
  const double zlo = ground_lo - 1, zhi = top + 1;
  const Vector2d tile_corners[4] = {{0, 0}, {r.extent_x, 0}, {r.extent_x, r.extent_y}, {0, r.extent_y}};
  std::vector<TileView> views;
  for (std::size_t h = 0; h < r.headings.size(); ++h) {
    const Vector2d f(std::cos(r.headings[h]), std::sin(r.headings[h])), c(-f.y(), f.x());
    const common::Extent2 e = common::extent_along(tile_corners, f, c);
    const double a0 = e.umin, a1 = e.umax, c0 = e.vmin, c1 = e.vmax;
    const double pitch = (c1 - c0) / r.flight_lines;
    for (int line = 0; line < r.flight_lines; ++line) {
      const double cc = c0 + (line + 0.5) * pitch;
      const double half = pitch / 2 * (1 + r.swath_overlap);
      const Vector2d centre = (a0 + a1) / 2 * f + cc * c;
      std::vector<Vector3d> corners;
      for (double a : {a0, a1}) {
        for (double w : {cc - half, cc + half}) {
          for (double z : {zlo, zhi}) {
            const Vector2d p = a * f + w * c;
            corners.emplace_back(p.x(), p.y(), z);
          }
        }
      }
      std::vector<Vector2d> strip(std::begin(tile_corners), std::end(tile_corners));
      strip = clip(strip, c, cc + half);
      strip = clip(strip, -c, -(cc - half));
      for (std::size_t l = 0; l < r.looks.size(); ++l) {
        const Look& look = r.looks[l];
        const double az = r.headings[h] + look.azimuth;
        const bool nadir = std::abs(look.elevation - common::kPi / 2) < 1e-9;
        const Vector3d toward =
            nadir ? Vector3d::UnitZ()
                  : Vector3d(std::cos(look.elevation) * std::cos(az), std::cos(look.elevation) * std::sin(az),
                             std::sin(look.elevation));
        const Vector3d right = nadir ? Vector3d(c.x(), c.y(), 0) : Vector3d(-std::sin(az), std::cos(az), 0);
        const Vector3d anchor =
            Vector3d(centre.x(), centre.y(), 0) + (r.altitude / std::sin(look.elevation)) * toward;
        TileView v = fit_view(toward, right, anchor, corners, r.spacing);
        v.strip_centre = centre;
        v.strip_across = c;
        v.strip_half = half;
        v.line = line;
        v.heading_idx = static_cast<int>(h);
        v.look_idx = static_cast<int>(l);
        v.strip_area = area(strip);
        views.push_back(v);
      }
    }
  }
  return views;
}

TileView canopy_view(const TileRecipe& r, double ground_lo, double top) {
  std::vector<Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back(i & 1 ? r.extent_x : 0, i & 2 ? r.extent_y : 0, i & 4 ? top + 1 : ground_lo - 1);
  }
  const Vector3d anchor(r.extent_x / 2, r.extent_y / 2, r.altitude);
  TileView v = fit_view(Vector3d::UnitZ(), Vector3d::UnitX(), anchor, corners, r.canopy_spacing);
  v.strip_centre = Vector2d(r.extent_x / 2, r.extent_y / 2);
  v.strip_across = Vector2d(0, 1);
  v.strip_half = r.extent_y;
  v.strip_area = r.extent_x * r.extent_y;
  return v;
}

std::vector<TileView> tile_views(const Tile& tile) {
  return tile_views(tile.recipe, TerrainModel(tile.recipe, tile.seed).lo(), tile.top);
}

TileView canopy_view(const Tile& tile) {
  return canopy_view(tile.recipe, TerrainModel(tile.recipe, tile.seed).lo(), tile.top);
}

namespace {

// 12000, or 1.2e9 for large counts.
std::string short_num(double v) {
  char buf[32];
  if (v < 1e5) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  int e = static_cast<int>(std::floor(std::log10(v)));
  double m = std::round(v / std::pow(10.0, e) * 10) / 10;
  if (m >= 10) m /= 10, ++e;
  std::snprintf(buf, sizeof buf, "%.2ge%d", m, e);
  return buf;
}

std::string bytes(double b) {
  char buf[32];
  if (b >= 1e9) {
    std::snprintf(buf, sizeof buf, "%.3g GB", b / 1e9);
  } else {
    std::snprintf(buf, sizeof buf, "%.3g MB", b / 1e6);
  }
  return buf;
}

// The first of `keys` the recipe gives, as "line N: " ("" when none is given).
std::string line_of(const TileRecipe& r, std::initializer_list<const char*> keys) {
  for (const char* k : keys) {
    const auto it = r.lines.find(k);
    if (it != r.lines.end()) return "line " + std::to_string(it->second) + ": ";
  }
  return "";
}

}  // namespace

void check_tile_budget(const std::vector<TileView>& views, const TileRecipe& r, const std::string& name) {
  double canopy = 0, scan = 0;
  for (std::size_t k = 0; k < views.size(); ++k)
    (k == 0 ? canopy : scan) += views[k].pixels_x * views[k].pixels_y;
  const double total = canopy + scan;
  const std::size_t n = views.size() - 1;
  const std::string what = std::to_string(n) + (n == 1 ? " image" : " images") +
                           " and the canopy image have " + short_num(total) +
                           " pixels in all (up to as many points: about " + bytes(180 * total) +
                           " of memory, " + bytes(6 * total) + " of frames in TMPDIR)";
  if (total > kMaxTilePixels) {
    if (canopy >= scan) {
      const double room = std::max(kMaxTilePixels - scan, kMaxTilePixels / 2);
      const double at_least = std::ceil(1000 * r.canopy_spacing * std::sqrt(canopy / room)) / 1000;
      throw common::DataError(name, line_of(r, {"canopy_spacing", "extent"}) + "canopy_spacing " +
                                        common::format_length(r.canopy_spacing) + ": " + what +
                                        "; a tile may have at most " + short_num(kMaxTilePixels) +
                                        ": use a canopy_spacing of at least " +
                                        common::format_length(at_least));
    }
    const double room = std::max(kMaxTilePixels - canopy, kMaxTilePixels / 2);
    const double at_least = std::ceil(1000 * r.spacing * std::sqrt(scan / room)) / 1000;
    throw common::DataError(
        name, line_of(r, {"spacing", "extent", "looks", "headings", "flight_lines", "swath_overlap"}) +
                  "spacing " + common::format_length(r.spacing) + ": " + what + "; a tile may have at most " +
                  short_num(kMaxTilePixels) + ": use a spacing of at least " + common::format_length(at_least) +
                  ", a smaller extent, or fewer headings, looks or flight lines");
  }
  for (std::size_t k = 0; k < views.size(); ++k) {
    const TileView& v = views[k];
    if (v.pixels_x > kMaxImageSide || v.pixels_y > kMaxImageSide) {
      const bool nadir = k == 0;
      throw common::DataError(
          name, line_of(r, nadir ? std::initializer_list<const char*>{"canopy_spacing", "extent"}
                                 : std::initializer_list<const char*>{"spacing", "extent"}) +
                    (nadir ? "the canopy image" : "an image") + " of " + short_num(v.pixels_x) + " x " +
                    short_num(v.pixels_y) + " pixels is over " + short_num(kMaxImageSide) +
                    " a side: use a coarser spacing or more flight lines");
    }
  }
}

}  // namespace canopy::sim
