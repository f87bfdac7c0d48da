// Reading the footprints topview draws from the detections (v1 or v2), truth, score and
// candidates index documents, each through its documents/ reader; every member topview uses is
// checked, the error naming the file and the member.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/candidates.h"
#include "canopy/documents/detections.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/scene_truth.h"
#include "canopy/formats/json_document.h"
#include "topview/topview.h"

namespace canopy::topview {
namespace {

using Malformed = formats::MalformedField;

// The score's matches of this tile: the outcome of each candidate (right, wrong,
// false_alarm) and the missed vehicles' instances. The reader checks every match, not only the
// tile's: a right, wrong or false_alarm row names its candidate (once per tile), a missed row its
// instance.
struct Outcomes {
  std::map<std::string, std::string> of_candidate;
  std::set<long long> missed;
};

// The score's tile of `detections` (Params::tile -1): the one whose "detections" is that path
// as given, else the only tile of the score.
int tile_of(const documents::SceneScore& s, const std::string& path, const std::string& detections) {
  int found = -1;
  for (std::size_t k = 0; k < s.tiles.size(); ++k) {
    if (s.tiles[k].detections != detections) continue;
    if (found >= 0)
      throw common::DataError(path, "lists the detections " + detections + " twice: give --tile");
    found = static_cast<int>(k);
  }
  if (found >= 0) return found;
  if (s.tiles.size() == 1) return 0;
  throw common::DataError(path, "has no tile whose detections is " + detections + " (" +
                                    std::to_string(s.tiles.size()) + " tiles): give --tile");
}

Outcomes read_outcomes(const std::string& path, int tile, const std::string& detections) {
  const documents::SceneScore s = documents::read_scene_score_file(path);
  if (tile < 0) tile = tile_of(s, path, detections);
  if (tile >= static_cast<int>(s.tiles.size())) {
    throw common::DataError(
        path, "has no tile " + std::to_string(tile) + " (" + std::to_string(s.tiles.size()) + " tiles)");
  }
  Outcomes o;
  for (const documents::ScoreMatch& m : s.matches) {
    if (m.tile != tile) continue;
    if (m.outcome == "missed") {
      o.missed.insert(*m.instance);
    } else {
      o.of_candidate.emplace(*m.candidate, m.outcome);
    }
  }
  return o;
}

// The score's outcome of a detection; its level when the score does not list it.
Kind detection_kind(const Outcomes& o, const std::string& candidate, Kind level) {
  const auto it = o.of_candidate.find(candidate);
  return it == o.of_candidate.end() ? level
         : it->second == "right"    ? Kind::right
         : it->second == "wrong"    ? Kind::wrong
                                    : Kind::false_alarm;
}

void add_truth(const std::string& path, const Outcomes& outcomes, std::vector<Shape>& shapes) {
  const documents::SceneTruth t = documents::read_scene_truth_file(path);
  for (std::size_t k = 0; k < t.vehicles.size(); ++k) {
    const documents::TrueVehicle& v = t.vehicles[k];
    if (v.footprint.empty()) {
      throw common::DataError(path, "vehicles[" + std::to_string(k) + "]: missing \"footprint\"");
    }
    const bool miss = outcomes.missed.count(v.instance) > 0;
    shapes.push_back({v.footprint, miss ? Kind::missed : Kind::truth});
  }
}

// A rejected candidate's kind by its "reason"; other reasons (and none given) are counted.
Kind reason_of(const documents::Rejection& r, std::map<std::string, int>& reasons) {
  const std::string reason = r.reason.value_or("not given");
  if (reason == "none") return Kind::none;
  if (reason == "failed") return Kind::failed;
  ++reasons[reason];
  return Kind::rejected;
}

// A candidate's footprint from detect's index: the length x width rectangle around "centre",
// its long side along "heading" (radians from +x), counter-clockwise.
Ring index_footprint(const documents::Candidate& c, const std::string& w) {
  if (!c.centre) throw Malformed(w + ": missing \"centre\"");
  if (!c.heading) throw Malformed(w + ": missing \"heading\"");
  const double l = c.length / 2, b = c.width / 2;
  const double h = *c.heading;
  const double ux = std::cos(h), uy = std::sin(h);
  const double x = (*c.centre)[0], y = (*c.centre)[1];
  Ring r;
  for (const auto& [sl, sb] : {std::pair{1, -1}, {1, 1}, {-1, 1}, {-1, -1}}) {
    r.push_back({x + sl * l * ux - sb * b * uy, y + sl * l * uy + sb * b * ux});
  }
  return r;
}

// The index to take the rejected candidates' footprints from (see read_footprints), or "".
std::string find_index(const Sources& sources, const documents::Detections& d) {
  if (!sources.index.empty()) return sources.index;
  if (d.index.empty()) return "";
  namespace fs = std::filesystem;
  const fs::path named(d.index);
  std::error_code ec;
  if (fs::is_regular_file(named, ec)) return named.string();
  const fs::path beside = fs::path(sources.detections).parent_path() / named;
  if (named.is_relative() && fs::is_regular_file(beside, ec)) return beside.string();
  return "";
}

// The rejected candidates' outlines (their footprints from the index) in the order listed.
void add_rejected(const Sources& sources, const documents::Detections& d, Footprints& out) {
  std::vector<std::pair<std::string, Kind>> wanted;
  for (const documents::Rejection& r : d.rejected)
    wanted.emplace_back(r.candidate, reason_of(r, out.reasons));
  // An --index given is read (and refused when unreadable) even when nothing was rejected: it was
  // ignored then, so a missing or malformed file passed with exit 0 (stop 68).
  if (wanted.empty() && sources.index.empty()) return;
  const std::string path = find_index(sources, d);
  if (path.empty()) {
    out.undrawn = static_cast<int>(wanted.size());
    common::log::warn(sources.detections + ": no candidates index found (--index names it): the " +
                      std::to_string(wanted.size()) + " rejected candidates are not drawn");
    return;
  }
  const documents::Candidates index = documents::read_candidates_file(path);
  try {
    std::map<std::string, std::size_t> at;
    for (std::size_t i = 0; i < index.candidates.size(); ++i) at.emplace(index.candidates[i].id, i);
    for (const auto& [id, kind] : wanted) {
      const auto it = at.find(id);
      if (it == at.end())
        throw Malformed("has no candidate \"" + id + "\" (rejected in " + sources.detections + ")");
      out.shapes.push_back(
          {index_footprint(index.candidates[it->second], "candidates[" + std::to_string(it->second) + "]"),
           kind});
    }
  } catch (const Malformed& e) { throw common::DataError(path, e.what()); }
}

void add_detections(const Sources& sources, const Outcomes* outcomes, Footprints& out) {
  const documents::Detections d = documents::read_detections_file(sources.detections);
  std::vector<Shape> found;
  for (std::size_t k = 0; k < d.detections.size(); ++k) {
    const documents::Detection& det = d.detections[k];
    if (det.footprint.empty()) {
      throw common::DataError(sources.detections,
                              "detections[" + std::to_string(k) + "]: missing \"footprint\"");
    }
    const Kind level = det.level == "class" ? Kind::cls : Kind::model;
    found.push_back({det.footprint, outcomes ? detection_kind(*outcomes, det.candidate, level) : level});
  }
  add_rejected(sources, d, out);
  out.shapes.insert(out.shapes.end(), found.begin(), found.end());
  out.detections_tile = d.tile;
}

// "x0 to x1, y y0 to y1" of a box {x0, y0, x1, y1}, to 0.1 m.
std::string span(const std::array<double, 4>& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x %.1f to %.1f, y %.1f to %.1f", b[0], b[2], b[1], b[3]);
  return buf;
}

}  // namespace

Footprints read_footprints(const Sources& sources, int tile) {
  const bool scored = !sources.score.empty();
  const Outcomes outcomes = scored ? read_outcomes(sources.score, tile, sources.detections) : Outcomes{};
  Footprints out;
  out.scored = scored;
  out.truth = !sources.truth.empty();
  if (out.truth) add_truth(sources.truth, outcomes, out.shapes);
  add_detections(sources, scored ? &outcomes : nullptr, out);
  out.detections_file = sources.detections;
  out.truth_file = sources.truth;
  return out;
}

void check_tile(const Footprints& footprints, const std::string& tile, const std::array<double, 4>& box) {
  const double m = kTileMargin;
  for (const bool truth : {false, true}) {
    std::size_t shapes = 0, within = 0;
    std::array<double, 4> all{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const Shape& s : footprints.shapes) {
      if ((s.kind == Kind::truth || s.kind == Kind::missed) != truth || s.ring.empty()) continue;
      std::array<double, 4> b{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
      for (const auto& p : s.ring) {
        b = {std::min(b[0], p[0]), std::min(b[1], p[1]), std::max(b[2], p[0]), std::max(b[3], p[1])};
      }
      all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]), std::max(all[3], b[3])};
      ++shapes;
      if (b[0] <= box[2] + m && b[2] >= box[0] - m && b[1] <= box[3] + m && b[3] >= box[1] - m) ++within;
    }
    if (shapes == 0 || within == shapes) continue;
    const std::string& file = truth ? footprints.truth_file : footprints.detections_file;
    const std::string what =
        truth ? "true vehicles' footprints" : "footprints (detections and rejected candidates)";
    const std::string recorded = !truth && !footprints.detections_tile.empty()
                                     ? " (they record the tile " + footprints.detections_tile + ")"
                                     : "";
    char margin[32];
    std::snprintf(margin, sizeof margin, "%g m", m);
    if (within == 0) {
      throw common::DataError(
          file, "none of its " + std::to_string(shapes) + " " + what + " lies within " + margin +
                    " of the points of " + tile + " (" + span(box) + "; the footprints: " + span(all) +
                    "): " + (truth ? "the truth" : "the detections") + " of another tile?" + recorded);
    }
    common::log::warn(file + ": " + std::to_string(shapes - within) + " of its " + std::to_string(shapes) +
                      " " + what + " lie more than " + margin + " outside the points of " + tile + " (" +
                      span(box) + "; the footprints: " + span(all) +
                      "): drawn, the map widened to hold them" + recorded);
  }
}

}  // namespace canopy::topview
