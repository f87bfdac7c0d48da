// classify's answer for one candidate: a canopy.verdict (version 1) at class level ("level":
// "class", "model": null, no hypotheses), docs/decisions/classify.md §9. Read back by
// documents/verdict.h's read_verdict (the one verdict reader: collect reads the class, group,
// reason, sizes and densities from there); written here.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/pose.h"
#include "canopy/formats/provenance.h"

namespace canopy::documents {

// One of classify's measurements ("features" member, in the order given): a number (an
// integer count when `integer`), or null when value is nullopt (or not finite).
struct ClassFeature {
  std::string name;
  std::optional<double> value;
  bool integer = false;
};

// The measured rectangle before the sampling correction.
struct MeasuredRectangle {
  std::array<double, 3> size{};    // L W H (m)
  std::array<double, 2> centre{};  // candidate frame (m)
  double heading_deg = 0;
  double spacing = 0;          // 1 / sqrt(density)
  double edge_correction = 0;  // edge_factor x spacing (m)
};

// The modelbase entry nearest the answer by size.
struct NearestModel {
  std::string model, cls;
  std::array<double, 3> size{};  // L W H
};

struct ClassVerdict {
  formats::Provenance provenance;
  std::string candidate;           // points path, as given
  std::string cls, group, reason;  // "" = null
  std::string detail;              // one sentence (written as a string, even "")
  // The kind of evidence a none rests on (density, surface, size, shape; docs/decisions/
  // classify.md §24): written as the last member "refused_on" when not empty, so an answer
  // with a class, and every document before it, keeps its bytes.
  std::string refused_on;
  double confidence = 0;                         // in [0, 1]
  std::optional<formats::Pose> pose, pose_tile;  // class frame -> candidate / tile frame
  std::optional<std::array<double, 3>> size;     // L W H corrected (a vehicle only)
  std::optional<MeasuredRectangle> measured;     // when enough points were measured
  std::optional<double> density;                 // object points per m² of its rectangle
  double density_needed_class = 0, density_needed_model = 0;
  std::uint64_t points = 0;  // object points
  std::vector<ClassFeature> features;
  std::optional<NearestModel> nearest;
  std::optional<formats::Pose> transform;  // candidate frame -> tile frame
  double class_score = 0, class_margin = 0;
};

// The document's text (JSON, one space indent, a final newline), byte-identical to classify's
// before the move. common::Error on a non-finite confidence, density, class score or margin or
// pose.
std::string serialize_class_verdict(const ClassVerdict& verdict);

}  // namespace canopy::documents
