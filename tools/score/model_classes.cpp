// score --model-classes: the classes of models (share/models/classes.csv), given to true vehicles
// and model answers without one.
#include <map>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "score/score.h"

namespace canopy::score {

std::map<std::string, std::string> parse_model_classes(const std::string& text, const std::string& name) {
  std::map<std::string, std::string> classes;
  std::size_t start = 0;
  int line_no = 0;
  bool header = false;
  auto valid = [](const std::string& c) {
    if (c.empty() || c.size() > 64) return false;
    for (char ch : c)
      if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '-')) return false;
    return true;
  };
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') {
      if (end == text.size()) break;
      continue;
    }
    const std::string where = "line " + std::to_string(line_no) + ": ";
    const std::size_t comma = line.find(',');
    if (comma == std::string::npos || line.find(',', comma + 1) != std::string::npos)
      throw common::DataError(name, where + "expected 'model,class', got '" + line.substr(0, 80) + "'");
    const std::string model = line.substr(0, comma), cls = line.substr(comma + 1);
    if (!header) {
      if (model != "model" || cls != "class")
        throw common::DataError(name, where + "the first line must be the header 'model,class'");
      header = true;
      continue;
    }
    if (model.empty() || model.size() > 128)
      throw common::DataError(name, where + "empty or over-long model name");
    if (!valid(cls))
      throw common::DataError(
          name, where + "class '" + cls.substr(0, 80) + "' is not 1-64 characters of [a-z0-9-]");
    if (!classes.emplace(model, cls).second)
      throw common::DataError(name, where + "model '" + model + "' given twice");
    if (end == text.size()) break;
  }
  if (!header) throw common::DataError(name, "no header line 'model,class'");
  return classes;
}

void apply_model_classes(std::vector<Tile>& tiles, const std::map<std::string, std::string>& classes) {
  auto class_of = [&](const std::string& model) {
    const auto it = classes.find(model);
    return it == classes.end() ? std::string() : it->second;
  };
  for (Tile& t : tiles) {
    for (TrueVehicle& v : t.truth.vehicles)
      if (v.cls.empty()) v.cls = class_of(v.model);
    for (Detection& d : t.detections.detections)
      if (d.cls.empty() && !d.model.empty()) d.cls = class_of(d.model);
  }
}

}  // namespace canopy::score
