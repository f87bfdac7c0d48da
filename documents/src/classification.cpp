#include "canopy/documents/classification.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/verdict.h"
#include "verdict_json.h"

namespace canopy::documents {
namespace {

using Json = nlohmann::ordered_json;

double finite(double v, const char* what) {
  if (!std::isfinite(v)) throw common::Error(std::string("classify: refusing to write a non-finite ") + what);
  return v;
}

Json text_or_null(const std::string& s) { return s.empty() ? Json(nullptr) : Json(s); }

Json pose_or_null(const std::optional<formats::Pose>& p) {
  return p ? verdict_json::pose_json(*p) : Json(nullptr);
}

Json triple(const std::array<double, 3>& a) { return Json::array({a[0], a[1], a[2]}); }

Json features_json(const std::vector<ClassFeature>& features) {
  Json j = Json::object();
  for (const ClassFeature& f : features) {
    if (!f.value) {
      j[f.name] = nullptr;
    } else if (f.integer) {
      j[f.name] = static_cast<std::uint64_t>(*f.value);
    } else {
      j[f.name] = *f.value;
    }
  }
  return j;
}

}  // namespace

std::string serialize_class_verdict(const ClassVerdict& v) {
  Json measured = nullptr;
  if (v.measured) {
    const MeasuredRectangle& m = *v.measured;
    measured = Json{{"size", triple(m.size)},
                    {"centre", Json::array({m.centre[0], m.centre[1]})},
                    {"heading_deg", m.heading_deg},
                    {"spacing", m.spacing},
                    {"edge_correction", m.edge_correction}};
  }
  Json nearest = nullptr;
  if (v.nearest)
    nearest = Json{{"model", v.nearest->model}, {"class", v.nearest->cls}, {"size", triple(v.nearest->size)}};
  Json j{{"format", kVerdictFormat},
         {"version", kVerdictVersion},
         {"provenance", formats::provenance_json(v.provenance)},
         {"candidate", v.candidate},
         {"level", "class"},
         {"model", nullptr},
         {"class", text_or_null(v.cls)},
         {"group", text_or_null(v.group)},
         {"confidence", finite(v.confidence, "confidence")},
         {"reason", text_or_null(v.reason)},
         {"detail", v.detail},
         {"pose", pose_or_null(v.pose)},
         {"pose_tile", pose_or_null(v.pose_tile)},
         {"heading_ambiguity_deg", 180},
         {"size", v.size ? triple(*v.size) : Json(nullptr)},
         {"measured", measured},
         {"density", v.density ? Json(finite(*v.density, "density")) : Json(nullptr)},
         {"density_needed", Json{{"class", v.density_needed_class}, {"model", v.density_needed_model}}},
         {"points", v.points},
         {"features", features_json(v.features)},
         {"nearest", nearest},
         {"fit_rms", nullptr},
         {"explained", nullptr},
         {"free_space_violation", nullptr},
         {"transform", pose_or_null(v.transform)},
         {"chosen", -1},
         {"hypotheses", Json::array()},
         {"nearest_instance", v.nearest ? Json(v.nearest->model) : Json(nullptr)},
         {"class_score", finite(v.class_score, "class_score")},
         {"class_margin", finite(v.class_margin, "class_margin")}};
  if (!v.refused_on.empty()) j["refused_on"] = v.refused_on;
  return j.dump(1) + "\n";
}

}  // namespace canopy::documents
