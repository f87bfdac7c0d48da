// The point files of detect's output directory (output.h): one PCD per candidate (its crop in
// its local frame) and the classification PLY. Comments: a candidate keeps the tile's, then
// come `provenance` (formats::provenance_comments) and a line on what the file holds.
#pragma once

#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "detect/detect.h"

namespace canopy::detect {

// The candidate's PCD bytes. `path` names the file in errors (coordinates PCD cannot hold).
std::string candidate_pcd(const Candidate& c, const std::vector<std::string>& provenance,
                          const std::string& path);

// classes.ply: classification_cloud(tile, result) with the classes and the local origin in
// its comments.
std::string classes_ply(const formats::PointCloud& tile, const Result& result,
                        const std::vector<std::string>& provenance);

}  // namespace canopy::detect
