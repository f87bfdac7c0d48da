// topview: tile scan + detections.json [+ truth.json [+ score.json]] -> a PNG from straight
// above with the footprints outlined (right, wrong, false alarm, missed in their colours).
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "topview/topview.h"

using namespace canopy;
using Json = nlohmann::json;

namespace {

Json read_json(const std::string& path, const char* format) {
  Json j;
  try {
    j = Json::parse(common::read_file(path));
  } catch (const Json::parse_error& e) {
    throw common::DataError(path, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("format") || j["format"] != format) {
    throw common::DataError(path, std::string("not a ") + format + " document");
  }
  return j;
}

topview::Ring ring_of(const Json& fp, const std::string& path, const std::string& where) {
  topview::Ring r;
  if (!fp.is_array() || fp.size() < 3 || fp.size() > 64)
    throw common::DataError(path, where + ": not a footprint polygon");
  for (const auto& p : fp) {
    if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number()) {
      throw common::DataError(path, where + ": a corner is not [x, y]");
    }
    r.push_back({p[0].get<double>(), p[1].get<double>()});
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("topview",
                    "A tile from straight above (highest point per pixel, grey by height) with the "
                    "footprints of the detections and, if given, of the true vehicles, coloured by "
                    "the score's outcome: right green, wrong model orange, false alarm magenta, "
                    "missed yellow.");
  tool.without_threads();
  std::string in, out, detections, truth, score;
  int tile = 0, size = 1024;
  tool.add_input(&in, "the tile scan (PCD, PLY or LAS with x y z)");
  tool.add_output(&out, "PNG");
  tool.add("--detections", &detections, "detections.json (canopy.detections v1)");
  tool.add("--truth", &truth, "truth.json (canopy.scene_truth v1): true footprints");
  tool.add("--score", &score, "score.json (canopy.scene_score v1): colours by outcome");
  tool.add("--tile", &tile, "this tile's index in the score's tiles");
  tool.add("--size", &size, "pixels along the longer side");
  return tool.run(argc, argv, [&] {
    if (in.empty() || in == "-" || out.empty() || out == "-")
      throw common::UsageError("-i and -o must name files");
    if (detections.empty()) throw common::UsageError("--detections is required");
    if (size < 16 || size > 8192) throw common::UsageError("--size must be in [16, 8192]");
    if (!score.empty() && truth.empty()) throw common::UsageError("--score needs --truth");
    if (tile < 0) throw common::UsageError("--tile must be >= 0");
    common::check_output(out);
    const Json d = read_json(detections, "canopy.detections");
    std::map<std::string, std::string> outcome;  // candidate -> right/wrong/false_alarm
    std::set<long long> missed;
    if (!score.empty()) {
      const Json s = read_json(score, "canopy.scene_score");
      if (!s.contains("tiles") || !s["tiles"].is_array() || tile >= static_cast<int>(s["tiles"].size())) {
        throw common::DataError(score, "has no tile " + std::to_string(tile));
      }
      for (const auto& m : s.value("matches", Json::array())) {
        if (m.value("tile", -1) != tile) continue;
        if (m["outcome"] == "missed") {
          missed.insert(m["instance"].get<long long>());
        } else {
          outcome[m["candidate"].get<std::string>()] = m["outcome"].get<std::string>();
        }
      }
    }
    std::vector<topview::Shape> shapes;
    if (!truth.empty()) {
      const Json t = read_json(truth, "canopy.scene_truth");
      std::size_t k = 0;
      for (const auto& v : t.value("vehicles", Json::array())) {
        const std::string where = "vehicles[" + std::to_string(k++) + "]";
        const bool miss = missed.count(v.value("instance", -1LL)) > 0;
        shapes.push_back(
            {ring_of(v.value("footprint", Json()), truth, where), miss ? topview::kMissed : topview::kTruth});
      }
    }
    std::size_t k = 0;
    for (const auto& det : d.value("detections", Json::array())) {
      const std::string where = "detections[" + std::to_string(k++) + "]";
      topview::Rgb c = topview::kDetection;
      if (!score.empty()) {
        const auto it = outcome.find(det.value("candidate", std::string()));
        c = it == outcome.end()     ? topview::kDetection
            : it->second == "right" ? topview::kRight
            : it->second == "wrong" ? topview::kWrong
                                    : topview::kFalseAlarm;
      }
      shapes.push_back({ring_of(det.value("footprint", Json()), detections, where), c});
    }
    const formats::PointCloud scan = formats::read_points(in, "topview");
    scan.require({"x", "y", "z"}, common::display_name(in), "is this a point cloud?");
    const topview::Image img = topview::render(scan, shapes, size);
    common::write_file_atomic(out, topview::encode_png(img));
    common::log::info(std::to_string(img.width) + " x " + std::to_string(img.height) + " pixels, " +
                      std::to_string(img.pixel * 1000).substr(0, 6) + " mm a pixel, " +
                      std::to_string(shapes.size()) + " footprints");
  });
}
