// The vehicle classes of canopy's taxonomy and their groups (docs/decisions/families.md §2): the
// twelve families classify sizes (tools/classify class_ranges()) and collect compares by group
// (collect --contradiction-level group). One table, read by both tools (a tool may not link
// another's library: docs/decisions/structure.md).
#pragma once

#include <string>
#include <vector>

namespace canopy::common {

struct VehicleClass {
  std::string name, group;
};

// The twelve families in tools/rangetrace/families.cpp's order, with their groups:
// car = sedan, hatchback, suv, pickup; van = van; truck = box-truck, semi-tractor; bus = bus;
// machine = wheeled-apc, wheel-loader; tracked = tracked-apc, tank.
const std::vector<VehicleClass>& vehicle_classes();
// The group of a family's name, "" for any other name.
std::string family_group(const std::string& cls);
// The group of any class name: a family's group, a group's own name (car, van, truck, bus,
// tracked, machine) itself, any other name (a modelbase's class of its own) itself.
std::string class_group(const std::string& cls);

}  // namespace canopy::common
