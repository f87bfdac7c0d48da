#include "canopy/formats/provenance.h"

namespace canopy::formats {

std::vector<std::string> provenance_comments(const Provenance& p) {
  std::vector<std::string> lines;
  lines.push_back(p.tool + " (canopy) " + p.version);
  for (const auto& [name, value] : p.parameters) lines.push_back("parameter " + name + " = " + value);
  for (const std::string& in : p.inputs) lines.push_back("input " + in);
  return lines;
}

nlohmann::ordered_json provenance_json(const Provenance& p) {
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const auto& [k, v] : p.parameters) params[k] = v;
  return nlohmann::ordered_json{
      {"tool", p.tool}, {"version", p.version}, {"parameters", params}, {"inputs", p.inputs}};
}

}  // namespace canopy::formats
