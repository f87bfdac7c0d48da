// topview's drawing helpers shared by its source files (not a public interface).
#pragma once

#include "topview/topview.h"

namespace canopy::topview {

// The legend panel at text scale `scale` (1 = the 5 x 7 font at one pixel a dot): its size
// for the footprints and the picture's pixel size.
struct Panel {
  int width = 0, height = 0;
};
Panel legend_size(const Footprints& footprints, int scale);

// Draws the legend into the panel right of the map (columns from img.map_width) and records
// the scale bar in img.
void draw_legend(Image& img, const Footprints& footprints, int scale);

// Text in the 5 x 7 font, each dot `scale` x `scale` pixels, its top-left corner at (col, row);
// clipped to the picture.
void draw_text(Image& img, int col, int row, const std::string& text, int scale, const Rgb& colour);

void fill_rect(Image& img, int col, int row, int width, int height, const Rgb& colour);

}  // namespace canopy::topview
