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

struct Params {
  int size = 1024;  // pixels along the longer side of the picture, [16, 8192]
  int tile = 0;     // this tile's index in the score's tiles, >= 0
};

// Throws common::UsageError naming the option: --size must be in [16, 8192], --tile >= 0.
void validate(const Params& params);

// The documents whose footprints are drawn (paths; truth and score empty = not given; a score
// needs the truth).
struct Sources {
  std::string detections;  // canopy.detections v1
  std::string truth;       // canopy.scene_truth v1: true footprints
  std::string score;       // canopy.scene_score v1: colours by outcome
};

// Reads the documents: the true footprints first (kTruth, or kMissed when the score says the
// tile's vehicle was missed), then the detections (kDetection, or with a score kRight, kWrong,
// kFalseAlarm by the outcome of the candidate). DataError naming the file and the member: not
// JSON, another format, a version other than 1, no "detections" / "vehicles" / "tiles" /
// "matches" array, no tile `tile` in the score, a detection without a string "candidate", a
// vehicle without an integer "instance" >= 0, a match without "tile" (an index of "tiles") or
// "outcome" (right, wrong, false_alarm, missed), a missed match without "instance", another
// match without a string "candidate", a footprint that is not a polygon of 3-64 [x, y] corners.
std::vector<Shape> read_footprints(const Sources& sources, int tile);

// The picture (render at Params::size; `tile` is read_footprints'), validate()d first.
Image run(const formats::PointCloud& scan, const std::vector<Shape>& shapes, const Params& params);

// The picture: `size` pixels along the longer side of the box holding the points and shapes.
// The highest point per pixel (non-finite points skipped), grey from the 2nd to the 98th
// percentile of those heights, then the outlines two pixels wide in the given order.
Image render(const formats::PointCloud& scan, const std::vector<Shape>& shapes, int size);
std::string encode_png(const Image& image);

}  // namespace canopy::topview
