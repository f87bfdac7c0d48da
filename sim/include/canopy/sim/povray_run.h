// Running POV-Ray in a private temporary directory. Shared by rangetrace's single-vehicle
// scenes and tiles and by the tile builder (tile.h). `povray` is the program (the --povray
// option: a name looked up on PATH or a path).
#pragma once

#include <Eigen/Core>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "canopy/sim/model.h"
#include "canopy/sim/sandbox.h"

namespace canopy::sim {

// A private directory under $TMPDIR (or /tmp), removed with its files on destruction and
// also when the process is stopped by SIGINT, SIGTERM or SIGHUP (the signal handler kills
// and reaps the running POV-Ray processes, removes the directory, then lets the signal
// take its default course). POV-Ray children also die with rangetrace on SIGKILL
// (run_process); the directory then stays behind until the next run removes it (its
// "owner" file names a process that no longer exists).
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::vector<std::string> files() const;

 private:
  std::string path_;
  int slot_ = -1;
};

// Models made reachable to POV-Ray from the private directory under safe names: include k
// is the symbolic link "model<k>.inc" (to the user's file) and its directory the link
// "inc<k>" (passed as +Linc<k>), so spaces or quotes in the user's paths never reach the
// command line or an #include string. POV-Ray messages are mapped back to the real paths.
// What POV-Ray may read besides the system (sandbox.h): the built-in models' directory, the
// files of user includes; `user_code` when a user include is among the models.
struct Staged {
  std::vector<std::string> include_code;                     // per model: POV-Ray code declaring Vehicle
  std::vector<std::string> args;                             // +L options
  std::vector<std::pair<std::string, std::string>> renames;  // staged name -> real path
  std::vector<std::string> readable;                         // absolute paths, read-only in the jail
  bool user_code = false;
};
Staged stage_models(const std::vector<Model>& models, const TempDir& tmp);

// Runs `cmd` in directory `dir`, stdin /dev/null, stdout and stderr to `log_path`, in a new
// session and process group without a controlling terminal (under a small supervisor process).
// The group is known to the signal cleanup (killed and reaped on SIGINT, SIGTERM, SIGHUP) and
// dies with rangetrace, even on SIGKILL (the supervisor's PR_SET_PDEATHSIG). Returns the
// command's exit status (128 + n when killed by signal n).
int run_process(const Command& cmd, const std::string& dir, const std::string& log_path);

// Runs povray with `args` in directory `dir`, confined (sandbox.h) with what `st` makes
// readable, console output to `log_name` there. Throws Error with POV-Ray's own message (staged
// names replaced by the real ones) when it fails.
void run_povray(const std::string& povray, const Staged& st, const std::string& dir,
                std::vector<std::string> args, const std::string& log_name,
                const std::vector<std::pair<std::string, std::string>>& renames = {});

// Frames first..last (inclusive) of a POV-Ray animation, rendered by one process at width x
// height pixels.
// POV-Ray runs per render thread a caller keeps in flight (render_frames' `processes`): POV-Ray
// 3.7 waits a fixed wall time between the frames of one run without using CPU (≈ 0.28 s per
// frame, docs/decisions/cost.md §3); with 4 runs per thread that idle overlaps the others' work.
// Each run parses the scene once more (≈ +0.02 CPU-s per run for a thesis scan).
inline constexpr int kRunsPerThread = 4;

struct FrameRange {
  int first = 0, last = 0;
  int width = 0, height = 0;
  // The pixels traced (0-based, inclusive; POV-Ray's +SC/+EC/+SR/+ER): the whole image when
  // col0 < 0. POV-Ray still writes the whole image, the pixels outside the window black (0),
  // which the decoders read as "the ray hit nothing" (docs/decisions/cost.md §11).
  int col0 = -1, col1 = -1, row0 = -1, row1 = -1;
};

// POV-Ray's render-window options for `r` (1-based, inclusive), none for the whole image.
// A window is at least 2 pixels wide and high, because POV-Ray reads a value of 1 (and any
// value in [0, 1]) as a fraction of the image: "+EC1" would mean the last column.
std::vector<std::string> window_args(const FrameRange& r);

// Renders the animation `pov` (a scene file in `tmp` of `frames` frames; 16-bit PPM, gamma 1,
// no antialiasing) as one POV-Ray process per range, at most `processes` at a time
// (common::parallel_for; a free process takes the next range in order), the console output of
// range t in render<t>.log. The first failing range's message (in range order) is thrown as
// Error after every process has finished. Returns the frame files by frame number.
std::map<int, std::string> render_frames(const std::string& povray, const TempDir& tmp, const Staged& st,
                                         const std::string& pov, int frames,
                                         const std::vector<FrameRange>& ranges, int processes,
                                         const std::vector<std::pair<std::string, std::string>>& renames);

// Bounding boxes (world frame) of several models from one POV-Ray parse run.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> models_extent(const std::vector<Model>& models,
                                                                       const std::string& povray,
                                                                       const TempDir& tmp);

// Warns (before any rendering) when a model is implausibly large for a vehicle, or (with `crop`,
// a single-vehicle scan's crop box: length, width, height in m) larger than the crop box.
void warn_model_size(const Model& model, const Eigen::Vector3d& size, const Eigen::Vector3d* crop);

}  // namespace canopy::sim
