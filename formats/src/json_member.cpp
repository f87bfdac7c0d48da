#include "canopy/formats/json_document.h"

namespace canopy::formats {

const nlohmann::ordered_json& json_member(const nlohmann::ordered_json& j, const char* key,
                                          const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw MalformedField(where + ": missing \"" + key + "\"");
  return j.at(key);
}

}  // namespace canopy::formats
