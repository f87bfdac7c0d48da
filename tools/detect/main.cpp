// detect: tile (PCD / PLY points / LAS) -> directory of vehicle candidates (index.json + <id>.pcd + classes.ply).
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/las_crs.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/provenance.h"
#include "canopy/formats/sensor_direction.h"
#include "canopy/formats/trajectory.h"
#include "detect/detect.h"
#include "detect/output.h"

using namespace canopy;

namespace {

// "1 candidate", "3 candidates".
std::string candidates_count(std::size_t n) {
  return std::to_string(n) + (n == 1 ? " candidate" : " candidates");
}

// The warnings about the tile, logged as they come and kept for the index's "warnings" (collect
// relays them: a warning only in detect's log went unread, stop 70).
struct TileWarnings {
  std::vector<std::string> said;
  void operator()(const std::string& message) {
    common::log::warn(message);
    said.push_back(message);
  }
};

// The options beside detect::Params.
struct Cli {
  std::string in = "-", out, clustering = "grid", split_rows = "auto", trajectory;
  bool no_classes = false;
  CLI::Option *voxel = nullptr, *min_planarity = nullptr,
              *cell = nullptr;  // given: overrides the density rule
};

void bind(common::Tool& tool, detect::Params& p, Cli& cli) {
  tool.add_input(
      &cli.in,
      "tile: PCD, PLY point set or LAS (x y z, float64 for georeferenced coordinates; any other fields)");
  tool.app().add_option("-o,--output", cli.out,
                        "output directory, required (its parent must exist; built beside it and "
                        "swapped into place; only a previous detect output, proven by its "
                        "manifest.json, is replaced)");
  cli.cell = tool.add_length("--cell", &p.cell,
                             "DTM cell; default: clamp(sqrt(24 / measured density), 0.5 m, 2 m), "
                             "docs/decisions/detect.md §7");
  tool.add_length("--max-window", &p.max_window,
                  "largest ground-filter window (objects narrower are not ground)");
  tool.add("--terrain-slope", &p.terrain_slope,
           "ground-filter height threshold growth per metre of window (rise/run)");
  tool.add_length("--initial-distance", &p.initial_distance,
                  "ground-filter height threshold at the smallest window");
  tool.add_length("--max-distance", &p.max_distance, "ground-filter height threshold cap");
  tool.add_length("--ground-tolerance", &p.ground_tolerance, "points this close to the first DTM refine it");
  tool.add("--min-ground-share", &p.min_ground_share,
           "fewest occupied cells with ground (share) for a terrain");
  tool.add_length("--min-object-height", &p.min_object_height, "lower: ground or grass");
  cli.voxel = tool.add_length("--voxel", &p.voxel,
                              "clustering voxel edge (26-connected voxels form an object); default: "
                              "max(0.2 m, 1.9 / sqrt(measured density)), docs/decisions/detect.md §7");
  tool.add("--clustering", &cli.clustering,
           "grid (voxel connected components) or euclidean (PCL, same partition)");
  tool.add_length("--min-length", &p.min_length, "shortest vehicle footprint");
  tool.add_length("--max-length", &p.max_length, "longest vehicle footprint");
  tool.add_length("--min-width", &p.min_width, "narrowest vehicle footprint");
  tool.add_length("--max-width", &p.max_width, "widest vehicle footprint");
  tool.add_length("--min-height", &p.min_height, "lowest vehicle");
  tool.add_length("--max-height", &p.max_height, "tallest vehicle (higher points are canopy)");
  tool.add("--min-points", &p.min_points, "fewest points of a candidate object");
  cli.min_planarity = tool.add("--min-planarity", &p.min_planarity,
                               "shape test: an object with a smaller share of its surface in planar "
                               "neighbourhoods and less than --min-planar-area of it is vegetation (0 = "
                               "off); default: 0.2 where the measured density is >= 30 points/m², else 0");
  tool.add("--min-planar-area", &p.min_planar_area,
           "shape test: m^2 of planar surface that keep an object whatever its share");
  tool.add_length("--planar-radius", &p.planar_radius, "neighbourhood radius of the planarity test");
  tool.add_length("--margin", &p.margin, "crop margin around a candidate's footprint and above its height");
  tool.add("--split-rows", &cli.split_rows,
           "auto, on or off: split an object longer or wider than one vehicle into one piece per "
           "roof (rows of parked cars merged by the voxel); auto: on where the measured density is "
           "< 90.25 points/m², docs/decisions/detect.md §9");
  tool.add_length("--row-roof-height", &p.row_roof_height,
                  "bottom of the roof band whose points separate the roofs of a row");
  tool.add_length("--row-max-height", &p.row_max_height,
                  "tallest vehicle of a row: a part of the roof band under which the object rises "
                  "higher (a truck's cab, a wheel loader) is not a roof, and a row split needs two "
                  "roofs; 0 = no such test, the rule before, docs/decisions/detect.md §11");
  tool.add("--row-trim", &p.row_trim,
           "an object longer or wider than one vehicle whose roof band holds one roof (a car with "
           "a bicycle stand, a planter or a low hedge joined to it) keeps only its parts, this many "
           "row tolerances apart in the top view, that hold the roof or lie below the band within "
           "its reach; 0 = no trim, the rule before, docs/decisions/detect.md §12");
  tool.add("--min-split-share", &p.min_split_share,
           "an object re-clustered at half the voxel (objects that touch) is split only when the "
           "parts kept hold at least this share of its points (a sparse vehicle only falls into "
           "fragments); 0 = any two parts, the rule before, docs/decisions/detect.md §10");
  tool.add("--merge-gap", &p.merge_gap,
           "objects whose points come within this many clustering voxels of each other in the top "
           "view, end to end, with a union that fits one vehicle, are one (the cab and the deck of "
           "a tractor unit); 0 = never merge, the rule before, docs/decisions/detect.md §10");
  tool.add("--side-gap", &p.side_gap,
           "clustering voxels: an object only wider than two narrow vehicles is cut across its "
           "width at an empty slab only when the empty run is at least this wide (narrower: the "
           "spaces between scan lines over one wide body, a tank; 0.5 = one point spacing); 0 = any "
           "empty slab, the default (0.5 is not adopted: docs/decisions/detect.md §14)");
  tool.add("--end-gap", &p.end_gap,
           "clustering voxels: an object otherwise accepted whole is cut across its long axis at a "
           "run of empty slabs at least this long in which the ground is seen (a vehicle and a bush "
           "at its end that the voxel joined; a sampling hole over one body's top hides the ground); "
           "0 = no such cut, the rule before and the default, docs/decisions/detect.md §19");
  tool.add("--merge-tall-rows", &p.merge_tall_rows,
           "true or false: a piece of a row split is merged end to end (--merge-gap) with a piece "
           "that rises above --row-max-height (a tractor unit's cab cut from its deck by a row "
           "split); false = pieces of a row split never merged, the rule before, "
           "docs/decisions/detect.md §13");
  tool.add("--join-stacked", &p.join_stacked,
           "true or false: clusters that touch in the top view, beside each other (not one over "
           "the other), whose union is in line and fits one vehicle are one object before any "
           "split (a vehicle's parts at different heights whose vertical faces the sensor did not "
           "see: a cab beside a deck from above); false = the rule before, "
           "docs/decisions/detect.md §16");
  tool.add("--merge-fragments", &p.merge_fragments,
           "true or false: a cluster too small to be an object that lies under a crown (a tile point "
           "over most of its points, a voxel above the object's top) is merged into the accepted "
           "object it touches in the top view (--merge-gap) when the union stays in line and fits "
           "one vehicle (the sparse returns of a vehicle's part hidden under a crown); false = such "
           "clusters dropped, the rule before and the default, docs/decisions/detect.md §24");
  tool.add_length(
      "--merge-fragments-gap", &p.merge_fragments_gap,
      "with --merge-fragments: a fragment farther from the object than --merge-gap, but at most "
      "this far, is merged when the gap is hidden (a crown over all of it, no ground seen in it); "
      "0 = only within --merge-gap, docs/decisions/detect.md §24");
  tool.add("--merge-fragments-beside", &p.merge_fragments_beside,
           "true or false: with --merge-fragments, only a fragment beside the object (at most a "
           "quarter of its top-view cells shared with it), not over it, docs/decisions/detect.md §24");
  tool.add("--object-field", &p.object_field,
           "true or false: every candidate crop gets the field `object` (uint8), 1 for the points of "
           "the candidate's own object (after the row split, trim and merges), 2 for points detect "
           "gave to another object or piece, 3 for those a trim to one roof cut off the candidate's "
           "object (the trim's leftover), 0 for the rest (ground, grass), for inspection; false = "
           "the crops before, docs/decisions/detect.md §17, §18");
  tool.add_flag("--no-classes", &cli.no_classes, "do not write classes.ply");
  tool.app().add_option("--trajectory", cli.trajectory,
                        "sensor trajectory (formats/README.md, Trajectory) in the tile's frame: a "
                        "tile without sensor_x/y/z (a sensor-mode render, LAS) gets the direction "
                        "toward the sensor of each point at its gps_time, so the candidates carry "
                        "it as a rendered scan's do (classify's sight lines, fitvox's normals, "
                        "verify); a tile with the columns keeps them");
}

// The tile's sensor_x/y/z from the trajectory (--trajectory), unless it has them.
void add_sensor_directions(formats::PointCloud* tile, const std::string& trajectory_path,
                           const std::string& name, TileWarnings& warn) {
  formats::SensorDirectionOptions so;
  const formats::Trajectory trajectory = formats::read_trajectory(trajectory_path);
  so.trajectory = &trajectory;
  so.trajectory_name = common::display_name(trajectory_path);
  const bool columns = tile->has("sensor_x") || tile->has("sensor_y") || tile->has("sensor_z");
  so.source = columns ? formats::SensorSource::kColumns : formats::SensorSource::kTrajectory;
  const formats::SensorDirections sd = formats::sensor_directions(*tile, so, name);
  for (const auto& w : sd.warnings) warn(w);
  if (sd.used == formats::SensorSource::kColumns) {
    warn(name + ": has sensor_x/y/z: --trajectory " + so.trajectory_name + " not used");
    return;
  }
  auto& sx = tile->add("sensor_x", formats::kFloat32);
  auto& sy = tile->add("sensor_y", formats::kFloat32);
  auto& sz = tile->add("sensor_z", formats::kFloat32);
  for (std::size_t i = 0; i < sd.directions.size(); ++i) {
    sx[i] = sd.directions[i].x();
    sy[i] = sd.directions[i].y();
    sz[i] = sd.directions[i].z();
  }
  common::log::info(sd.summary);
}

detect::Clustering clustering_of(const std::string& text) {
  if (text == "grid") return detect::Clustering::kGrid;
  if (text == "euclidean") return detect::Clustering::kEuclidean;
  throw common::UsageError("--clustering must be grid or euclidean");
}

// detect's lengths are metres; a LAS tile may declare feet (not converted: the candidates'
// transforms are rigid, tile units = metres).
void warn_las_units(const formats::LasCrs& crs, const std::string& name, TileWarnings& warn) {
  const auto& unit = crs.unit;
  if (!unit || unit->metres == 1.0) return;
  char f[64];
  std::snprintf(f, sizeof f, "%.10g", unit->metres);
  warn(name + ": its georeferencing gives the coordinates in " + unit->name +
       (unit->metres > 0 ? std::string(" (") + f + " m)" : std::string()) + " (" + unit->source +
       "); detect reads them as metres, so every length (DTM cell, vehicle ranges) is taken in " +
       unit->name + ": convert the tile to metres first");
}

// The CRS the tile's LAS/LAZ file records (index.json's "crs"; collect's GeoJSON carries it),
// said in one line; a record without an EPSG code, or two that disagree, in one warning.
void say_crs(const formats::LasCrs& crs, const std::string& name, TileWarnings& warn) {
  if (crs.epsg > 0) common::log::info(name + ": CRS " + crs.code() + " (" + crs.from + ")");
  if (!crs.note.empty()) {
    warn(name + ": " + crs.note +
         (crs.epsg > 0 ? "" : ": no CRS in the index (give collect --crs, make CRS=EPSG:<code>)"));
  }
}

// The detect phase's INFO line.
std::string summary(const detect::Result& r) {
  const detect::Stats& s = r.stats;
  // Clusters merged by --merge-fragments (never with it off).
  const std::string frag = s.fragments > 0 ? " (" + std::to_string(s.fragments) + " fragments)" : "";
  char buf[700];
  std::snprintf(
      buf, sizeof buf,
      "density %.1f points/m² (DTM cell %.2f m, voxel %.2f m, min planarity %.2f, rows %s); ground %zu of "
      "%zu cells "
      "(%.2f s); %zu "
      "object points in %zu clusters (%zu stacked joined), %zu splits (%zu rows, %zu trims), %zu merges%s, "
      "rejected %zu small %zu large %zu canopy bottoms %zu not planar (%.2f s); %s (%.2f s)",
      r.density.rule, r.density.cell, r.density.voxel, r.density.min_planarity,
      r.density.split_rows ? "split" : "kept", s.ground_cells, s.cells, s.seconds_ground, s.band_points,
      s.clusters, s.stacked, s.splits, s.row_splits, s.trims, s.merges, frag.c_str(), s.rejected_small,
      s.rejected_large, s.rejected_canopy, s.rejected_shape, s.seconds_objects,
      candidates_count(r.candidates.size()).c_str(), s.seconds_candidates);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("detect",
                    "Vehicle candidates in a whole tile: ground (DTM), objects between "
                    "the ground and the canopy, footprint and height tests; one local-frame "
                    "PCD per candidate plus index.json and a classification PLY.");
  tool.without_threads();
  detect::Params p;
  Cli cli;
  bind(tool, p, cli);
  return tool.run(argc, argv, [&] {
    if (cli.out.empty() || cli.out == "-") throw common::UsageError("-o/--output must name a directory");
    p.clustering = clustering_of(cli.clustering);
    if (cli.split_rows != "auto" && cli.split_rows != "on" && cli.split_rows != "off")
      throw common::UsageError("--split-rows must be auto, on or off");
    p.split_rows_from_density = cli.split_rows == "auto";
    p.split_rows = cli.split_rows == "on";
    p.voxel_from_density = cli.voxel->count() == 0;
    p.planarity_from_density = cli.min_planarity->count() == 0;
    p.cell_from_density = cli.cell->count() == 0;
    detect::validate(p);
    detect::check_output_dir(cli.out, cli.in);  // before the work; again before the swap
    const std::string name = common::display_name(cli.in);
    common::log::Phase read("read");
    // Tiles are read by magic: PCD, PLY point set, LAS or LAZ; a LAS/LAZ tile's header block
    // (its CRS records) comes with the points, from standard input or a FIFO too.
    std::optional<formats::LasHeaderBlock> las_header;
    formats::PointCloud tile = formats::read_points(cli.in, "detect", formats::FieldSelection{}, &las_header);
    read.done(std::to_string(tile.size()) + " points");
    TileWarnings warnings;
    if (!cli.trajectory.empty()) add_sensor_directions(&tile, cli.trajectory, name, warnings);
    const formats::LasCrs crs = las_header ? formats::las_crs(*las_header) : formats::LasCrs{};
    warn_las_units(crs, name, warnings);
    say_crs(crs, name, warnings);
    common::log::Phase work("detect");
    detect::Result r = detect::run(p, {&tile, name});
    r.crs = crs.code();
    r.crs_from = crs.from;
    r.warnings = warnings.said;
    work.done(summary(r));
    const formats::Provenance prov{"detect", CANOPY_VERSION, tool.parameters(), {cli.in}};
    common::log::Phase write("write");
    detect::write_output(cli.out, tile, r, p, prov, cli.in, !cli.no_classes);
    write.done(candidates_count(r.candidates.size()) + " to " + cli.out);
  });
}
