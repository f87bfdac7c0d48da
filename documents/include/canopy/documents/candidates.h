// A tile's candidates index: index.json of detect's output directory, format
// "canopy.candidates", version 2 (formats/README.md "Candidate index"). detect writes it;
// collect, classify, topview, candtruth and report read it. Version 2 carries no ground truth
// (issue 30: what the recogniser's path reads holds no truth; candtruth writes the candidates'
// truth beside it) and records the crop margin. Version 1 indexes are read too: their "truth"
// and "instances" members are dropped unread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

inline constexpr const char* kCandidatesFormat = "canopy.candidates";
inline constexpr int kCandidatesVersion = 2;

using Matrix4 = std::array<double, 16>;  // 4 x 4 row-major, float64

// One candidate. detect writes every member; a reader requires id, transform, length and
// width and type-checks the others when they are there (hand-written indexes of the tests and
// older indexes leave some out).
struct Candidate {
  std::string id;       // a plain name (letters, digits, _ . -; 1 to 64; not . or ..), unique
  std::string file;     // id + ".pcd" ("" when not given)
  Matrix4 transform{};  // local -> tile, rigid (R orthonormal within 1e-6, det +1), last row 0 0 0 1
  std::optional<std::array<double, 3>> centre;   // the transform's translation
  double length = 0, width = 0;                  // >= 0 (m)
  std::optional<double> heading;                 // radians from +x toward +y
  std::optional<double> height;                  // m
  std::optional<std::int64_t> point_count;       // rows of the candidate PCD
  std::optional<std::int64_t> object_points;     // points of the detected object
  std::optional<double> density;                 // object points per m² (null or absent: older index)
  std::optional<double> planarity, planar_area;  // detect's shape test

  // density, else object_points / (length x width) when both are known and the area > 0.
  std::optional<double> object_density() const;
};

struct GroundGrid {
  double cell = 0;  // the DTM cell applied (m)
  std::int64_t cells = 0, ground_cells = 0, filled_cells = 0, ground_points = 0;
};

// The tile's density as detect measured it and what its density rule made of it
// (docs/decisions/detect.md §7): the index's "density" object (detect_density_json).
struct DetectDensity {
  double all = 0;                       // points per occupied 1 m cell (per m²)
  std::optional<double> ground, first;  // on open ground cells; first returns (null when unknown)
  std::int64_t occupied_cells = 0, open_ground_cells = 0;
  double rule = 0;  // the density the rule used
  double voxel = 0, min_planarity = 0, dtm_cell = 0;
  bool voxel_by_rule = false, planarity_by_rule = false, cell_by_rule = false;
  // Rows of parked vehicles split (detect.md §9), and the roofs' clustering tolerance (m).
  bool split_rows = false, split_rows_by_rule = false;
  double row_tolerance = 0;
};

// The "density" object of `d` as detect writes it into the index. Throws common::Error for a
// non-finite number (a writer's bug).
nlohmann::ordered_json detect_density_json(const DetectDensity& d);

struct Candidates {
  nlohmann::ordered_json provenance;  // as written (reading); null when absent
  std::string tile;                   // the tile detect read, as given ("" when absent)
  std::optional<std::int64_t> tile_points;
  // The tile's CRS as its file records it ("EPSG:<code>", detect reads LAS/LAZ CRS records:
  // formats/las_crs.h) and where it was read; "" when the file records none (PCD, PLY, a LAS
  // without a CRS record or without an EPSG code in it): then the index has neither member.
  std::string crs, crs_from;
  // What detect warned about the tile as it read it (its log's warnings, one sentence each, the
  // tile named: coordinates in feet, a CRS record without an EPSG code, the trajectory's gaps),
  // so that collect can relay them (stop 70). Written only when there is one: an index of a
  // tile detect did not warn about is as before.
  std::vector<std::string> warnings;
  std::optional<std::array<double, 3>> origin;
  std::string classes;  // classes.ply's name, "" for null / absent
  std::optional<GroundGrid> ground;
  // The tile's density and what the density rule made of it (docs/decisions/detect.md §7),
  // an object kept as written (collect copies it into the detections); null when absent.
  nlohmann::ordered_json density;
  // The crop box's margin around the footprint and above the height (m): a candidate's crop is
  // every tile point whose frame coordinates have |x| <= length / 2 + margin, |y| <= width / 2 +
  // margin, -margin <= z <= height + margin. Version 2; absent in version 1.
  std::optional<double> margin;
  std::vector<Candidate> candidates;  // in the index's order

  // provenance.tool when it is a string, else "".
  std::string written_by() const;
  // density.all when it is a number > 0.
  std::optional<double> density_all() const;
  // density.ground (points per open-ground 1 m cell) when it is a number > 0; none when null or
  // absent (detect saw too little open ground in the tile) or 0.
  std::optional<double> density_ground() const;
  // density.first (first returns per occupied 1 m cell: about one per pulse) when it is a number
  // > 0; none when null (no return numbers in the tile) or absent or 0.
  std::optional<double> density_first() const;
  // The candidate of that id, nullptr when none.
  const Candidate* find(const std::string& id) const;
};

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1 or 2, a version 2 index with "truth" or "instances"
// members (ground truth belongs to candtruth's file), a "crs" that is not "EPSG:<1-6 digits>", "warnings"
// not an array of strings, a margin that
// is not a finite number >= 0, "candidates" missing or not an array, a candidate without a plain unique id, a
// transform that is not a rigid 4 x 4 (4 rows of 4 numbers, or 16 numbers), length or width missing, not
// finite or negative, any other member of a wrong type
// ("candidates[2].heading must be a finite number").
Candidates read_candidates(const std::string& text, const std::string& name);
// The file at `path` (common::read_file), then read_candidates.
Candidates read_candidates_file(const std::string& path);

// The index as detect writes it (version 2, one space indent, a final newline), every member
// of `c` written, `prov` as provenance. Throws common::Error for a non-finite number, no margin,
// or a candidate without centre, heading, height, point_count, object_points, density,
// planarity or planar_area (a writer's bug).
std::string write_candidates(const Candidates& c, const formats::Provenance& prov);

}  // namespace canopy::documents
