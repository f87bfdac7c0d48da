// classify's verdict document and its pose inputs (detect's index, --transform).
#include <cmath>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/documents/candidates.h"
#include "canopy/formats/pose_eigen.h"
#include "canopy/documents/classification.h"
#include "classify/classify.h"

namespace canopy::classify {
namespace {

using documents::ClassFeature;

ClassFeature count(const char* name, std::size_t n) { return {name, static_cast<double>(n), true}; }
ClassFeature number(const char* name, double v) { return {name, v, false}; }
ClassFeature optional(const char* name, const std::optional<double>& v) { return {name, v, false}; }

std::vector<ClassFeature> features_of(const Features& f) {
  const double deg = 180 / common::kPi;
  std::vector<ClassFeature> out{count("crop_points", f.crop_points),
                                count("ground_points", f.ground_points),
                                count("object_points", f.object_points),
                                number("crop_spacing", f.crop_spacing),
                                number("heading_pca_deg", f.heading_pca * deg),
                                number("heading_hull_deg", f.heading_hull * deg),
                                number("heading_refined_deg", f.heading_refined * deg),
                                optional("ground_density", f.ground_density),
                                optional("fill", f.fill),
                                number("plateau_share", f.plateau_share),
                                number("end_low", f.end_low),
                                number("end_high", f.end_high),
                                number("end_fill", f.end_fill),
                                number("notch", f.notch),
                                number("notch_sampled", f.notch_sampled),
                                number("rectangularity", f.rectangularity),
                                count("dents", f.dents),
                                number("tip_width", f.tip_width),
                                number("tip_level", f.tip_level),
                                optional("shoulder", f.shoulder),
                                optional("rim", f.rim),
                                optional("bed", f.bed),
                                number("top_roughness", f.top_roughness),
                                count("top_cells", f.top_cells),
                                number("top_roughness_line", f.top_roughness_line),
                                count("top_cells_line", f.top_cells_line),
                                number("below_share", f.below_share),
                                number("ground_through", f.ground_through),
                                count("interior_points", f.interior_points),
                                number("below_share_cells", f.below_share_cells),
                                number("ground_through_cells", f.ground_through_cells),
                                count("interior_cells", f.interior_cells),
                                optional("late_returns", f.late_returns),
                                optional("echo_widening", f.echo_widening),
                                optional("multi_returns", f.multi_returns)};
  // Only when --bridge crossed a strip inside the rectangle (classify.md §27).
  if (f.shadow_area > 0) out.push_back(number("shadow_area", f.shadow_area));
  if (f.fill_rectangle) out.push_back(optional("fill_rectangle", f.fill_rectangle));
  // Only when fill is the tile's (--fill-tile-ground, classify.md §31): 1.
  if (f.fill_from_tile) out.push_back(count("fill_from_tile", 1));
  // Only when that reference was the tile's first returns (--fill-tile-first, classify.md §46): 1.
  if (f.fill_from_first) out.push_back(count("fill_from_first", 1));
  // Only when the crop holds several flight passes (classify.md §14): a crop without them gets
  // the document it got before.
  if (f.below_share_any) out.push_back(optional("below_share_any", f.below_share_any));
  if (f.ground_through_any) out.push_back(optional("ground_through_any", f.ground_through_any));
  if (f.late_shadowed) {
    out.push_back(optional("late_shadowed", f.late_shadowed));
    out.push_back(count("ring_returns", f.ring_returns));
    out.push_back(optional("ring_shadowed", f.ring_shadowed));
  }
  if (f.ground_edge_splits) out.push_back(count("ground_edge_splits", *f.ground_edge_splits));
  if (f.passes > 1) {
    out.push_back(count("passes", f.passes));
    out.push_back(count("object_passes", f.object_passes));
    out.push_back(optional("fill_all_passes", f.fill_all_passes));
    out.push_back(optional("ground_through_all_passes", f.ground_through_all_passes));
  }
  return out;
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
  documents::ClassVerdict v;
  v.provenance = doc.provenance;
  v.candidate = doc.candidate;
  v.cls = a.cls;
  v.group = a.group;
  v.reason = a.reason;
  v.refused_on = a.refused_on;
  v.detail = a.detail;
  v.confidence = a.confidence;
  if (!a.cls.empty()) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(f.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    t.translation() = Eigen::Vector3d(f.centre.x(), f.centre.y(), 0);
    v.pose = formats::to_pose(t);
    if (doc.transform) v.pose_tile = formats::to_pose(*doc.transform * t);
    v.size = std::array<double, 3>{f.length, f.width, f.height};
  }
  if (a.measured) {
    v.measured = documents::MeasuredRectangle{{f.length_measured, f.width_measured, f.height_measured},
                                              {f.centre.x(), f.centre.y()},
                                              f.heading * 180 / common::kPi,
                                              f.spacing,
                                              p.edge_factor * f.spacing};
    v.density = f.density;
  }
  v.density_needed_class = p.min_density;
  v.density_needed_model = p.model_density;
  v.points = f.object_points;
  v.features = features_of(f);
  if (doc.nearest)
    v.nearest = documents::NearestModel{doc.nearest->name, doc.nearest->cls, doc.nearest->size};
  if (doc.transform) v.transform = formats::to_pose(*doc.transform);
  v.class_score = a.class_score;
  v.class_margin = a.class_margin;
  return documents::serialize_class_verdict(v);
}

Eigen::Isometry3d index_transform(const documents::Candidates& index, const std::string& name,
                                  const std::string& id) {
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
