// Single-vehicle scans: a private temporary directory (POV-Ray's working directory, the only
// one it may write in its jail: sandbox.h; includes come through +L), parallel processes over
// the views, decoding.
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/math.h"
#include "canopy/sim/povray_run.h"
#include "rangetrace/rangetrace.h"

namespace canopy::rangetrace {

using common::Error;

namespace {

// The model as seen from the private directory (its include staged under a safe name).
Model staged_model(const Model& model, const Staged& st) {
  Model m = model;
  m.include_dir.clear();
  m.include_file.clear();
  m.inline_code = st.include_code[0];
  return m;
}

std::vector<std::string> picture_args(const Staged& st) {
  std::vector<std::string> args = {"-D", "-P", "-V", "+WT1"};
  args.insert(args.end(), st.args.begin(), st.args.end());
  return args;
}

std::vector<std::pair<std::string, std::string>> scene_renames(const Staged& st, const std::string& pov) {
  auto renames = st.renames;
  renames.emplace_back(pov, "rangetrace's generated " + pov + " (after the model's include)");
  return renames;
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> model_bounds(const Model& model, const Params& params) {
  TempDir tmp;
  return models_extent({model}, params.povray, tmp)[0];
}

namespace {

// The single-vehicle scan's frames: contiguous blocks of views, one per process; frames 2k
// (coordinates) and 2k+1 (labels) of view k.
std::vector<FrameRange> view_blocks(int views, int workers, int size) {
  std::vector<FrameRange> ranges;
  for (int w = 0; w < workers; ++w) {
    const int first = views * w / workers, last = views * (w + 1) / workers - 1;
    ranges.push_back({2 * first, 2 * last + 1, size, size});
  }
  return ranges;
}

// The same blocks, each run tracing only the pixels that can see the crop box in any of its
// views (the union of their crop_window). One run per view, each with its own window, traces
// fewer pixels still but costs more CPU: a start-up and scene parse per run (cost.md §11).
std::vector<FrameRange> view_windows(const SceneRecipe& scene, const Params& params, int workers) {
  std::vector<FrameRange> ranges = view_blocks(static_cast<int>(scene.views.size()), workers, params.size);
  for (FrameRange& r : ranges) {
    std::vector<PixelWindow> ws;
    for (int f = r.first; f <= r.last; f += 2) ws.push_back(crop_window(params, scene.views[f / 2]));
    const PixelWindow u = window_union(ws);
    r.col0 = u.col0;
    r.col1 = u.col1;
    r.row0 = u.row0;
    r.row1 = u.row1;
  }
  return ranges;
}

// The decoded points of every view as the scan's columns (x y z sensor_x/y/z view_idx label).
formats::PointCloud scan_cloud(const ScanColumns& cols) {
  formats::PointCloud cloud;
  const std::size_t n = cols.points.size();
  cloud.resize(n);
  const char* names[] = {"x", "y", "z", "sensor_x", "sensor_y", "sensor_z"};
  for (int a = 0; a < 6; ++a) {
    auto& c = cloud.add(names[a], formats::kFloat32);
    for (std::size_t i = 0; i < n; ++i) c[i] = a < 3 ? cols.points[i][a] : cols.sensor[i][a - 3];
  }
  auto& vi = cloud.add("view_idx", formats::kInt32);
  auto& lb = cloud.add("label", formats::kUint32);
  for (std::size_t i = 0; i < n; ++i) {
    vi[i] = cols.view_idx[i];
    lb[i] = cols.label[i];
  }
  return cloud;
}

// Decodes and crops the two frames of every view.
formats::PointCloud decode_views(const std::map<int, std::string>& frames, const SceneRecipe& scene,
                                 const Encoding& enc, const Placement& placement, const Params& params) {
  ScanColumns cols;
  const int views = static_cast<int>(scene.views.size());
  for (int k = 0; k < views; ++k) {
    if (!frames.count(2 * k) || !frames.count(2 * k + 1)) {
      throw Error("POV-Ray wrote no image for view " + std::to_string(k));
    }
    const std::string& cf = frames.at(2 * k);
    const std::string& lf = frames.at(2 * k + 1);
    const Image16 coords = parse_ppm(common::read_file(cf), cf);
    const Image16 labels = parse_ppm(common::read_file(lf), lf);
    if (coords.width != params.size || labels.width != params.size) {
      throw Error("POV-Ray image of view " + std::to_string(k) + " has the wrong size");
    }
    decode_view(coords, labels, enc, placement, params, view_direction(scene.views[k], params.pose), k, &cols);
  }
  return scan_cloud(cols);
}

}  // namespace

formats::PointCloud render_scan(const Model& model, const SceneRecipe& scene, const Params& params) {
  if (params.size < 1 || !(params.spacing > 0)) throw common::UsageError("--size and --spacing must be > 0");
  TempDir tmp;
  common::log::Phase prep("model");
  const auto [lo, hi] = models_extent({model}, params.povray, tmp)[0];
  const Eigen::Vector3d crop(params.crop_length, params.crop_width, params.crop_height);
  warn_model_size(model, hi - lo, &crop);
  const Staged st = stage_models({model}, tmp);
  const Placement placement = place(lo, hi, params.pose);
  const Encoding enc = encoding_for(placement, params);
  const std::vector<Disc> foliage = make_foliage(scene, params.pose, placement.top, params.seed);
  char dims[160];
  std::snprintf(dims, sizeof dims, "%s %.3f x %.3f x %.3f m, %zu foliage discs", model.name.c_str(),
                hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(), foliage.size());
  prep.done(dims);

  common::log::Phase render("render");
  common::write_file_atomic(tmp.path() + "/scene.pov",
                            scene_pov(staged_model(model, st), placement, enc, scene.views, foliage, params));
  const int views = static_cast<int>(scene.views.size());
  // POV-Ray 3.7 idles a fixed wall time between the frames of one run (docs/decisions/cost.md
  // §3): kRunsPerThread runs per thread, all in flight, overlap one run's idle with the others'
  // work. A frame's pixels depend on the clock only, not on the split: the scan is the same.
  const int workers = std::max(1, std::min(views, kRunsPerThread * std::max(1, params.threads)));
  const std::vector<FrameRange> ranges =
      params.window ? view_windows(scene, params, workers) : view_blocks(views, workers, params.size);
  double traced = 0;
  for (const FrameRange& r : ranges) {
    const double frames = r.last - r.first + 1;
    traced += r.col0 < 0 ? frames * r.width * r.height
                         : frames * (r.col1 - r.col0 + 1) * static_cast<double>(r.row1 - r.row0 + 1);
  }
  const std::map<int, std::string> frames = render_frames(params.povray, tmp, st, "scene.pov", 2 * views,
                                                          ranges, workers, scene_renames(st, "scene.pov"));
  char share[64];
  std::snprintf(share, sizeof share, " (%.0f%% traced)",
                100 * traced / (2.0 * views * params.size * params.size));
  render.done(std::to_string(views) + " views x 2 passes, " + std::to_string(params.size) + "x" +
              std::to_string(params.size) + " pixels" + (params.window ? share : "") + ", " +
              std::to_string(workers) + " processes");

  common::log::Phase decode("decode");
  formats::PointCloud cloud = decode_views(frames, scene, enc, placement, params);
  decode.done(std::to_string(cloud.size()) + " points in the crop box");
  return cloud;
}

std::string render_picture(const Model& model, const SceneRecipe* scene, int view_idx, const Params& params) {
  TempDir tmp;
  const auto [lo, hi] = models_extent({model}, params.povray, tmp)[0];
  warn_model_size(model, hi - lo, nullptr);
  const Staged st = stage_models({model}, tmp);
  const Placement placement = place(lo, hi, params.pose);
  std::vector<View> views = {View{0, 75 * common::kPi / 180}};
  std::vector<Disc> foliage;
  if (scene != nullptr) {
    if (view_idx < 0 || view_idx >= static_cast<int>(scene->views.size())) {
      throw common::UsageError("--view " + std::to_string(view_idx) + ": the scene has " +
                               std::to_string(scene->views.size()) + " views");
    }
    views = {scene->views[view_idx]};
    foliage = make_foliage(*scene, params.pose, placement.top, params.seed);
  }
  common::write_file_atomic(tmp.path() + "/picture.pov",
                            scene_pov(staged_model(model, st), placement, encoding_for(placement, params),
                                      views, foliage, params, scene != nullptr ? 1 : 2));
  auto args = picture_args(st);
  const std::string size = std::to_string(params.size);
  args.insert(args.end(), {"+W" + size, "+H" + size, "+A0.05", "+R3", "+FN8", "+Ipicture.pov",
                           "+Opicture.png", "+WT" + std::to_string(std::max(1, params.threads))});
  run_povray(params.povray, st, tmp.path(), args, "picture.log", scene_renames(st, "picture.pov"));
  return common::read_file(tmp.path() + "/picture.png");
}

}  // namespace canopy::rangetrace
