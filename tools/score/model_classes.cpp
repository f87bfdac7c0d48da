// score --model-classes: the classes of models (share/models/classes.csv), given to true vehicles
// and model answers without one.
#include <map>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "score/score.h"

namespace canopy::score {

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
