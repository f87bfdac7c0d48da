#include "canopy/common/vehicle_classes.h"

namespace canopy::common {

const std::vector<VehicleClass>& vehicle_classes() {
  static const std::vector<VehicleClass> k = {
      {"sedan", "car"},           {"hatchback", "car"}, {"suv", "car"},
      {"pickup", "car"},          {"van", "van"},       {"box-truck", "truck"},
      {"semi-tractor", "truck"},  {"bus", "bus"},       {"wheeled-apc", "machine"},
      {"tracked-apc", "tracked"}, {"tank", "tracked"},  {"wheel-loader", "machine"},
  };
  return k;
}

std::string family_group(const std::string& cls) {
  for (const VehicleClass& k : vehicle_classes()) {
    if (cls == k.name) return k.group;
  }
  return "";
}

std::string class_group(const std::string& cls) {
  const std::string g = family_group(cls);
  return g.empty() ? cls : g;
}

}  // namespace canopy::common
