// The vehicle taxonomy (common/vehicle_classes.h): the twelve families and their groups, which
// classify's class ranges and collect's contradiction by group both read.
#include <catch2/catch.hpp>

#include <set>
#include <string>
#include <vector>

#include "canopy/common/vehicle_classes.h"

using namespace canopy;

TEST_CASE("vehicle taxonomy: the twelve families in families.cpp's order, each with its group") {
  std::vector<std::string> names, groups;
  for (const common::VehicleClass& k : common::vehicle_classes()) {
    names.push_back(k.name);
    groups.push_back(k.group);
  }
  CHECK(names == std::vector<std::string>{"sedan", "hatchback", "suv", "pickup", "van", "box-truck",
                                          "semi-tractor", "bus", "wheeled-apc", "tracked-apc", "tank",
                                          "wheel-loader"});
  CHECK(groups == std::vector<std::string>{"car", "car", "car", "car", "van", "truck", "truck", "bus",
                                           "machine", "tracked", "tracked", "machine"});
  // Six groups; no family is named like another family's group but its own (van, bus).
  const std::set<std::string> group_set(groups.begin(), groups.end());
  CHECK(group_set == std::set<std::string>{"car", "van", "truck", "bus", "machine", "tracked"});
  for (const common::VehicleClass& k : common::vehicle_classes())
    if (group_set.count(k.name) != 0) CHECK(k.name == k.group);
}

TEST_CASE("vehicle taxonomy: a family's group, a group's own name, any other name its own group") {
  CHECK(common::family_group("pickup") == "car");
  CHECK(common::family_group("semi-tractor") == "truck");
  CHECK(common::family_group("wheeled-apc") == "machine");
  CHECK(common::family_group("tank") == "tracked");
  CHECK(common::family_group("car").empty());  // a group is not a family
  CHECK(common::family_group("tractor").empty());
  CHECK(common::class_group("pickup") == "car");
  CHECK(common::class_group("tracked-apc") == "tracked");
  for (const char* g : {"car", "van", "truck", "bus", "machine", "tracked"})
    CHECK(common::class_group(g) == g);
  // A modelbase's class of its own is its own group (collect: it agrees only with itself).
  CHECK(common::class_group("tractor") == "tractor");
  CHECK(common::class_group("forklift") == "forklift");
  CHECK(common::class_group("") == "");
}
