// score: detections of whole tiles against their ground truth (issue 16; formats/README.md
// "Scene scores", docs/decisions/scene-experiment.md).
//
// Matching, per tile: detections in order of falling confidence (ties: candidate id), each
// takes the nearest still unmatched true vehicle whose centre lies within `match_radius`
// (horizontal distance; ties: the lower instance id); a detection left without one is a false
// alarm, a true vehicle left without one is missed. So a duplicate detection of one vehicle
// is a false alarm, and dropping the detections below a threshold never changes the matches
// above it (the precision-recall curve is one pass over the sorted detections).
//
// Levels (canopy.detections v2): model-level detections are matched first, exactly as above
// (every model-level figure is what a v1 document gives); then the class-level detections
// (classify's answers: a class and group, heading modulo 180°) take the true vehicles left,
// by position, in the same order. Class-level figures are reported beside (class_* keys):
// "identified" there means the detection's group or class names the truth's model or class.
#pragma once

#include <array>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "canopy/documents/scene_score.h"
#include "canopy/formats/provenance.h"

namespace canopy::score {

struct TrueVehicle {
  int instance = 0;
  std::string model;
  double x = 0, y = 0, z = 0;  // bottom centre of the bounding box, tile coordinates
  double heading = 0;          // degrees
  double cover = 0;            // measured canopy cover over its footprint, [0, 1]
  std::string cls;             // the truth's "class" (procedural families), "" = none
  // Its outline seen from above (tile coordinates, 3 to 64 corners); empty when the truth has
  // none (hand labels may omit it).
  std::vector<std::array<double, 2>> footprint;
};

// A clutter object of a rendered tile: its kind and its box seen from above (centre, length
// along its heading, width across).
struct TrueClutter {
  std::string kind;
  double x = 0, y = 0, length = 0, width = 0;
  double heading = 0;  // degrees
};

struct Truth {
  std::string name;                   // file, as given
  double extent_x = 0, extent_y = 0;  // m
  std::vector<TrueVehicle> vehicles;
  std::vector<TrueClutter> clutter;  // empty for hand-labelled tiles
};

struct Detection {
  std::string candidate;
  std::string level = "model";  // "model" or "class" (v2)
  std::string model;            // "" for a class-level detection
  std::string cls, group;       // class-level: classify's class and group (model level: as given)
  double confidence = 0;
  double x = 0, y = 0, z = 0;  // model origin in tile coordinates
  double heading = 0;          // degrees
};

// A rejected candidate that says where it was (collect writes its position since issue 29):
// why, how dense and how sure the rejection is. The reliability table judges those with a
// confidence; a missed vehicle's fate reads them all.
struct Rejection {
  std::string candidate;
  std::string reason;                // "" when the document gives none
  std::optional<double> confidence;  // null or absent in the document: nullopt
  std::optional<double> density;     // the object's points per m², when collect wrote it
  double x = 0, y = 0;               // the candidate's centre, tile coordinates
};

struct Detections {
  std::string name;
  int version = 1;
  int candidates = 0;                       // candidates verified
  int none = 0;                             // of which answered none
  std::vector<Detection> detections;        // model level
  std::vector<Detection> class_detections;  // class level (v2)
  std::vector<Rejection> rejected;          // every rejection with a position
};

// One tile of an experiment: its detections, truth and the experiment's labels.
struct Tile {
  Detections detections;
  Truth truth;
  double noise_mm = std::numeric_limits<double>::quiet_NaN();  // NaN = not given
  std::string cover;  // cover level label ("light", ...), "" = not given
};

struct Params {
  double match_radius = 1.5;                              // m
  std::vector<double> cover_bins{0, 0.25, 0.5, 0.75, 1};  // edges of the per-vehicle cover bins
  double flip_threshold = 90;                             // heading error (deg) counted as a flip
};

// Throws common::UsageError naming the option of the first parameter out of its range:
// --match-radius in (0, 100 m], --flip-threshold in (0, 180], --cover-bins at least two edges
// rising strictly within [0, 1].
void validate(const Params& params);

// Readers: check "format" and "version", name the file and the field in every error
// (common::DataError, exit code 1).
Truth parse_truth(const std::string& text, const std::string& name);
Detections parse_detections(const std::string& text, const std::string& name);

// Gives every true vehicle without a class, and every model-level detection without one, the
// class of its model when `classes` names it (so a class-level answer "semi-tractor" on a
// rendered "semi" is judged by its class, and a model answer carries its model's class).
void apply_model_classes(std::vector<Tile>& tiles, const std::map<std::string, std::string>& classes);

// The pairing of one tile. truth_of[d] = index into truth.vehicles of detection d's match or
// -1; order = detection indices by falling confidence.
// The class level's pairing (det.class_detections against the vehicles the model level left)
// is in `cls`, the same way.
struct LevelMatch {
  std::vector<int> order;
  std::vector<int> truth_of;
  std::vector<int> detection_of;  // per true vehicle, -1 = not matched at this level
};
struct TileMatch : LevelMatch {
  LevelMatch cls;
};
TileMatch match_tile(const Detections& det, const Truth& truth, double radius);
// Why true vehicle `v` of tile `t`, matched at neither level, was missed: the candidate nearest
// its centre (horizontal distance; ties: candidate id) among the detections of both levels and
// the positioned rejections whose centre lies within `radius` of the vehicle's centre or inside
// its footprint decides —
//   none                                  "no_candidate" (detect gave none there, or only one
//                                         centred elsewhere: merged into something larger)
//   a rejection                           "refused", with its reason and object density
//   a detection matched to another vehicle "taken" (one answer for two vehicles)
//   an unmatched detection                "off_centre" (answered, its centre beyond the radius)
struct MissedFate {
  std::string fate, candidate, reason;
  std::optional<double> density;
};
MissedFate missed_fate(const Tile& t, const TileMatch& m, std::size_t v, double radius);

// Throws common::DataError naming the detections and the truth when the two cannot be of one tile:
// both hold positions (detections of either level and positioned rejections; true vehicles and
// clutter) and none of the former lies within the box of the latter grown by the truth's larger
// extent + 10 m (a detection of the tile lies on the tile, as its vehicles do). Nothing to compare
// (no position on either side) passes.
void check_same_tile(const Tile& t);

// A class-level detection names the true vehicle's kind: its group or class equals the truth's
// model or class ("car", "van" in hand-labelled tiles; a family class in rendered ones).
bool class_identified(const Detection& det, const TrueVehicle& truth);

// |a - b| modulo 360, in [0, 180]: a 180-degree flip is an error of 180.
double heading_error(double a_deg, double b_deg);
// The same modulo 180 (front and back not known), in [0, 90].
double axis_error(double a_deg, double b_deg);

// Percentile p in [0, 100] of values (linear interpolation between order statistics, the
// "type 7" definition; the median of an even count is the mean of the middle two). NaN for
// no values.
double percentile(std::vector<double> values, double p);

// The whole score: a canopy.scene_score document (documents/scene_score.h; the provenance is
// the writer's).
documents::SceneScore score(const std::vector<Tile>& tiles, const Params& params);

// The one-line summary score logs (its INFO line) of `tiles` tiles and their overall summary row
// (`all`, the JSON's summary[0]): both levels, every rate with its count and 95% interval, e.g.
// "1 tile, 4 true vehicles, 5 detections (0 model level, 5 class level): recall 4/4 = 1.000
// [0.510, 1.000], precision 4/5 = 0.800 [0.376, 0.964], class right 3/4 = 0.750 [0.301, 0.954],
// model identified 0/0 (n/a)" (1 tile, 1 detection: singular). Recall, precision and class right are at any
// level (a vehicle found by the model or the class level; *_any_level in the JSON); "model identified" is the
// model level's identification (the right model of the model-level finds). n/a: nothing to count.
std::string summary_line(std::size_t tiles, const documents::ScoreRow& all);

// The tiles of an experiment and who scores them from what (the document's text:
// documents::write_scene_score(score(inputs.tiles, params), inputs.provenance)).
struct Inputs {
  std::vector<Tile> tiles;
  formats::Provenance provenance;
};

}  // namespace canopy::score
