// Procedural vehicle families (issue 17): a seeded generator of POV-Ray CSG vehicles of twelve
// classes with the built-in models' conventions (metres, ground at y = 0, centred on the
// origin, front toward +x, one object `Vehicle`, no textures). Overall dimensions and part
// proportions are drawn from ranges that real vehicles of the class span
// (docs/decisions/families.md). An instance is named by (class, instance number); the same
// pair gives the same text on every platform (common::Rng, fixed-precision printing).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canopy::sim {

struct FamilyRange {
  double lo = 0, hi = 0;  // m
};

// One class: its name and the ranges of its overall bounding box (length along x including
// any gun or bucket, width across without mirrors, height to the highest part).
struct FamilyClass {
  const char* name;
  FamilyRange length, width, height;
};

// The classes in a fixed order (sedan, hatchback, suv, pickup, van, box-truck, semi-tractor,
// bus, wheeled-apc, tracked-apc, tank, wheel-loader).
const std::vector<FamilyClass>& family_classes();

// A generated instance: its class, number, model name ("<class>-<instance>"), the bounding
// box of its parts (world frame: x forward, y left, z up; from the primitives' extents, as
// POV-Ray's min/max_extent computes them) and the POV-Ray code declaring Vehicle.
struct FamilyInstance {
  std::string vehicle_class;
  int instance = 0;
  std::string name;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  std::string pov;
};

// Instance `instance` (0 <= instance <= 999999999) of class `vehicle_class`; a UsageError
// naming the classes for an unknown class.
FamilyInstance make_family_instance(const std::string& vehicle_class, int instance);

// "family:<class>:<instance>" specs (the --model syntax).
bool is_family_spec(const std::string& spec);
// Parses a family spec; UsageError naming the problem.
FamilyInstance family_from_spec(const std::string& spec);

}  // namespace canopy::sim
