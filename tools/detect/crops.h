// The point files of detect's output directory (output.h): one PCD per candidate (its crop in
// its local frame) and the classification PLY. Comments: a candidate keeps the tile's, then
// come `provenance` (formats::provenance_comments) and a line on what the file holds.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "detect/detect.h"

namespace canopy::detect {

// The candidate's PCD bytes. `path` names the file in errors (coordinates PCD cannot hold).
std::string candidate_pcd(const Candidate& c, const std::vector<std::string>& provenance,
                          const std::string& path);

// classes.ply: classification_cloud(tile, result) with the classes and the local origin in
// its comments, as formats::serialize_ply writes it.
std::string classes_ply(const formats::PointCloud& tile, const Result& result,
                        const std::vector<std::string>& provenance);
// The same bytes handed to `sink` in pieces (the header, then blocks of 65 536 rows): the file
// is written without the whole of it, nor a cloud of its columns, in memory (cost.md §17).
void classes_ply(const formats::PointCloud& tile, const Result& result,
                 const std::vector<std::string>& provenance,
                 const std::function<void(const char*, std::size_t)>& sink);

}  // namespace canopy::detect
