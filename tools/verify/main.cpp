// verify: check gmatch's top hypotheses against the candidate's points; answer a model with a
// pose and a confidence, or "none".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>

#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/pcd.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/formats/sensor_direction.h"
#include "canopy/formats/trajectory.h"
#include "canopy/documents/verdict.h"
#include "verify/verify.h"

namespace cm = canopy::common;
namespace doc = canopy::documents;
namespace fm = canopy::formats;
namespace vf = canopy::verify;

namespace {

// The options beside verify::Params.
struct Cli {
  std::string in = "-", out = "-", points, segments, modelbase, transform;
  std::string free_space = "unseen";
  std::string sensor_direction = "auto", trajectory;
  std::string check_trajectory;       // the mode that checks a trajectory file alone
  double trajectory_tolerance = 1.0;  // s
  bool no_flip = false;
  bool no_box = false;
};

void bind(cm::Tool& tool, vf::Params& p, Cli& cli) {
  tool.add_input(&cli.in, "match result JSON (gmatch's, or baseline --hypotheses')");
  tool.add_output(&cli.out, "verdict JSON");
  CLI::Option* points = tool.add("--points", &cli.points,
                                 "candidate points PCD with normals and sensor directions "
                                 "(fitvox samples)")
                            ->required();
  tool.add("--segments", &cli.segments,
           "candidate segment graph JSON (the one gmatch matched); not needed for a match result "
           "without segment pairs (baseline --hypotheses': each model's start is its pose)");
  CLI::Option* modelbase =
      tool.add("--modelbase", &cli.modelbase,
               "directory of <model>.json graphs, <model>.pcd surfaces and "
               "optional <model>.class classes; a surface's label-1 points are the model, or, when it "
               "carries no labels (no label field, or 0 on every point: fitvox on unlabelled points), "
               "its points above 5 cm")
          ->required();
  tool.add("--transform", &cli.transform,
           "candidate frame -> tile frame, 12 or 16 numbers row-major (detect's index.json "
           "transform); adds pose_tile");
  tool.add("-k,--top-k", &p.top_k, "gmatch hypotheses checked");
  tool.add_length("--min-height", &p.min_height, "candidate points below this z are ground");
  tool.add_length("--inlier-distance", &p.inlier_distance,
                  "point-to-plane distance counted as on the model surface");
  tool.add_length("--inlier-radius", &p.inlier_radius, "and within this of the nearest model sample");
  tool.add("--seen-spacing", &p.seen_spacing,
           "free space: a model sample counts as seen with a candidate point within max(--inlier-radius, "
           "this x the candidate's point spacing) (the median nearest-neighbour distance of its points "
           "above --min-height); 0 = --inlier-radius alone, the test before");
  tool.add("--facing", &p.facing, "model surface counts for a view when normal . sensor >= this");
  tool.add_length("--ray-cell", &p.ray_cell, "cell of the per-view depth buffers");
  tool.add_length("--occlusion-margin", &p.occlusion_margin,
                  "a scan point this much nearer the sensor hides model surface");
  tool.add("--free-space", &cli.free_space,
           "unseen: expected-visible model surface without a scan point violates free space; "
           "through: only where the view's depth cell holds a scan point")
      ->check(CLI::IsMember({"unseen", "through"}));
  tool.add("--sensor-direction", &cli.sensor_direction,
           "direction toward the sensor of each point: columns (sensor_x/y/z), trajectory "
           "(--trajectory at the point's gps_time), scan-angle (scan_angle + flight direction "
           "from gps_time), vertical; auto: the first of these the points allow")
      ->check(CLI::IsMember({"auto", "columns", "trajectory", "scan-angle", "vertical"}));
  tool.add("--trajectory", &cli.trajectory,
           "sensor trajectory (formats/README.md, Trajectory) in the tile's frame; --transform "
           "maps the points into it");
  tool.add("--trajectory-tolerance", &cli.trajectory_tolerance,
           "seconds a point's gps_time may lie beyond the trajectory's ends");
  // (CLI11 runs the options' callbacks in their order, -i's first, and then checks the
  // required ones: given, this mode needs neither --points nor --modelbase, and reads no -i.)
  tool.add("--check-trajectory", &cli.check_trajectory,
           "instead: read this file as --trajectory reads it, say what it holds and exit (1 with "
           "the line and the problem when it is not a trajectory); needs no other option (make "
           "tile checks TRAJECTORY= so before detect)")
      ->each([points, modelbase, &cli](const std::string& file) {
        if (file.empty()) return;
        points->required(false);
        modelbase->required(false);
        cli.in.clear();  // no -i is read: stdin on a terminal is no error (common::Tool::run)
      });
  tool.add_length("--icp-coarse", &p.icp_coarse, "ICP correspondence distance, first stage");
  tool.add_length("--icp-fine", &p.icp_fine, "ICP correspondence distance, second stage");
  tool.add("--icp-iterations", &p.icp_iterations, "ICP iterations per stage (0 = no ICP), at most 500");
  tool.add("--icp-points", &p.icp_points, "candidate points ICP uses at most (even stride)");
  tool.add_flag("--no-flip", &cli.no_flip, "do not try the 180-degree flip of each start")
      ->default_str("false");
  tool.add_angle("--max-tilt", &p.max_tilt,
                 "how far a posed model's vertical may lean from the tile's vertical (a parked vehicle "
                 "stands upright); a hypothesis posed only beyond it scores 0 (180deg: no bound)");
  tool.add("--accept", &p.accept, "answer none when the best score is below this");
  tool.add("--box-margin", &p.box_margin,
           "answer a model only when its score beats the null hypothesis's (a plain box of the "
           "candidate's extent) by at least this");
  tool.add_flag("--no-box", &cli.no_box, "check no null-hypothesis box (the decision without it)")
      ->default_str("false");
  tool.add("--conf-bias", &p.conf_bias, "confidence logistic: bias");
  tool.add("--conf-score", &p.conf_score, "confidence logistic: weight of the score");
  tool.add("--conf-margin", &p.conf_margin, "confidence logistic: weight of the margin over the next model");
  tool.add("--conf-box", &p.conf_box, "confidence logistic: weight of the score's margin over the box's");
  tool.add("--none-bias", &p.none_bias, "none's confidence logistic (a vehicle is there): bias");
  tool.add("--none-score", &p.none_score, "none's confidence logistic: weight of the best score");
  tool.add("--none-margin", &p.none_margin,
           "none's confidence logistic: weight of the margin over the next model");
  tool.add("--none-box", &p.none_box,
           "none's confidence logistic: weight of the best score's margin over the box's");
}

// "r00,r01,r02,t0,r10,...,t2[,0,0,0,1]" (12 or 16 numbers, row-major) -> candidate->tile.
Eigen::Isometry3d parse_transform(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    // Decimal numbers only: std::stod alone would also take "0x1p0", "inf" and " 1".
    if (item.empty() || cm::decimal_prefix(item) != item.size()) {
      throw cm::UsageError("--transform: '" + item + "' is not a decimal number");
    }
    try {
      v.push_back(std::stod(item));
    } catch (const std::exception&) { throw cm::UsageError("--transform: '" + item + "' is out of range"); }
  }
  if (v.size() != 12 && v.size() != 16) {
    throw cm::UsageError("--transform needs 12 or 16 comma-separated numbers (row-major 3x4 or 4x4)");
  }
  // A 4x4's fourth row is 0,0,0,1: anything else is no rigid transform written row-major, most
  // likely a column-major one, whose translation would be dropped here (review F15, stop 71).
  if (v.size() == 16 && !(v[12] == 0 && v[13] == 0 && v[14] == 0 && v[15] == 1)) {
    std::ostringstream row;
    row << v[12] << "," << v[13] << "," << v[14] << "," << v[15];
    throw cm::UsageError("--transform: the fourth row of a 4x4 must be 0,0,0,1, not " + row.str() +
                         " (the matrix is read row-major: a column-major one?)");
  }
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) M(r, c) = v[4 * r + c];
  }
  Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if (!M.allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0) {
    throw cm::UsageError("--transform: the 3x3 part is not a rotation");
  }
  return Eigen::Isometry3d(M);
}

// What the check reads: the match, the candidate's graph and points, the hypotheses' models.
struct Loaded {
  doc::MatchResult match;
  doc::SegmentGraph graph;
  vf::Candidate candidate;
  std::vector<vf::Model> models;
};

Loaded read_inputs(const Cli& cli, const vf::Params& p, const std::optional<Eigen::Isometry3d>& to_tile) {
  Loaded in;
  in.match = doc::read_match_result(cli.in);
  if (in.match.models.empty()) throw cm::DataError(cm::display_name(cli.in), "match result ranks no model");
  if (!cli.segments.empty()) {
    in.graph = doc::read_segment_graph(cli.segments);
  } else {
    // Without the graph the pairs name nothing: only a match result without pairs (baseline
    // --hypotheses') is checked without it.
    for (const auto& m : in.match.models) {
      if (!m.pairs.empty()) {
        throw cm::UsageError("--segments is needed: " + cm::display_name(cli.in) + " pairs " + m.model +
                             " with segments of the candidate's graph (a gmatch match result)");
      }
    }
  }
  const fm::PointCloud cloud = fm::read_pcd(cli.points);
  // Sensor directions (issue 26): the columns when present (the simulator's path, unchanged),
  // else derived from what the points carry.
  fm::SensorDirectionOptions so;
  so.source = fm::parse_sensor_source(cli.sensor_direction, "--sensor-direction");
  fm::Trajectory trajectory;
  if (!cli.trajectory.empty()) {
    trajectory = fm::read_trajectory(cli.trajectory);
    so.trajectory = &trajectory;
    so.trajectory_name = cm::display_name(cli.trajectory);
  }
  so.tolerance = cli.trajectory_tolerance;
  if (to_tile) so.to_world = *to_tile;
  const fm::SensorDirections sd = fm::sensor_directions(cloud, so, cm::display_name(cli.points));
  for (const auto& w : sd.warnings) cm::log::warn(w);
  if (sd.used == fm::SensorSource::kColumns) {
    in.candidate = vf::candidate_from_cloud(cloud, cli.points);
  } else {
    cm::log::info(sd.summary);
    in.candidate = vf::candidate_from_cloud(cloud, cli.points, &sd.directions);
  }
  std::vector<std::string> names;
  for (int i = 0; i < p.top_k && i < static_cast<int>(in.match.models.size()); ++i) {
    names.push_back(in.match.models[i].model);
  }
  in.models = vf::read_models(cli.modelbase, names, cm::display_name(cli.in));
  return in;
}

// The check phase's INFO line: the answer (or none), its scores, the class.
std::string summary(const canopy::documents::Verdict& v) {
  char line[256];
  if (v.chosen >= 0) {
    const auto& h = v.hypotheses[v.chosen];
    const auto e = fm::euler_degrees(h.pose);
    std::snprintf(line, sizeof line,
                  "%s, confidence %.3f (score %.3f: explained %.3f, free-space violation %.3f, "
                  "rms %.1f mm, heading %.1f deg)",
                  v.model.c_str(), v.confidence, h.score, h.explained, h.free_space_violation,
                  h.fit_rms * 1e3, e[0]);
  } else {
    std::snprintf(line, sizeof line, "none, confidence %.3f", v.confidence);
  }
  std::string said = line;
  if (v.has_classes) {
    std::snprintf(line, sizeof line, "; class %s (nearest instance %s, score %.3f, margin %.3f)",
                  v.vehicle_class.empty() ? "none" : v.vehicle_class.c_str(),
                  v.nearest_instance.empty() ? "none" : v.nearest_instance.c_str(), v.class_score,
                  v.class_margin);
    said += line;
  }
  return said;
}

// --check-trajectory: the file read as --trajectory reads it (formats::read_trajectory), its
// samples and span said.
void check_trajectory(const std::string& path) {
  const fm::Trajectory t = fm::read_trajectory(path);
  char span[96];
  std::snprintf(span, sizeof span, "time %.15g to %.15g s", t.samples.front().time, t.samples.back().time);
  cm::log::info(cm::display_name(path) + ": a canopy trajectory of " + std::to_string(t.samples.size()) +
                (t.samples.size() == 1 ? " sample, " : " samples, ") + span);
}

}  // namespace

int main(int argc, char** argv) {
  cm::Tool tool("verify",
                "Checks gmatch's top hypotheses against the candidate's points (pose by segment "
                "pairs + point-to-plane ICP, explained share and free-space violation); writes "
                "a canopy.verdict JSON: a model with pose and confidence, or none.");
  tool.without_threads();
  vf::Params p;
  Cli cli;
  bind(tool, p, cli);
  return tool.run(argc, argv, [&] {
    if (!cli.check_trajectory.empty()) return check_trajectory(cli.check_trajectory);
    p.flip = !cli.no_flip;
    p.box = !cli.no_box;
    p.free_space_through = cli.free_space == "through";
    vf::validate(p);
    std::optional<Eigen::Isometry3d> to_tile;
    if (!cli.transform.empty()) to_tile = parse_transform(cli.transform);
    if (!(cli.trajectory_tolerance >= 0) || !std::isfinite(cli.trajectory_tolerance)) {
      throw cm::UsageError("--trajectory-tolerance must be a finite number of seconds >= 0");
    }
    if (cli.sensor_direction == "trajectory" && cli.trajectory.empty()) {
      throw cm::UsageError("--sensor-direction trajectory needs --trajectory FILE");
    }

    cm::log::Phase read("read");
    const Loaded in = read_inputs(cli, p, to_tile);
    vf::check_inputs_belong({&in.match, cli.in, cli.segments.empty() ? nullptr : &in.graph, cli.segments,
                             &in.candidate, cli.points});
    read.done(std::to_string(in.candidate.points.size()) + " candidate points, " +
              std::to_string(in.models.size()) + " hypotheses");

    cm::log::Phase phase("check");
    canopy::documents::Verdict v =
        vf::run(p, {&in.candidate, &in.graph, &in.match, &in.models, to_tile ? &*to_tile : nullptr});
    // --free-space and the sensor direction options at their defaults are left out of the
    // provenance: verdicts stay byte-identical to those written before the options existed.
    auto parameters = tool.parameters();
    const bool trajectory_default = cli.trajectory.empty() && cli.trajectory_tolerance == 1.0;
    parameters.erase(
        std::remove_if(parameters.begin(), parameters.end(),
                       [&](const auto& kv) {
                         // --no-box: the verdict of before the null hypothesis existed.
                         // --seen-spacing 0: the verdict of before the option existed.
                         // No --segments (a match result without pairs): nothing to record.
                         return (kv.first == "segments" && cli.segments.empty()) ||
                                ((kv.first == "box-margin" || kv.first == "no-box") && !p.box) ||
                                (kv.first == "seen-spacing" && p.seen_spacing == 0) ||
                                (kv.first == "free-space" && !p.free_space_through) ||
                                (kv.first == "sensor-direction" && cli.sensor_direction == "auto") ||
                                (kv.first == "trajectory" && cli.trajectory.empty()) ||
                                (kv.first == "trajectory-tolerance" && trajectory_default) ||
                                kv.first == "check-trajectory";
                       }),
        parameters.end());
    std::vector<std::string> inputs{cli.in, cli.points, cli.segments, cli.modelbase};
    if (cli.segments.empty()) inputs.erase(inputs.begin() + 2);
    if (!cli.trajectory.empty()) inputs.push_back(cli.trajectory);
    v.provenance = {"verify", CANOPY_VERSION, parameters, inputs};
    v.candidate = cli.points;
    phase.done(summary(v));
    canopy::documents::write_verdict(v, cli.out);
  });
}
