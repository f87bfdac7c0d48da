// tile_grid: PNG tiles in a labelled grid. Text is rasterised by VTK's FreeType text renderer
// on the CPU (no OpenGL, no X display).
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>

#include <algorithm>

#include "canopy/common/error.h"
#include "figures/figures.h"

namespace canopy::figures {
namespace {

// Text rasterised to an RGBA bitmap, rows top to bottom.
struct Text {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
};

Text rasterise(const std::string& text, int size, bool bold) {
  Text out;
  if (text.empty()) return out;
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  if (renderer == nullptr) throw common::Error("VTK has no text renderer (RenderingFreeType missing)");
  vtkNew<vtkTextProperty> prop;
  prop->SetFontFamilyToArial();
  prop->SetFontSize(size);
  prop->SetBold(bold);
  prop->SetColor(0, 0, 0);
  prop->SetJustificationToLeft();
  prop->SetVerticalJustificationToBottom();
  vtkNew<vtkImageData> image;
  int dims[2] = {0, 0};
  if (!renderer->RenderString(prop, vtkStdString(text), image, dims, 72)) {
    throw common::Error("cannot render the text '" + text + "'");
  }
  int extent[6];
  image->GetExtent(extent);
  const int w = extent[1] - extent[0] + 1, h = extent[3] - extent[2] + 1;
  if (w <= 0 || h <= 0 || image->GetNumberOfScalarComponents() != 4) return out;
  out.width = std::min(w, dims[0] > 0 ? dims[0] : w);
  out.height = std::min(h, dims[1] > 0 ? dims[1] : h);
  out.rgba.resize(4 * static_cast<std::size_t>(out.width) * out.height);
  const auto* src = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (int y = 0; y < out.height; ++y) {  // VTK row 0 is the bottom
    for (int x = 0; x < out.width; ++x) {
      const unsigned char* p = src + 4 * (static_cast<std::size_t>(y) * w + x);
      std::copy(p, p + 4, &out.rgba[4 * (static_cast<std::size_t>(out.height - 1 - y) * out.width + x)]);
    }
  }
  return out;
}

struct Clip {
  int x0, y0, x1, y1;  // half-open
};

// Alpha-blends text onto the image with its top-left corner at (x0, y0), clipped to `clip`.
void draw(Image& image, const Text& text, int x0, int y0, Clip clip) {
  clip = {std::max(0, clip.x0), std::max(0, clip.y0), std::min(image.width, clip.x1),
          std::min(image.height, clip.y1)};
  for (int y = 0; y < text.height; ++y) {
    for (int x = 0; x < text.width; ++x) {
      const int px = x0 + x, py = y0 + y;
      if (px < clip.x0 || py < clip.y0 || px >= clip.x1 || py >= clip.y1) continue;
      const std::uint8_t* t = &text.rgba[4 * (static_cast<std::size_t>(y) * text.width + x)];
      std::uint8_t* q = image.at(px, py);
      for (int k = 0; k < 3; ++k)
        q[k] = static_cast<std::uint8_t>((t[k] * t[3] + q[k] * (255 - t[3]) + 127) / 255);
    }
  }
}

void fill(Image& image, int x0, int y0, int w, int h, std::array<std::uint8_t, 3> c) {
  for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y) {
    for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x) {
      std::copy(c.begin(), c.end(), image.at(x, y));
    }
  }
}

// Copies the tile centred into the cell at (x0, y0) of size w x h, clipped to the cell.
void blit(Image& image, const Image& tile, int x0, int y0, int w, int h) {
  const int dx = (w - tile.width) / 2, dy = (h - tile.height) / 2;
  for (int y = 0; y < tile.height; ++y) {
    const int cy = y + dy;
    if (cy < 0 || cy >= h) continue;
    for (int x = 0; x < tile.width; ++x) {
      const int cx = x + dx;
      if (cx < 0 || cx >= w) continue;
      std::copy(tile.at(x, y), tile.at(x, y) + 3, image.at(x0 + cx, y0 + cy));
    }
  }
}

// Union over the present tiles of the boxes of non-background pixels: {x0, y0, x1, y1}
// (inclusive), in the coordinates of a tile of the first tile's size; nullopt when every
// tile is plain background.
std::optional<std::array<int, 4>> content_box(const std::vector<std::optional<Image>>& cells) {
  std::optional<std::array<int, 4>> box;
  for (const auto& cell : cells) {
    if (!cell) continue;
    const std::uint8_t* bg = cell->at(0, 0);
    for (int y = 0; y < cell->height; ++y) {
      for (int x = 0; x < cell->width; ++x) {
        const std::uint8_t* p = cell->at(x, y);
        if (p[0] == bg[0] && p[1] == bg[1] && p[2] == bg[2]) continue;
        if (!box) box = std::array<int, 4>{x, y, x, y};
        auto& b = *box;
        b[0] = std::min(b[0], x), b[1] = std::min(b[1], y), b[2] = std::max(b[2], x), b[3] = std::max(b[3], y);
      }
    }
  }
  return box;
}

Image crop(const Image& image, int x0, int y0, int w, int h) {
  Image out(w, h, {image.at(0, 0)[0], image.at(0, 0)[1], image.at(0, 0)[2]});
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x0 + x < 0 || y0 + y < 0 || x0 + x >= image.width || y0 + y >= image.height) continue;
      std::copy(image.at(x0 + x, y0 + y), image.at(x0 + x, y0 + y) + 3, out.at(x, y));
    }
  }
  return out;
}

}  // namespace

Image tile_grid(const std::vector<std::optional<Image>>& cells, const GridParams& params) {
  if (params.cols < 1) throw common::UsageError("--cols must be at least 1");
  if (cells.empty()) throw common::UsageError("no cells to tile");
  const int cols = params.cols;
  const int rows = static_cast<int>((cells.size() + cols - 1) / cols);
  if (!params.row_labels.empty() && static_cast<int>(params.row_labels.size()) != rows) {
    throw common::UsageError(std::to_string(params.row_labels.size()) + " row labels for " +
                             std::to_string(rows) + " rows (" + std::to_string(cells.size()) + " cells in " +
                             std::to_string(cols) + " columns)");
  }
  if (!params.col_labels.empty() && static_cast<int>(params.col_labels.size()) != cols) {
    throw common::UsageError(std::to_string(params.col_labels.size()) + " column labels for " +
                             std::to_string(cols) + " columns");
  }
  const auto first = std::find_if(cells.begin(), cells.end(), [](const auto& c) { return c.has_value(); });
  if (first == cells.end()) throw common::Error("every cell is missing: no image to tile");
  int cw = (*first)->width, ch = (*first)->height;
  std::vector<std::optional<Image>> trimmed;
  if (params.trim) {
    if (const auto box = content_box(cells)) {
      const int m = std::max(0, params.margin);
      const int x0 = std::max(0, (*box)[0] - m), y0 = std::max(0, (*box)[1] - m);
      const int x1 = std::min(cw - 1, (*box)[2] + m), y1 = std::min(ch - 1, (*box)[3] + m);
      for (const auto& cell : cells) {
        trimmed.push_back(
            cell ? std::optional<Image>(crop(*cell, x0 + (cell->width - cw) / 2, y0 + (cell->height - ch) / 2,
                                             x1 - x0 + 1, y1 - y0 + 1))
                 : std::nullopt);
      }
      cw = x1 - x0 + 1;
      ch = y1 - y0 + 1;
    }
  }
  const auto& tiles = trimmed.empty() ? cells : trimmed;
  const int gap = std::max(0, params.gap), pad = std::max(4, params.font_size / 2);

  std::vector<Text> row_text, col_text;
  int left = 0, top = 0;
  for (const auto& s : params.row_labels) {
    row_text.push_back(rasterise(s, params.font_size, true));
    left = std::max(left, row_text.back().width + 2 * pad);
  }
  for (const auto& s : params.col_labels) {
    col_text.push_back(rasterise(s, params.font_size, true));
    top = std::max(top, col_text.back().height + pad);
  }
  const Text title = rasterise(params.title, params.font_size + 4, true);
  const int title_h = params.title.empty() ? 0 : title.height + pad;
  top += title_h;

  Image out(left + cols * cw + (cols + 1) * gap, top + rows * ch + (rows + 1) * gap);
  const Clip all{0, 0, out.width, out.height};
  if (!params.title.empty()) draw(out, title, (out.width - title.width) / 2, pad / 2, all);
  for (int c = 0; c < static_cast<int>(col_text.size()); ++c) {
    const int x = left + gap + c * (cw + gap) + (cw - col_text[c].width) / 2;
    draw(out, col_text[c], x, top - col_text[c].height - pad / 2, all);
  }
  for (int r = 0; r < static_cast<int>(row_text.size()); ++r) {
    const int y = top + gap + r * (ch + gap) + (ch - row_text[r].height) / 2;
    draw(out, row_text[r], left - pad - row_text[r].width, y, all);
  }
  const Text failed = rasterise("failed", params.font_size, false);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int r = static_cast<int>(i) / cols, c = static_cast<int>(i) % cols;
    const int x0 = left + gap + c * (cw + gap), y0 = top + gap + r * (ch + gap);
    if (tiles[i]) {
      blit(out, *tiles[i], x0, y0, cw, ch);
    } else {
      fill(out, x0, y0, cw, ch, {232, 232, 232});
      draw(out, failed, x0 + (cw - failed.width) / 2, y0 + (ch - failed.height) / 2,
           Clip{x0, y0, x0 + cw, y0 + ch});
    }
  }
  return out;
}

}  // namespace canopy::figures
