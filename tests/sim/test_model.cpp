// The simulator's frame conversion (canopy/sim/model.h): world (right-handed, z up) <->
// POV-Ray (left-handed, y up).
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include "canopy/sim/model.h"

using canopy::sim::pov_frame;
using Eigen::Vector3d;

TEST_CASE("pov_frame swaps y and z and is its own inverse") {
  const Vector3d w(1.5, -2.25, 0.75);
  CHECK(pov_frame(w) == Vector3d(1.5, 0.75, -2.25));
  CHECK(pov_frame(pov_frame(w)) == w);
  // Right-handed x cross y = z becomes, in the POV-Ray frame, the left-handed relation.
  const Vector3d px = pov_frame(Vector3d::UnitX()), py = pov_frame(Vector3d::UnitY()),
                 pz = pov_frame(Vector3d::UnitZ());
  CHECK(px.cross(py).dot(pz) == Approx(-1.0));
}
