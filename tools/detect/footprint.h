// A cluster's footprint: the minimum-area rectangle enclosing its top view
// (docs/decisions/detect.md §3, "Footprint").
#pragma once

#include <Eigen/Core>

#include <vector>

namespace canopy::detect {

struct Footprint {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // local frame
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();   // unit, long side
  double length = 0, width = 0;
};

// Minimum-area enclosing rectangle: one side lies on a hull edge (Freeman & Shapira 1975);
// axis canonical (heading in (-pi/2, pi/2]).
Footprint min_area_rectangle(const std::vector<Eigen::Vector2d>& points);

}  // namespace canopy::detect
