// detect's shape test (step 4 of detect.h, docs/decisions/detect.md §3b): vehicles are made of
// planes, vegetation (bush groups, crown pieces) is volumetric scatter.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detect/detect.h"
#include "detect/frame.h"
#include "detect/objects.h"

namespace canopy::detect {

// How much of the surface of the points `pts` (rows of the local frame `l`) lies in locally
// planar neighbourhoods of `radius`: a neighbourhood is planar when sqrt(l3 / l2) <= `ratio`
// of its covariance's eigenvalues.
Shape planar_shape(const LocalFrame& l, const std::vector<std::uint32_t>& pts, double radius, double ratio);

// The objects that pass the shape test (each with its shape set), in order, and how many did not.
struct ShapeTest {
  std::vector<Object> kept;
  std::size_t rejected = 0;
};

// An object is vegetation when its planar share is below params.min_planarity (> 0) and its
// planar area below params.min_planar_area; a vehicle under a bush keeps its panels' area.
ShapeTest shape_test(std::vector<Object> objects, const LocalFrame& l, const Params& params);

}  // namespace canopy::detect
