// topview: a tile seen from straight above (the highest point per pixel, grey by height) with
// footprints drawn over it: truth vehicles, detections, and with a score their outcome
// (docs/decisions/scene-experiment.md).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::topview {

using Rgb = std::array<std::uint8_t, 3>;
using Ring = std::vector<std::array<double, 2>>;

// Outline colours.
inline constexpr Rgb kTruth{255, 255, 255};     // a true vehicle (found)
inline constexpr Rgb kMissed{255, 220, 0};      // a true vehicle nothing matched
inline constexpr Rgb kDetection{0, 200, 255};   // a detection, no score given
inline constexpr Rgb kRight{0, 220, 0};         // matched, right model
inline constexpr Rgb kWrong{255, 140, 0};       // matched, wrong model
inline constexpr Rgb kFalseAlarm{230, 0, 230};  // matched nothing

struct Shape {
  Ring ring;  // tile coordinates
  Rgb colour;
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;     // row-major from the top (north) row, 3 bytes a pixel
  double x0 = 0, y1 = 0, pixel = 1;  // x of the left edge, y of the top edge, metres a pixel
  Rgb at(int col, int row) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(row) * width + col);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

// The picture: `size` pixels along the longer side of the box holding the points and shapes.
Image render(const formats::PointCloud& scan, const std::vector<Shape>& shapes, int size);
std::string encode_png(const Image& image);

}  // namespace canopy::topview
