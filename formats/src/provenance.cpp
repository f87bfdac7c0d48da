#include "canopy/formats/provenance.h"

namespace canopy::formats {

std::vector<std::string> provenance_comments(const Provenance& p) {
  std::vector<std::string> lines;
  lines.push_back(p.tool + " (canopy) " + p.version);
  for (const auto& [name, value] : p.parameters) lines.push_back("parameter " + name + " = " + value);
  for (const std::string& in : p.inputs) lines.push_back("input " + in);
  return lines;
}

}  // namespace canopy::formats
