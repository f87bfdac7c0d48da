// detect's output directory: index.json (format "canopy.candidates", version 1, see
// formats/README.md), one PCD per candidate (<id>.pcd) and the classification PLY
// (classes.ply). Written into a temporary directory beside the destination and renamed into
// place, so a failed run leaves no partial directory.
#pragma once

#include <string>

#include "canopy/formats/point_cloud.h"
#include "canopy/formats/provenance.h"
#include "detect/detect.h"

namespace canopy::detect {

// The index document. `tile` is the input path as given; `classes` the PLY's file name in the
// directory, or empty when none is written.
std::string serialize_index(const Result& result, const Params& params, const formats::Provenance& provenance,
                            const std::string& tile, const std::string& classes);

// Writes the whole directory atomically. Refuses (DataError) when `dir` exists and is not a
// directory, or is a directory that is neither empty nor a previous detect output (holds an
// index.json); a previous output is replaced as a whole. The PCD and PLY comments: a
// candidate keeps the tile's, then come formats::provenance_comments(provenance) and a line on
// what the file holds (the candidate's id and frame; the classes and the local origin).
void write_output(const std::string& dir, const formats::PointCloud& tile, const Result& result,
                  const Params& params, const formats::Provenance& provenance, const std::string& tile_name,
                  bool write_classes);

}  // namespace canopy::detect
