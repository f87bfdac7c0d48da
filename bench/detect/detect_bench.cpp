// detect benchmark: recall, candidates per true vehicle and pose error on seeded synthetic
// tiles (tests/fixtures/fixtures/detect_synth_tile.h) at light / medium / dense canopy cover
// and 0 / 8 / 32 mm noise; and a large tile written to disk for timing the CLI (bench/detect/run.sh).
#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/progressive_morphological_filter.h>

#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "canopy/formats/pcd.h"
#include "candtruth/candtruth.h"
#include "detect/detect.h"
#include "detect/output.h"
#include "fixtures/detect_synth_tile.h"

using namespace canopy;
using detect_test::TileSpec;
using detect_test::VehicleSpec;

namespace {

struct Model {
  const char* name;
  double length, width, height;
  bool cabin;
};
// Sizes of the modelbase's vehicles and the extremes of the default ranges.
const Model kModels[] = {
    {"car", 4.5, 1.8, 1.45, true},   {"suv", 4.9, 2.0, 1.8, true},        {"van", 5.5, 2.0, 2.3, false},
    {"semi", 6.9, 2.5, 3.6, true},   {"earthmover", 8.0, 3.0, 3.4, true}, {"tank", 6.9, 3.54, 2.4, true},
    {"truck", 8.0, 2.5, 3.2, false}, {"trailer", 16.0, 2.5, 4.0, false},  {"small", 3.0, 1.6, 1.4, true}};

bool clear_of_vehicles(const TileSpec& s, double x, double y, double grow) {
  for (const auto& v : s.vehicles) {
    if (detect_test::in_footprint(v, x, y, grow)) return false;
  }
  return true;
}

// `vehicles` at random poses, footprints at least 1 m apart (circle test on the half diagonals).
void place_vehicles(TileSpec& s, common::Rng& rng, int vehicles) {
  const double half = s.half_extent;
  int tries = 0;
  while (int(s.vehicles.size()) < vehicles && tries++ < 10000) {
    const Model& m = kModels[rng.below(std::size(kModels))];
    if (s.terrain == detect_test::Terrain::kRolling && m.length > 10) continue;  // rigid boxes
    VehicleSpec v{rng.uniform(-half + 9, half - 9),
                  rng.uniform(-half + 9, half - 9),
                  rng.uniform(-canopy::common::kPi, canopy::common::kPi),
                  m.length,
                  m.width,
                  m.height,
                  std::uint32_t(s.vehicles.size() + 1),
                  m.cabin};
    bool ok = true;
    for (const auto& o : s.vehicles) {
      if (std::hypot(v.x - o.x, v.y - o.y) <
          0.5 * (std::hypot(v.length, v.width) + std::hypot(o.length, o.width)) + 1.0)
        ok = false;
    }
    if (ok) s.vehicles.push_back(v);
  }
}

// A random tree clear of the vehicles (false when its trunk would stand on one); its branches
// at least 0.5 m above a vehicle under the crown.
bool random_tree(const TileSpec& s, common::Rng& rng, detect_test::TreeSpec* tree) {
  const double half = s.half_extent;
  detect_test::TreeSpec& t = *tree;
  t.x = rng.uniform(-half, half);
  t.y = rng.uniform(-half, half);
  if (!clear_of_vehicles(s, t.x, t.y, 0.5)) return false;
  t.crown_radius = rng.uniform(2.0, 4.5);
  t.crown_base = rng.uniform(3.0, 7.0);
  t.crown_top = t.crown_base + rng.uniform(4.0, 8.0);
  t.trunk_radius = rng.uniform(0.12, 0.3);
  for (const auto& v : s.vehicles) {
    if (std::hypot(v.x - t.x, v.y - t.y) < t.crown_radius + 0.5 * std::hypot(v.length, v.width)) {
      const double need = detect_test::ground_z(s, v.x, v.y) + v.height + 0.5 +
                          0.5 * v.length * std::tan(s.slope_deg * canopy::common::kPi / 180) -
                          detect_test::ground_z(s, t.x, t.y);
      if (t.crown_base < need) {
        t.crown_top += need - t.crown_base;
        t.crown_base = need;
      }
    }
  }
  return true;
}

// Trees until `cover` of the tile area lies under a crown (measured on a 0.5 m grid).
void plant_trees(TileSpec& s, common::Rng& rng, double cover) {
  const double half = s.half_extent;
  const int g = int(2 * half / 0.5);
  std::vector<char> covered(std::size_t(g) * std::size_t(g), 0);
  std::size_t count = 0;
  int tries = 0;
  while (double(count) / double(covered.size()) < cover && tries++ < 20000) {
    detect_test::TreeSpec t;
    if (!random_tree(s, rng, &t)) continue;
    s.trees.push_back(t);
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i) {
        const double x = -half + (i + 0.5) * 0.5, y = -half + (j + 0.5) * 0.5;
        char& c = covered[std::size_t(j) * std::size_t(g) + std::size_t(i)];
        if (!c && std::hypot(x - t.x, y - t.y) < t.crown_radius) {
          c = 1;
          ++count;
        }
      }
  }
}

// A seeded tile: `vehicles` at random non-overlapping poses, trees until `cover` of the tile
// area lies under a crown, bushes and boulders.
TileSpec random_tile(std::uint64_t seed, double cover, double noise, double half, int vehicles, double spacing) {
  TileSpec s;
  s.seed = seed;
  s.half_extent = half;
  s.noise = noise;
  s.spacing = spacing;
  s.occlusion = 0.5;
  common::Rng rng(common::derive_seed(seed, "detect-bench"));
  s.terrain = seed % 3 == 0   ? detect_test::Terrain::kFlat
              : seed % 3 == 1 ? detect_test::Terrain::kSlope
                              : detect_test::Terrain::kRolling;
  s.slope_deg = 10;
  s.slope_azimuth = rng.uniform(0, 2 * canopy::common::kPi);
  s.rolling_amplitude = 1.5;
  s.rolling_wavelength = 40;
  place_vehicles(s, rng, vehicles);
  plant_trees(s, rng, cover);
  for (int b = 0; b < int(half / 3); ++b) {
    detect_test::BushSpec bu{rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(0.6, 1.5), 0.2,
                             rng.uniform(1.0, 2.5)};
    if (clear_of_vehicles(s, bu.x, bu.y, 0.3)) s.bushes.push_back(bu);
  }
  for (int b = 0; b < 3; ++b) {
    detect_test::BoulderSpec bo{rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(0.4, 1.2)};
    if (clear_of_vehicles(s, bo.x, bo.y, bo.radius + 0.3)) s.boulders.push_back(bo);
  }
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// One row of the recall table (a cover level at a noise level).
struct Tally {
  std::size_t vehicles = 0, covered = 0, candidates = 0, false_cands = 0;
  std::vector<double> centre_err, heading_err;
  double cover_sum = 0, seconds = 0;
};

// What lies around a vehicle no candidate covers, and how detect classified its points (stderr).
void report_missed(const TileSpec& s, const formats::PointCloud& tile, const detect::Result& r,
                   const VehicleSpec& v, const char* cover, double noise) {
  std::size_t cls[4] = {0, 0, 0, 0}, pts = 0;
  double hmin = 1e9, hmax = -1e9;
  const auto& inst = tile.col("instance");
  for (std::size_t i = 0; i < tile.size(); ++i) {
    if (inst[i] != v.instance) continue;
    ++pts;
    ++cls[std::min<int>(3, r.classes[i])];
    hmin = std::min(hmin, double(r.height[i]));
    hmax = std::max(hmax, double(r.height[i]));
  }
  for (const auto& t : s.trees) {
    if (std::hypot(t.x - v.x, t.y - v.y) < 8)
      std::fprintf(stderr, "  tree at %.1f %.1f r %.1f base %.1f top %.1f trunk %.2f\n", t.x, t.y,
                   t.crown_radius, t.crown_base, t.crown_top, t.trunk_radius);
  }
  for (const auto& b : s.bushes) {
    if (std::hypot(b.x - v.x, b.y - v.y) < 8)
      std::fprintf(stderr, "  bush at %.1f %.1f r %.1f top %.1f\n", b.x, b.y, b.radius, b.top);
  }
  std::fprintf(stderr, "  %zu points: ground %zu other %zu candidate %zu; height %.2f..%.2f\n", pts, cls[1],
               cls[2], cls[3], hmin, hmax);
  std::fprintf(stderr,
               "missed: seed %llu cover %s noise %.3f vehicle %u (%.1f x %.1f x %.1f) at %.1f "
               "%.1f, cover %.2f\n",
               (unsigned long long)s.seed, cover, noise, v.instance, v.length, v.width, v.height, v.x, v.y,
               detect_test::canopy_cover(s, v));
}

// The candidates' ground truth (candtruth, from the labelled tile and the index's geometry).
documents::CandidateTruth truth_of(const formats::PointCloud& tile, const detect::Result& r) {
  candtruth::Inputs in;
  in.tile = &tile;
  in.tile_name = "tile";
  in.index = detect::index_document(r, detect::Params{}, "tile", "");
  return candtruth::run(candtruth::Params{}, in);
}

// A vehicle split over several candidates (stderr).
void report_split(const TileSpec& s, const detect::Result& r, const documents::CandidateTruth& truth,
                  const VehicleSpec& v, const char* cover, double noise, std::size_t mine) {
  std::fprintf(stderr, "%zu candidates: seed %llu cover %s noise %.3f vehicle %u (%.1f x %.1f x %.1f):", mine,
               (unsigned long long)s.seed, cover, noise, v.instance, v.length, v.width, v.height);
  for (std::size_t k = 0; k < r.candidates.size(); ++k) {
    const auto& c = r.candidates[k];
    if (truth.candidates[k].instance == v.instance)
      std::fprintf(stderr, " [%.1f x %.1f x %.1f, coverage %.2f]", c.length, c.width, c.height,
                   truth.candidates[k].coverage);
  }
  std::fprintf(stderr, "\n");
}

// Adds one tile's vehicles and candidates to the row.
void tally_tile(const TileSpec& s, const formats::PointCloud& tile, const detect::Result& r,
                const char* cover, double noise, Tally& t) {
  t.candidates += r.candidates.size();
  const documents::CandidateTruth truth = truth_of(tile, r);
  for (const auto& c : truth.candidates) t.false_cands += c.instance == 0;
  for (const auto& v : s.vehicles) {
    ++t.vehicles;
    t.cover_sum += detect_test::canopy_cover(s, v);
    const detect::Candidate* best = nullptr;
    std::int64_t best_points = 0;
    for (std::size_t k = 0; k < r.candidates.size(); ++k) {
      const auto& ct = truth.candidates[k];
      if (ct.instance == v.instance && (!best || ct.points > best_points)) {
        best = &r.candidates[k];
        best_points = ct.points;
      }
    }
    if (!best) {
      report_missed(s, tile, r, v, cover, noise);
      continue;
    }
    ++t.covered;
    std::size_t mine = 0;
    for (const auto& c : truth.candidates) mine += c.instance == v.instance;
    if (mine > 1) report_split(s, r, truth, v, cover, noise, mine);
    t.centre_err.push_back((best->to_tile.block<3, 1>(0, 3) - detect_test::vehicle_centre(s, v)).norm());
    const double cosang =
        std::abs(best->to_tile.block<3, 1>(0, 0).dot(detect_test::vehicle_rotation(s, v).col(0)));
    t.heading_err.push_back(std::acos(std::min(1.0, cosang)) * 180 / canopy::common::kPi);
  }
}

int recall(int tiles) {
  const struct {
    const char* name;
    double cover;
  } covers[] = {{"light", 0.2}, {"medium", 0.45}, {"dense", 0.7}};
  std::printf(
      "| cover (tile share / mean per vehicle) | noise | vehicles | recall | candidates per vehicle | "
      "false candidates | centre error median | heading error median | s per tile |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& cv : covers) {
    for (const double noise : {0.0, 0.008, 0.032}) {
      Tally t;
      for (int k = 0; k < tiles; ++k) {
        const std::uint64_t seed = 1000 + std::uint64_t(k);  // the same scenes at every noise level
        const TileSpec s = random_tile(seed, cv.cover, noise, 30, 8, 0.1);
        const formats::PointCloud tile = detect_test::make_tile(s);
        const auto t0 = std::chrono::steady_clock::now();
        const detect::Result r = detect::run(detect::Params{}, {&tile, "bench"});
        t.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        tally_tile(s, tile, r, cv.name, noise, t);
      }
      std::printf("| %s (%.2f / %.2f) | %.0f mm | %zu | %.1f%% | %.2f | %zu | %.2f m | %.1f deg | %.2f |\n",
                  cv.name, cv.cover, t.cover_sum / double(t.vehicles), noise * 1e3, t.vehicles,
                  100.0 * double(t.covered) / double(t.vehicles), double(t.candidates) / double(t.vehicles),
                  t.false_cands, median(t.centre_err), median(t.heading_err), t.seconds / tiles);
      std::fflush(stdout);
    }
  }
  return 0;
}

int big_tile(double points, const std::string& path) {
  // Ground ~ 46% of the points at medium cover: (2 half / spacing)^2 = 0.46 points.
  const double half = 50;
  const double spacing = 2 * half / std::sqrt(0.46 * points);
  TileSpec s = random_tile(77, 0.45, 0.008, half, 12, spacing);
  const formats::PointCloud tile = detect_test::make_tile(s);
  formats::write_pcd(tile, path);
  std::printf("wrote %zu points (spacing %.4f m, %zu vehicles, %zu trees) to %s\n", tile.size(), spacing,
              s.vehicles.size(), s.trees.size(), path.c_str());
  return 0;
}

// PCL's PMF on every point of a tile against detect (PMF on the 0.5 m minimum raster + DTM
// + everything else), same thresholds: why detect filters the raster.
int pmf(double half) {
  TileSpec s = random_tile(5, 0.45, 0.008, half, 2, 0.1);
  const formats::PointCloud tile = detect_test::make_tile(s);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (std::size_t i = 0; i < tile.size(); ++i) {
    cloud->push_back(pcl::PointXYZ(float(tile.col("x")[i]), float(tile.col("y")[i]), float(tile.col("z")[i])));
  }
  const detect::Params p;
  auto t0 = std::chrono::steady_clock::now();
  pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> f;
  f.setInputCloud(cloud);
  f.setCellSize(float(p.cell));
  f.setMaxWindowSize(float(p.max_window));
  f.setSlope(float(p.terrain_slope / p.cell));
  f.setInitialDistance(float(p.initial_distance));
  f.setMaxDistance(float(p.max_distance));
  f.setBase(2.0f);
  f.setExponential(true);
  pcl::Indices ground;
  f.extract(ground);
  const double full = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t0 = std::chrono::steady_clock::now();
  const detect::Result r = detect::run(p, {&tile, "pmf"});
  const double ours = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t truth_ground = 0, full_right = 0, ours_right = 0;
  std::vector<char> is_ground(tile.size(), 0);
  for (auto g : ground) is_ground[std::size_t(g)] = 1;
  for (std::size_t i = 0; i < tile.size(); ++i) {
    const bool t = tile.col("label")[i] == formats::kLabelGround;
    truth_ground += t;
    full_right += (is_ground[i] != 0) == t;
    ours_right += (r.classes[i] == detect::kClassGround) == t;
  }
  std::printf(
      "%zu points (%.0f x %.0f m): PCL PMF on all points %.2f s, %.2f%% agree with the labels; "
      "detect (raster PMF + DTM + objects + candidates) %.2f s, ground class %.2f%% agree\n",
      tile.size(), 2 * half, 2 * half, full, 100.0 * double(full_right) / double(tile.size()), ours,
      100.0 * double(ours_right) / double(tile.size()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "recall") return recall(argc > 2 ? std::atoi(argv[2]) : 4);
  if (mode == "pmf") return pmf(argc > 2 ? std::atof(argv[2]) : 10);
  if (mode == "tile" && argc == 4) return big_tile(std::atof(argv[2]), argv[3]);
  std::fprintf(stderr, "usage: detect_bench recall [tiles] | tile <points> <out.pcd> | pmf [half extent]\n");
  return 2;
}
