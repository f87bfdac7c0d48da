// candtruth: which labelled vehicle each of detect's candidates holds, and which candidates hold
// each vehicle (canopy.candidate_truth, documents/candidate_truth.h). The truth statistics that
// detect computed on the recogniser's path before issue 30: detect's index and crops now carry no
// truth, and this stage reads it from the labelled tile (rangetrace's tiles) and the index's
// geometry. docs/decisions/detect.md, "Truth outside the recogniser's path".
#pragma once

#include <optional>
#include <string>

#include "canopy/documents/candidate_truth.h"
#include "canopy/documents/candidates.h"
#include "canopy/formats/point_cloud.h"

namespace canopy::candtruth {

struct Params {
  std::string label_field = "label";        // ground-truth class (formats/labels.h); optional in the tile
  std::string instance_field = "instance";  // ground-truth vehicle id (0 = none); required in the tile
  std::optional<double> margin;             // the crop margin (m); default: the index's
};

struct Inputs {
  // x y z in tile coordinates, the instance field, optionally the label field (borrowed: the
  // caller keeps it, as detect's tile).
  const formats::PointCloud* tile = nullptr;
  std::string tile_name;  // names the tile in errors and in the output
  documents::Candidates index;
  std::string index_name;
};

using Outputs = documents::CandidateTruth;

// Throws common::UsageError (--margin) for a margin that is not a finite number >= 0, or empty
// field names.
void validate(const Params& params);

// A candidate's crop is every tile point whose coordinates in the candidate's frame (the
// inverse of the index's transform) satisfy |x| <= length / 2 + margin, |y| <= width / 2 +
// margin and -margin <= z <= height + margin: the box detect cropped. A point belongs to
// vehicle v when its instance field is v > 0 and (where the tile has a label field) its label
// is kLabelTarget. A candidate's truth is the vehicle with the most points in its crop (ties:
// the smaller id), its points there, coverage = those points / the vehicle's points in the
// tile, purity = those points / the crop's points that are not ground (label kLabelGround;
// every crop point without a label field); instance 0 (a false candidate) when no vehicle
// point is in the crop. Throws common::DataError naming the tile: no x y z, no instance field,
// a field value that is not an integer >= 0 below 2^32; naming the index: no margin (a
// version 1 index) and none given, a candidate without height, tile_points that differ from
// the tile's points.
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::candtruth
