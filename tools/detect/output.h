// detect's output directory: index.json (format "canopy.candidates", version 2, see
// formats/README.md), one PCD per candidate (<id>.pcd), the classification PLY (classes.ply)
// and manifest.json, written last, listing every one of these files with its size and SHA-256
// (format "canopy.detect_manifest", version 1): the proof that detect wrote the directory.
//
// Built in a temporary directory `.<name>.tmp<pid>` beside the destination (flock'ed while
// its run lives) and swapped into place with renameat2(RENAME_EXCHANGE), so at every instant
// the old or the new complete output is at the path; then the old one is removed. Where the
// file system cannot exchange, two renames (the old one aside as `.<name>.old<pid>`, the new
// one in). Leftovers of killed runs (`.<name>.tmp<pid>`, `.<name>.old<pid>`: not locked by a
// live run, holding canopy's marker, manifest or index) are removed by the next run.
// docs/decisions/detect.md, "Output directory: replace only what detect wrote".
#pragma once

#include <functional>
#include <string>

#include "canopy/documents/candidates.h"

#include "canopy/formats/point_cloud.h"
#include "canopy/formats/provenance.h"
#include "detect/detect.h"

namespace canopy::detect {

// The manifest's name in an output directory.
inline constexpr const char* kManifestName = "manifest.json";

// The index of `result` as a document (every member detect writes but the provenance). `tile` is
// the input path as given; `classes` the PLY's file name in the directory, or empty when none is
// written. Also what tests and benches hand to candtruth.
documents::Candidates index_document(const Result& result, const Params& params, const std::string& tile,
                                     const std::string& classes);

// The index document's text: index_document with `provenance`.
std::string serialize_index(const Result& result, const Params& params, const formats::Provenance& provenance,
                            const std::string& tile, const std::string& classes);

// Checks, before any work, that `dir` can take detect's output. `dir` (symbolic links followed,
// to the directory they name) must not exist, or be an empty directory, or be a previous
// detect output: a directory whose manifest.json lists every file in it with the size and
// SHA-256 it still has — or, written before manifests existed, whose index.json is detect's
// and names every file in it — beside which it may hold only the chain's per-candidate
// directories `<id>/` (for an `<id>.pcd` it lists) of chain outputs (names ending in .pcd,
// .ply, .json, .log, .time, optionally + .tmp; no subdirectories or links). It must not hold
// `input` (the tile, "-" for stdin). Its parent directory must exist (it is not created).
// Throws DataError naming `dir` and what is there (exit 1); UsageError for ".", "..", "".
void check_output_dir(const std::string& dir, const std::string& input);

// Test hooks of write_output.
struct WriteHooks {
  // Called at each step: "created" (the temporary directory, locked and marked), "written"
  // (every file and the manifest), "swapped" (the new output at the path, the old one not yet
  // removed), "aside" (fallback only: the old output moved aside, the new one not yet in).
  std::function<void(const std::string& step)> step;
  bool no_exchange = false;  // use the two-rename fallback, as where RENAME_EXCHANGE is unsupported
};

// Writes the whole directory (check_output_dir's rule, checked again just before the swap).
// The PCD and PLY comments: a candidate keeps the tile's, then come
// formats::provenance_comments(provenance) and a line on what the file holds (the candidate's
// id and frame; the classes and the local origin). `tile_name` is the input path as given
// (index.json's "tile", and the tile that must not lie inside `dir`). SIGINT, SIGTERM, SIGHUP,
// SIGPIPE and SIGXFSZ while writing remove the temporary directory; they are held back during
// the swap and the removal of the old output.
void write_output(const std::string& dir, const formats::PointCloud& tile, const Result& result,
                  const Params& params, const formats::Provenance& provenance, const std::string& tile_name,
                  bool write_classes, const WriteHooks& hooks = {});

}  // namespace canopy::detect
