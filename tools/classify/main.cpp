// classify: a class-level answer (vehicle class and group, pose, size) or none with a reason,
// for one detect candidate at any density (docs/decisions/classify.md).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/candidates.h"
#include "canopy/documents/model_classes.h"
#include "canopy/documents/modelbase.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/points_io.h"
#include "classify/classify.h"
#include "classify/features.h"

namespace cm = canopy::common;
namespace fm = canopy::formats;
namespace cl = canopy::classify;
namespace fs = std::filesystem;

namespace {

struct Cli {
  std::string in = "-", out = "-", index, candidate, transform, modelbase, model_classes;
  std::string roughness = "plane";
};

void bind(cm::Tool& tool, cl::Params& p, Cli& cli) {
  tool.add_input(&cli.in, "candidate points (detect's <id>.pcd: local frame, ground z = 0)");
  tool.add_output(&cli.out, "verdict JSON (canopy.verdict v1, \"level\": \"class\")");
  tool.add("--index", &cli.index, "detect's index.json: the candidate's transform gives pose_tile");
  tool.add("--candidate", &cli.candidate,
           "the candidate's id in --index (default: the input's file name stem)");
  tool.add("--transform", &cli.transform,
           "candidate frame -> tile frame, 12 or 16 numbers row-major (instead of --index)");
  tool.add("--modelbase", &cli.modelbase,
           "directory of <model>.pcd surfaces with <model>.class files (or --model-classes): each entry's "
           "size is a class range too (--entry-classes), and the answered class's entry nearest in size "
           "is named as a hint");
  tool.add("--model-classes", &cli.model_classes,
           "CSV 'model,class' (share/models/classes.csv): the class of a --modelbase entry without a "
           "<model>.class file");
  tool.add_length("--ground-cut", &p.ground_cut, "points below this height are ground or grass");
  tool.add("--link-factor", &p.link_factor,
           "object clustering distance, in units of the crop's point spacing");
  tool.add_length("--link-min", &p.link_min, "object clustering distance: at least this (at most 1.5 m)");
  tool.add_length("--bridge", &p.bridge,
                  "join to the object a cluster beyond its end along the candidate's long axis, within its "
                  "width, at most this far in the top view (a windscreen's gap; 0: off)");
  tool.add_length("--bridge-length", &p.bridge_length,
                  "--bridge joins only while the object stays this short");
  tool.add("--bridge-fill", &p.bridge_fill,
           "fill leaves out of the rectangle the strips --bridge crossed, by the share of each that "
           "returned nothing (a vehicle's glass; false: the whole rectangle)");
  tool.add("--fill-empty-cells", &p.fill_empty_cells,
           "fill leaves out of any object's rectangle the cells (2 x the crop's spacing) that hold no return "
           "at all, not even the ground's (glass; instead of --bridge-fill's strips)");
  tool.add(
      "--fill-tile-ground", &p.fill_tile_ground,
      "where the crop has too little open ground to measure fill (closed canopy), measure it against "
      "the tile's open-ground density (--index's density.ground; none there (unless --fill-tile-first), or "
      "false: fill unmeasured, no refusal)");
  tool.add("--fill-tile-first", &p.fill_tile_first,
           "with --fill-tile-ground, where the tile has no open-ground density either (closed canopy), "
           "measure fill against its first-return density (--index's density.first: one per pulse; false: "
           "fill unmeasured there)");
  tool.add("--bridge-min-share", &p.bridge_min_share,
           "--bridge joins only a cluster holding at least this share of the object's points (0: any)");
  tool.add("--max-echo-widening", &p.max_echo_widening,
           "with echo_width in the candidate: an object whose median echo is wider than this many times "
           "the open ground's is vegetation_like, one at or under it is hard and ground_through does not "
           "refuse it (0: off)");
  tool.add("--echo-late", &p.echo_late,
           "with --max-echo-widening: late_returns does not refuse a hard object either");
  tool.add("--echo-late-drawbar", &p.echo_late_drawbar,
           "with --echo-late: a hard object whose late_returns the cue waived is a drawbar (trailer) "
           "when its narrower end is narrower than this share of the width (if above --drawbar-width) "
           "and lower than --drawbar-level x the height (0: --drawbar-width)");
  tool.add("--echo-late-widening", &p.echo_late_widening,
           "with --echo-late: late_returns is waived only for an object whose median echo is at most "
           "this many times the open ground's (0: every hard object, --max-echo-widening)");
  tool.add("--join-stacked", &p.join_stacked,
           "join to the object the clusters that meet it in the top view beside it and in line with it "
           "(parts at two heights whose step the nadir view did not sample; false: one cluster)");
  tool.add("--min-points", &p.min_points, "fewer object points: too_sparse");
  tool.add("--min-density", &p.min_density, "fewer object points per m^2 of its rectangle: too_sparse");
  tool.add("--edge-factor", &p.edge_factor, "size correction: length and width + this x the point spacing");
  tool.add("--height-quantile", &p.height_quantile, "height = this quantile of the object's heights");
  tool.add_length("--size-sigma", &p.size_sigma, "size uncertainty at any density");
  tool.add("--spacing-sigma", &p.spacing_sigma, "size uncertainty per unit of point spacing");
  tool.add("--size-gate", &p.size_gate, "a size may miss a class range by this many uncertainties");
  tool.add_length("--plateau-drop", &p.plateau_drop, "profile within this (+ 10% of H) of the top: plateau");
  tool.add("--roughness", &cli.roughness,
           "what --max-roughness reads: plane (a cell's top against the plane of its 3 x 3 "
           "neighbours' tops) or line (against the line through its nearest neighbours, along the "
           "smoothest of four directions; fitted with --max-roughness 0.20, docs/decisions/classify.md §19)")
      ->check(CLI::IsMember({"line", "plane"}));
  tool.add("--max-roughness", &p.max_roughness,
           "rougher top (median residual of a cell's top, --roughness) than this x the spacing (and "
           "--roughness-floor): vegetation_like");
  tool.add_length("--roughness-floor", &p.roughness_floor,
                  "the --max-roughness threshold is at least this (the cells' own floor of 0.3 m = 1.5 "
                  "spacings gives --max-roughness x 0.2 m; docs/decisions/classify.md §28)");
  tool.add("--max-roughness-line", &p.max_roughness_line,
           "with --roughness plane, a top over its threshold is refused only when its roughness along lines "
           "is over this x the spacing (at least 0.2 m: the cells' floor) too: equipment on a roof "
           "(docs/decisions/classify.md §43; 0: off)");
  tool.add("--max-below-share", &p.max_below_share,
           "more interior object points with an object point 0.5 m above them: vegetation_like");
  tool.add("--max-ground-through", &p.max_ground_through,
           "more interior ground returns under an object point (share of interior returns): vegetation_like");
  tool.add("--min-fill", &p.min_fill,
           "fewer points per m^2 of the rectangle than this x the open ground's around it: vegetation_like");
  tool.add("--max-late-returns", &p.max_late_returns,
           "more object points with return_number > 1 (LAS): vegetation_like");
  tool.add("--min-plateau", &p.min_plateau,
           "less of its length within the plateau (no roof): not_vehicle_shape (0: off)");
  tool.add("--min-end-fill", &p.min_end_fill,
           "an end fifth's top view filled less than this x the middle's (a drawbar, an ellipse): "
           "not_vehicle_shape, but for tanks (0: off)");
  tool.add("--min-notch", &p.min_notch,
           "a car-group answer needs a bonnet or boot under its cabin: its top's profile this far (share "
           "of H) under the profile's upper hull; else not_vehicle_shape (0: off)");
  tool.add("--max-notch", &p.max_notch,
           "a tracked, van or bus answer whose profile lies more than this (share of H) under its upper "
           "hull (a body behind a drawbar): not_vehicle_shape (0: off)");
  tool.add("--drawbar-width", &p.drawbar_width,
           "an end narrower than this share of the width and lower than --drawbar-level x the height "
           "is a drawbar (trailer, caravan): not_vehicle_shape (0: off)");
  tool.add("--drawbar-level", &p.drawbar_level,
           "see --drawbar-width: the drawbar's highest point, share of the height (0: off)");
  tool.add("--min-rectangularity", &p.min_rectangularity,
           "a car-group answer whose top view's convex hull fills less than this share of its minimum-area "
           "rectangle (an oval outline: a rock; an ellipse 0.785) and a notch under --rectangularity-notch: "
           "not_vehicle_shape (0: off)");
  tool.add("--min-shoulder", &p.min_shoulder,
           "a car- or van-group answer whose sides, in the middle of its length, reach less than this share "
           "of its height (a body narrowing upward: a stack of logs or pipes, a tent): not_vehicle_shape "
           "(0: off; classify.md §30)");
  tool.add("--max-rim", &p.max_rim,
           "a car- or van-group answer whose sides, in the middle of its length, stand more than this share "
           "of its height above its centre (an open top: a flatbed's side boards, an open box's walls; a "
           "car's or van's roof is highest across its middle): not_vehicle_shape (0: off; classify.md §38)");
  tool.add("--min-bed", &p.min_bed,
           "a top whose bed is at least this share of its height (at an end, its sides stand over its "
           "centre and under its top: a pickup's open bed behind its cab) is answered no car- or van-group "
           "class but a pickup (0: off; classify.md §39)");
  tool.add("--rectangularity-notch", &p.rectangularity_notch,
           "see --min-rectangularity: only an answer whose top's profile lies within this (share of H) of "
           "its upper hull is refused (a stepped car is kept; 1: the outline alone)");
  tool.add("--rectangularity-sampled", &p.rectangularity_sampled,
           "see --min-rectangularity: the step is measured over the profile's bins holding at least half "
           "the median bin's points (a bin with less than one row of samples across may have lost its "
           "top; classify.md §37; false: every bin)");
  tool.add("--plateau-split", &p.plateau_split, "plateau share between a minor and a long roof");
  tool.add("--tail-split", &p.tail_split,
           "higher end's level (share of H) between dropping and staying at the roof");
  tool.add("--profile-penalty", &p.profile_penalty,
           "size-sigmas added to a class whose profile the top contradicts");
  tool.add("--box-plateau", &p.box_plateau, "plateau share of a flat box (not a vehicle unless a bus)");
  tool.add("--box-ends", &p.box_ends, "end level (share of H) of a flat box");
  tool.add("--model-density", &p.model_density,
           "points/m^2 the model-level chain needs (for the reason text)");
  tool.add("--by-pass", &p.by_pass,
           "fill and ground_through count only the ground of the flight passes (point_source_id, "
           "gps_time) that saw the object");
  tool.add("--sight-lines", &p.sight_lines,
           "below_share and ground_through count only the points whose line toward the sensor "
           "(sensor_x/y/z) passes through the object above them (false: every point)");
  tool.add("--late-returns-inside", &p.late_returns_inside,
           "late_returns counts a later return only when every earlier return of its pulse "
           "(point_source_id, gps_time) is in the crop at or below the object's top (false: every "
           "return_number > 1)");
  tool.add("--late-shadow", &p.late_shadow,
           "late_returns weighs a later return whose pulse met something first above the object or "
           "outside the crop by the share of the ground around the object that is shadowed too "
           "(later returns; false: every return_number > 1 counts)");
  tool.add("--ground-through-edges", &p.ground_through_edges,
           "ground_through does not count a ground return whose pulse's earlier returns are all "
           "object points on the edge of their layer (a footprint split by an edge; false: every "
           "ground return)");
  tool.add("--pass-share", &p.pass_share, "a pass saw the object when it holds this share of its points");
  tool.add("--entry-classes", &p.entry_classes,
           "the --modelbase entries with a class are class ranges too (their size +- --entry-tolerance)");
  tool.add("--entry-tolerance", &p.entry_tolerance,
           "an entry's class range: its L W H x [1 - this, 1 + this]");
  tool.add("--entry-profile", &p.entry_profile,
           "an entry's class range is no class for a top whose plateau share or end levels differ from "
           "the entry's own (its surface measured as a candidate) by more than this share (0: off)");
  tool.add("--modelbase-classes-only", &p.modelbase_classes_only,
           "with --modelbase entries that have a class, a family's range is a class only if its name or "
           "group is one of theirs (docs/decisions/open-set.md)");
  tool.add("--family-entries", &p.family_entries,
           "with --modelbase-classes-only, a family's range is a class only when at least this many "
           "entries name it (its name or group; 1: one entry keeps its family)");
  tool.add("--class-envelope", &p.class_envelope,
           "for each class with two or more --modelbase entries, one more class range: the smallest box "
           "holding their L W H, x [1 - this, 1 + this] (docs/decisions/open-set.md; 0: off)");
}

// Modelbase entries that carry a class (<model>.class, else `classes`): their surfaces'
// label-1 extents.
std::vector<cl::ModelEntry> read_modelbase(const std::string& dir,
                                           const std::map<std::string, std::string>& classes,
                                           const cl::Params& p) {
  std::vector<cl::ModelEntry> out;
  for (const canopy::documents::ModelbaseEntry& e : canopy::documents::list_modelbase(dir)) {
    std::optional<std::string> cls = canopy::documents::read_model_class(dir, e.name);
    if (!cls) {
      const auto it = classes.find(e.name);
      if (it == classes.end()) continue;
      cls = it->second;
    }
    const std::string surface = (fs::path(dir) / (e.name + ".pcd")).string();
    const fm::PointCloud pc = fm::read_points(surface, "classify");
    pc.require({"x", "y", "z"}, surface, "is this a modelbase surface?");
    // (a label field of 0 everywhere, fitvox's for unlabelled input, carries no labels)
    const std::vector<double>* label = fm::carries_labels(pc) ? &pc.col("label") : nullptr;
    // Its label-1 points, as a candidate (ground z = 0): their extents and its top's profile.
    cl::Candidate c;
    for (std::size_t i = 0; i < pc.size(); ++i) {
      if (!label || (*label)[i] == 1) c.points.emplace_back(pc.col("x")[i], pc.col("y")[i], pc.col("z")[i]);
    }
    if (c.points.empty())
      throw cm::DataError(surface, "has no vehicle points (label 1) to measure the model");
    Eigen::Vector3d lo = c.points.front(), hi = lo;
    for (const Eigen::Vector3d& v : c.points) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    cl::ModelEntry entry{e.name, *cls, {hi.x() - lo.x(), hi.y() - lo.y(), std::max(0.0, hi.z())}, std::nullopt};
    const cl::Features f = cl::measure(c, p);
    if (f.object_points >= p.min_points)
      entry.profile = cl::ModelEntry::Profile{f.plateau_share, f.end_low, f.end_high, f.end_fill};
    out.push_back(std::move(entry));
  }
  return out;
}

std::string summary(const cl::Answer& a) {
  char line[512];
  const auto& f = a.features;
  if (!a.cls.empty()) {
    std::snprintf(line, sizeof line,
                  "%s (%s), confidence %.2f; %.2f x %.2f x %.2f m, heading %.1f deg (or +180), %zu points, "
                  "%.1f points/m^2",
                  a.cls.c_str(), a.group.c_str(), a.confidence, f.length, f.width, f.height,
                  f.heading * 180 / 3.14159265358979323846, f.object_points, f.density);
  } else {
    std::snprintf(line, sizeof line, "none (%s): %s", a.reason.c_str(), a.detail.c_str());
  }
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  cm::Tool tool("classify",
                "Class-level answer for one detect candidate: vehicle class and group (car, van, "
                "truck, bus, tracked, machine), heading (180-degree ambiguity), size and density, "
                "or none with a reason (too_sparse, vegetation_like, too_small, too_large, too_flat, "
                "not_vehicle_shape). Writes a canopy.verdict with \"level\": \"class\".");
  tool.without_threads();
  cl::Params p;
  Cli cli;
  bind(tool, p, cli);
  return tool.run(argc, argv, [&] {
    p.roughness = cli.roughness == "plane" ? cl::Params::Roughness::kPlane : cl::Params::Roughness::kLine;
    cl::validate(p);
    if (!cli.index.empty() && !cli.transform.empty()) {
      throw cm::UsageError("--index and --transform both give the pose: use one");
    }
    if (!cli.candidate.empty() && cli.index.empty()) throw cm::UsageError("--candidate needs --index");
    std::optional<Eigen::Isometry3d> to_tile;
    if (!cli.transform.empty()) to_tile = cl::parse_transform(cli.transform);

    cm::log::Phase read("read");
    cl::Inputs in;
    in.name = cm::display_name(cli.in);
    in.cloud = fm::read_points(cli.in, "classify");
    if (!cli.index.empty()) {
      std::string id = cli.candidate;
      if (id.empty()) {
        if (cli.in == "-") throw cm::UsageError("--index with stdin input needs --candidate");
        id = fs::path(cli.in).stem().string();
      }
      // (read_candidates refuses a density.ground that is not a number >= 0 or null, naming the file)
      const canopy::documents::Candidates index =
          canopy::documents::read_candidates(cm::read_file(cli.index), cli.index);
      to_tile = cl::index_transform(index, cli.index, id);
      if (p.fill_tile_ground) in.tile_ground_density = index.density_ground();
      if (p.fill_tile_ground && p.fill_tile_first && !in.tile_ground_density) {
        in.tile_ground_density = index.density_first();
        in.tile_ground_from_first = in.tile_ground_density.has_value();
      }
    } else if (p.fill_tile_ground) {
      throw cm::UsageError("--fill-tile-ground needs --index (the tile's open-ground density)");
    }
    std::vector<cl::ModelEntry> entries;
    if (!cli.model_classes.empty() && cli.modelbase.empty())
      throw cm::UsageError("--model-classes needs --modelbase");
    std::map<std::string, std::string> classes;
    if (!cli.model_classes.empty())
      classes = canopy::documents::parse_model_classes(cm::read_file(cli.model_classes), cli.model_classes);
    if (!cli.modelbase.empty()) entries = read_modelbase(cli.modelbase, classes, p);
    in.modelbase = entries;
    read.done(std::to_string(in.cloud.size()) + " candidate points" +
              (cli.modelbase.empty()
                   ? ""
                   : ", " + std::to_string(entries.size()) + " modelbase entries with a class"));

    cm::log::Phase phase("classify");
    const cl::Answer a = cl::run(p, in);
    cl::Document doc;
    std::vector<std::string> inputs = {cli.in};
    if (!cli.index.empty()) inputs.push_back(cli.index);
    if (!cli.modelbase.empty()) inputs.push_back(cli.modelbase);
    if (!cli.model_classes.empty()) inputs.push_back(cli.model_classes);
    doc.provenance = {"classify", CANOPY_VERSION, tool.parameters(), inputs};
    doc.candidate = cli.in;
    doc.transform = to_tile;
    doc.nearest = cl::nearest(a, entries);
    phase.done(summary(a));
    cm::write_file_atomic(cli.out, cl::serialize(a, p, doc));
  });
}
