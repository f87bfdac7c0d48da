// A synthetic vehicle-like scan for the fitvox benchmark and the adaptive-RMS measurement,
// generated in code (independent of rangetrace): a tank-like union of boxes on the ground
// plane z = 0 under 500 foliage discs (radius 100 mm, random orientation, in a band from the
// vehicle top to 2 m above it, over 12.2 m x 12.2 m), seen by orthographic views of 512 x 512
// rays at 30 mm spacing from 12 azimuths at 75 deg elevation (the thesis "circle" scene),
// nearest hit per ray, cropped to a 10 x 4 x 4 m box centred on the vehicle, plus isotropic
// Gaussian noise. Labels: 1 target, 2 foliage, 3 ground.
#pragma once

#include <cstdint>

#include "fitvox/fitvox.h"

namespace fitvox_bench {

struct SceneOptions {
  double sigma = 0;        // noise (m)
  std::uint64_t seed = 1;  // geometry (foliage) seed; the noise uses a seed derived from it
  int views = 12;
  int pixels = 512;
  double spacing = 0.03;  // m between rays
  double elevation_deg = 75;
  int discs = 500;
};

canopy::fitvox::Scan synth_scan(const SceneOptions& options);

}  // namespace fitvox_bench
