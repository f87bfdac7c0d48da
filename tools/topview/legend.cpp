// The legend right of the map: north, the height ramp, the outline colours with their counts,
// a scale bar in metres, the pixel size and the density, in the built-in 5 x 7 font.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "topview/draw.h"

namespace canopy::topview {
namespace {

constexpr Rgb kInk{20, 20, 20};
constexpr int kMargin = 8;       // text-scale pixels around the panel's content
constexpr int kChars = 36;       // the widest line, in characters
constexpr int kRampWidth = 120;  // text-scale pixels: the ramp and the longest scale bar

enum class Row { text, ramp, ticks, swatch, bar, gap };
struct Line {
  Row row;
  std::string text;
  Kind kind = Kind::truth;
};

int row_height(Row r) { return r == Row::gap ? 5 : r == Row::ramp ? 12 : r == Row::bar ? 9 : 11; }

// The kinds the legend lists: every candidate outcome (a count of 0 says so), the truth's when
// given.
std::vector<Kind> kinds_listed(const Footprints& fp) {
  std::vector<Kind> k;
  const auto add = [&k](std::initializer_list<Kind> more) {
    for (const Kind m : more) k.push_back(m);
  };
  if (fp.truth) add({Kind::truth});
  if (fp.scored)
    add({Kind::missed, Kind::right, Kind::wrong, Kind::false_alarm});
  else
    add({Kind::model, Kind::cls});
  add({Kind::none, Kind::rejected, Kind::failed});
  return k;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// The rejected candidates' reasons under their swatch: the kMaxReasons most frequent (ties by
// name), the rest summed; a reason cut to 24 characters (the reasons are the input's text).
void add_reasons(const Footprints& fp, std::vector<Line>& l) {
  constexpr std::size_t kMaxReasons = 8;
  std::vector<std::pair<std::string, int>> r(fp.reasons.begin(), fp.reasons.end());
  std::stable_sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  int rest = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    if (k >= kMaxReasons) {
      rest += r[k].second;
      continue;
    }
    const std::string name = r[k].first.size() > 24 ? r[k].first.substr(0, 21) + "..." : r[k].first;
    l.push_back({Row::text, "   " + name + " " + std::to_string(r[k].second)});
  }
  if (rest > 0) l.push_back({Row::text, "   other reasons " + std::to_string(rest)});
}

std::vector<Line> layout(const Footprints& fp, const Image* img) {
  std::vector<Line> l{
      {Row::text, "^ north up"}, {Row::gap, ""}, {Row::text, "height above ground (m)"}, {Row::ramp, ""},
      {Row::ticks, ""},          {Row::gap, ""}, {Row::text, "outlines (count)"}};
  for (const Kind k : kinds_listed(fp)) {
    const auto n =
        std::count_if(fp.shapes.begin(), fp.shapes.end(), [k](const Shape& s) { return s.kind == k; });
    l.push_back({Row::swatch, std::string(label_of(k)) + " " + std::to_string(n), k});
    if (k == Kind::rejected) add_reasons(fp, l);
  }
  if (fp.undrawn > 0) l.push_back({Row::text, "rejected, no index: " + std::to_string(fp.undrawn)});
  l.push_back({Row::gap, ""});
  l.push_back({Row::bar, ""});
  l.push_back({Row::text, img ? fixed(img->bar_metres, img->bar_metres < 1 ? 2 : 0) + " m" : ""});
  l.push_back({Row::gap, ""});
  // The data pixel (one height value; --pixel sets it), not the map pixel it is drawn zoomed to:
  // "pixel 0.076 m" on a plot whose heights are 0.38 m cells read as a resolution it does not have.
  l.push_back({Row::text, img ? "pixel " + fixed(img->data_pixel, img->data_pixel < 0.1 ? 3 : 2) + " m" : ""});
  l.push_back({Row::text, img ? fixed(img->density, 1) + " points/m2" : ""});
  l.push_back({Row::swatch, "no point", Kind::truth});  // drawn as kNoData
  return l;
}

// The longest round length (1, 2 or 5 x 10^k m) whose bar fits in `most` pixels.
double bar_length(double pixel, int most) {
  double best = 0.001;
  for (int e = -3; e <= 5; ++e) {
    for (const double m : {1.0, 2.0, 5.0}) {
      const double len = m * std::pow(10.0, e);
      if (len / pixel <= most) best = len;
    }
  }
  return best;
}

void draw_ramp(Image& img, int col, int row, int s) {
  const int w = kRampWidth * s;
  for (int x = 0; x < w; ++x) fill_rect(img, col + x, row, 1, 9 * s, height_colour(kRampTop * x / (w - 1)));
}

void draw_ticks(Image& img, int col, int row, int s) {
  const int w = kRampWidth * s;
  for (int m = 0; m <= static_cast<int>(kRampTop); ++m) {
    const int x = col + static_cast<int>(std::lround(m / kRampTop * (w - 1)));
    fill_rect(img, x, row - 3 * s, s, 2 * s, kInk);
    const std::string label = std::to_string(m) + (m == static_cast<int>(kRampTop) ? "+" : "");
    draw_text(img, std::max(col, x - 2 * s), row, label, s, kInk);
  }
}

void draw_swatch(Image& img, int col, int row, int s, const Line& line) {
  const bool nodata = line.text == "no point";
  fill_rect(img, col, row, 14 * s, 7 * s, Rgb{0, 0, 0});
  fill_rect(img, col + s, row + s, 12 * s, 5 * s, nodata ? kNoData : colour_of(line.kind));
  draw_text(img, col + 18 * s, row, line.text, s, kInk);
}

// A black bar with end ticks; records it in img.
void draw_bar(Image& img, int col, int row, int s) {
  img.bar_metres = bar_length(img.pixel, kRampWidth * s);
  img.bar_pixels = std::max(1, static_cast<int>(std::lround(img.bar_metres / img.pixel)));
  img.bar_col = col;
  img.bar_row = row + 5 * s;
  fill_rect(img, col, row + 4 * s, img.bar_pixels, 3 * s, Rgb{0, 0, 0});
  fill_rect(img, col, row, std::min(img.bar_pixels, s), 4 * s, Rgb{0, 0, 0});
  fill_rect(img, col + img.bar_pixels - std::min(img.bar_pixels, s), row, std::min(img.bar_pixels, s), 4 * s,
            Rgb{0, 0, 0});
}

}  // namespace

void fill_rect(Image& img, int col, int row, int width, int height, const Rgb& colour) {
  for (int r = std::max(0, row); r < std::min(img.height, row + height); ++r) {
    for (int c = std::max(0, col); c < std::min(img.width, col + width); ++c) {
      const std::size_t i = 3 * (static_cast<std::size_t>(r) * img.width + c);
      std::copy(colour.begin(), colour.end(), img.rgb.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
}

void draw_text(Image& img, int col, int row, const std::string& text, int scale, const Rgb& colour) {
  for (std::size_t k = 0; k < text.size(); ++k) {
    const int left = col + static_cast<int>(k) * (kGlyphWidth + 1) * scale;
    for (int r = 0; r < kGlyphHeight; ++r) {
      for (int c = 0; c < kGlyphWidth; ++c) {
        if (glyph_ink(text[k], c, r)) fill_rect(img, left + c * scale, row + r * scale, scale, scale, colour);
      }
    }
  }
}

std::vector<std::string> legend_text(const Footprints& footprints, const Image& img) {
  std::vector<std::string> out;
  for (const Line& l : layout(footprints, &img)) {
    if (l.row == Row::text) out.push_back(l.text);
  }
  return out;
}

Panel legend_size(const Footprints& footprints, int scale) {
  int h = 2 * kMargin;
  for (const Line& l : layout(footprints, nullptr)) h += row_height(l.row);
  return {(2 * kMargin + kChars * (kGlyphWidth + 1)) * scale, h * scale};
}

void draw_legend(Image& img, const Footprints& footprints, int scale) {
  const int s = scale, col = img.map_width + kMargin * s;
  // The bar's length first: its label is a line of the layout.
  img.bar_metres = bar_length(img.pixel, kRampWidth * s);
  int row = kMargin * s;
  for (const Line& l : layout(footprints, &img)) {
    switch (l.row) {
      case Row::text: draw_text(img, col, row, l.text, s, kInk); break;
      case Row::ramp: draw_ramp(img, col, row, s); break;
      case Row::ticks: draw_ticks(img, col, row, s); break;
      case Row::swatch: draw_swatch(img, col, row, s, l); break;
      case Row::bar: draw_bar(img, col, row, s); break;
      case Row::gap: break;
    }
    row += row_height(l.row) * s;
  }
}

}  // namespace canopy::topview
