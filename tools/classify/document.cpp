// classify's verdict document and its pose inputs (detect's index, --transform).
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/documents/candidates.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/pose_eigen.h"
#include "canopy/formats/verdict.h"
#include "classify/classify.h"

namespace canopy::classify {
namespace {

using Json = nlohmann::ordered_json;

double finite(double v, const char* what) {
  if (!std::isfinite(v)) throw common::Error(std::string("classify: refusing to write a non-finite ") + what);
  return v;
}

Json pose_json(const Eigen::Isometry3d& t) {
  const formats::Pose p = formats::to_pose(t);
  Json m = Json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m.push_back(finite(p.rotation[3 * r + c], "pose"));
    m.push_back(finite(p.translation[r], "pose"));
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) m.push_back(v);
  const auto e = formats::euler_degrees(p);
  return Json{{"matrix", m},
              {"translation", Json::array({p.translation[0], p.translation[1], p.translation[2]})},
              {"heading_deg", e[0]},
              {"pitch_deg", e[1]},
              {"roll_deg", e[2]}};
}

Json optional(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

Json text_or_null(const std::string& s) { return s.empty() ? Json(nullptr) : Json(s); }

Json features_json(const Features& f) {
  const double deg = 180 / common::kPi;
  return Json{{"crop_points", f.crop_points},
              {"ground_points", f.ground_points},
              {"object_points", f.object_points},
              {"crop_spacing", f.crop_spacing},
              {"heading_pca_deg", f.heading_pca * deg},
              {"heading_hull_deg", f.heading_hull * deg},
              {"heading_refined_deg", f.heading_refined * deg},
              {"ground_density", optional(f.ground_density)},
              {"fill", optional(f.fill)},
              {"plateau_share", f.plateau_share},
              {"end_low", f.end_low},
              {"end_high", f.end_high},
              {"top_roughness", f.top_roughness},
              {"top_cells", f.top_cells},
              {"below_share", f.below_share},
              {"ground_through", f.ground_through},
              {"interior_points", f.interior_points},
              {"below_share_cells", f.below_share_cells},
              {"ground_through_cells", f.ground_through_cells},
              {"interior_cells", f.interior_cells},
              {"late_returns", optional(f.late_returns)},
              {"multi_returns", optional(f.multi_returns)}};
}

// 4 x 4 matrix from 16 numbers (flat) or 4 rows of 4; rigid, last row 0 0 0 1.
Eigen::Isometry3d rigid(const std::vector<double>& v, const std::string& where) {
  if (v.size() != 12 && v.size() != 16) throw std::invalid_argument(where + " needs 12 or 16 numbers");
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (4 * r + c < static_cast<int>(v.size())) M(r, c) = v[static_cast<std::size_t>(4 * r + c)];
    }
  }
  if (!M.allFinite()) throw std::invalid_argument(where + " has a non-finite number");
  if (v.size() == 16 && (M(3, 0) != 0 || M(3, 1) != 0 || M(3, 2) != 0 || M(3, 3) != 1)) {
    throw std::invalid_argument(where + ": last row is not 0 0 0 1");
  }
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0) {
    throw std::invalid_argument(where + ": the 3 x 3 part is not a rotation");
  }
  return Eigen::Isometry3d(M);
}

}  // namespace

std::string serialize(const Answer& a, const Params& p, const Document& doc) {
  const Features& f = a.features;
  const bool vehicle = !a.cls.empty();
  Json pose = nullptr, pose_tile = nullptr;
  if (vehicle) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(f.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    t.translation() = Eigen::Vector3d(f.centre.x(), f.centre.y(), 0);
    pose = pose_json(t);
    if (doc.transform) pose_tile = pose_json(*doc.transform * t);
  }
  Json measured = nullptr;
  if (a.measured) {
    measured = Json{{"size", Json::array({f.length_measured, f.width_measured, f.height_measured})},
                    {"centre", Json::array({f.centre.x(), f.centre.y()})},
                    {"heading_deg", f.heading * 180 / common::kPi},
                    {"spacing", f.spacing},
                    {"edge_correction", p.edge_factor * f.spacing}};
  }
  Json nearest = nullptr;
  if (doc.nearest) {
    nearest = Json{{"model", doc.nearest->name},
                   {"class", doc.nearest->cls},
                   {"size", Json::array({doc.nearest->size[0], doc.nearest->size[1], doc.nearest->size[2]})}};
  }
  Json j{{"format", "canopy.verdict"},
         {"version", 1},
         {"provenance", formats::provenance_json(doc.provenance)},
         {"candidate", doc.candidate},
         {"level", "class"},
         {"model", nullptr},
         {"class", text_or_null(a.cls)},
         {"group", text_or_null(a.group)},
         {"confidence", finite(a.confidence, "confidence")},
         {"reason", text_or_null(a.reason)},
         {"detail", a.detail},
         {"pose", pose},
         {"pose_tile", pose_tile},
         {"heading_ambiguity_deg", 180},
         {"size", vehicle ? Json::array({f.length, f.width, f.height}) : Json(nullptr)},
         {"measured", measured},
         {"density", a.measured ? Json(finite(f.density, "density")) : Json(nullptr)},
         {"density_needed", Json{{"class", p.min_density}, {"model", p.model_density}}},
         {"points", f.object_points},
         {"features", features_json(f)},
         {"nearest", nearest},
         {"fit_rms", nullptr},
         {"explained", nullptr},
         {"free_space_violation", nullptr},
         {"transform", doc.transform ? pose_json(*doc.transform) : Json(nullptr)},
         {"chosen", -1},
         {"hypotheses", Json::array()},
         {"nearest_instance", doc.nearest ? Json(doc.nearest->name) : Json(nullptr)},
         {"class_score", finite(a.class_score, "class_score")},
         {"class_margin", finite(a.class_margin, "class_margin")}};
  return j.dump(1) + "\n";
}

Eigen::Isometry3d index_transform(const std::string& text, const std::string& name, const std::string& id) {
  const documents::Candidates index = documents::read_candidates(text, name);
  const documents::Candidate* c = index.find(id);
  if (!c) throw common::DataError(name, "has no candidate \"" + id + "\"");
  try {
    return rigid(std::vector<double>(c->transform.begin(), c->transform.end()), "transform of " + id);
  } catch (const std::invalid_argument& e) { throw common::DataError(name, e.what()); }
}

Eigen::Isometry3d parse_transform(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw common::UsageError("--transform: '" + item + "' is not a number");
    }
  }
  try {
    return rigid(v, "--transform");
  } catch (const std::invalid_argument& e) {
    throw common::UsageError(std::string(e.what()) + " (row-major 3x4 or 4x4, comma-separated)");
  }
}

}  // namespace canopy::classify
