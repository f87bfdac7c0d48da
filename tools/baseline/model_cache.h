// The baseline's models' side on disk (issue 31; docs/decisions/baseline.md §7): a
// canopy.baseline-models v1 file (formats/README.md), written once per modelbase by
// `baseline --prepare` and read back by every run given `--model-cache`, so that a candidate
// only computes its own side. The floats are stored bit for bit: a run with the file gives the
// same bytes as a run that computes the models' side itself.
//
// The file records what it was made from, and a reader refuses it (DataError naming the file,
// exit 1) when that differs from the run's: the parameters the models' side depends on (voxel,
// normal and feature radii, views, view elevation) and, per <model>.pcd of the modelbase, its
// name, size and FNV-1a 64 of its bytes; also a truncated or altered file (its body's length
// and FNV-1a 64 are in its header).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "baseline/baseline.h"

namespace canopy::baseline {

// One <model>.pcd of a modelbase as the file records it.
struct SurfaceStamp {
  std::string name;  // the model's name (the file's stem)
  std::uint64_t bytes = 0;
  std::uint64_t fnv1a = 0;  // FNV-1a 64 of the file's bytes
};

// Stamps of list_modelbase(dir), in its order. DataError naming the directory or a file.
std::vector<SurfaceStamp> stamp_modelbase(const std::string& dir);

// The file's bytes: `models` must hold both methods' sides, in the order of `stamps`.
std::string serialize_prepared(const PreparedModels& models, const Params& params,
                               const std::vector<SurfaceStamp>& stamps);

// Parses a file's bytes (`path` names it in errors) and checks it against the run's parameters
// and the modelbase's stamps. Throws DataError(path, cause).
PreparedModels parse_prepared(const std::string& bytes, const std::string& path, const Params& params,
                              const std::vector<SurfaceStamp>& stamps);

// `baseline --prepare`: reads the modelbase and returns the file's bytes (both methods).
std::string prepare_file(const std::string& modelbase, const Params& params, std::size_t* model_count);

// `baseline --model-cache`: reads `path` and checks it against `modelbase` and `params`.
PreparedModels load_prepared(const std::string& path, const std::string& modelbase, const Params& params);

}  // namespace canopy::baseline
