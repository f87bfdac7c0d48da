// The density rule of the model-level stages (issue 27; docs/decisions/density-scale.md): one
// candidate's measured object density (points per m² of its footprint, detect's index.json)
// -> the length scales of fitvox, cocone and ncut, with the tile chain's values of today
// (share/params/fitvox-tile.ini, cocone.ini, ncut.ini) as the dense end.
//
// Rule: a 128 mm voxel keeps fitvox-tile.ini's 6 points on a surface of kDenseDensity = 370
// points/m² (0.128² x 370 = 6.06). Below that density the voxel edge grows as the point spacing
// s = 1/sqrt(density) does, so that a voxel keeps the same ~6 points:
//   voxel = max(128 mm, ceil_mm(128 mm x sqrt(370 / density)))      (= k s, k = sqrt(6.06))
// and every length of the chain that was set in voxels at 128 mm keeps its ratio to the voxel,
// f = voxel / 128 mm: cocone's largest facet area x f², ncut's affinity radius and dense radius
// x f. Not scaled: dimensionless settings (fitvox's min-points and merge, gmatch's relative
// area and distance scales, the angles) and verify's distances, which compare the candidate's
// samples with the modelbase's 128 mm surface and measure pose and fit, not the candidate's
// spacing (scaling them let clutter through: density-scale.md, "verify"). At and above
// kDenseDensity every value is today's and the stages get no option at all (their command lines
// and outputs are byte-identical to before the rule). Lengths are whole millimetres so the
// options a plan writes are short, exact text.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace canopy::common {

// The dense end: today's tile-chain values.
constexpr double kDenseDensity = 370;     // points/m²: the density a 128 mm voxel needs
constexpr int kDenseVoxelMm = 128;        // fitvox-tile.ini voxel
constexpr double kDenseMaxArea = 0.04;    // cocone.ini max-area (m²)
constexpr int kDenseRadiusMm = 512;       // ncut.ini radius
constexpr int kDenseDenseRadiusMm = 175;  // ncut.ini dense-radius

// The lowest object density (points/m²) at which the model chain runs (collect --plan's default
// --model-density, mk/scenes.mk's TILE_MODEL_DENSITY): 20 since stop 69 (density-scale.md, "The
// model level at 20 points/m², re-measured": on the development ladder's rung 50, whose objects
// measure 21-64 points/m², the chain named 18 of 93 vehicles, all the right model, against 1 at 50,
// and no model on 65 clutter or part candidates nor on 54 real ones classify refused); 50 from
// stop 49 (the chain then named nothing below 50). Before the rule: 370.
constexpr double kModelLevelDensity = 20;
// The lowest object density (points per m² of its rectangle) at which classify answers a class
// (classify's --min-density default; below it too_sparse): what collect states a tile without
// candidates against when no class answer says it.
constexpr double kClassLevelDensity = 4.0;

// The chain's length scales for one candidate (lengths in mm, area in m²).
struct DensityScale {
  int voxel_mm = kDenseVoxelMm;
  double factor = 1;  // voxel / 128 mm, >= 1
  double max_area = kDenseMaxArea;
  int radius_mm = kDenseRadiusMm, dense_radius_mm = kDenseDenseRadiusMm;
  bool dense_end() const { return voxel_mm == kDenseVoxelMm; }
};

// The scale of a candidate of `density` points/m² (> 0 and finite; anything else, like an
// unknown density, gets the dense end: the behaviour before the rule).
inline DensityScale density_scale(double density) {
  DensityScale s;
  if (!(density > 0) || !std::isfinite(density) || density >= kDenseDensity) return s;
  // 1e-9: a density whose exact edge is a whole mm must not round up past it.
  const double exact = kDenseVoxelMm * std::sqrt(kDenseDensity / density);
  s.voxel_mm = std::max(kDenseVoxelMm, static_cast<int>(std::ceil(exact - 1e-9)));
  s.factor = static_cast<double>(s.voxel_mm) / kDenseVoxelMm;
  auto len = [&](int mm) { return static_cast<int>(std::lround(mm * s.factor)); };
  s.max_area = kDenseMaxArea * s.factor * s.factor;
  s.radius_mm = len(kDenseRadiusMm);
  s.dense_radius_mm = len(kDenseDenseRadiusMm);
  return s;
}

// The options one stage gets for scale `s` ("fitvox", "cocone", "ncut"), to follow its --config
// on the command line (a later option overrides the file's value); "" at the dense end and for
// a stage the rule does not touch (gmatch, verify).
constexpr const char* kDensityScaledStages[] = {"fitvox", "cocone", "ncut"};
inline std::string density_scale_options(const DensityScale& s, const std::string& stage) {
  if (s.dense_end()) return "";
  auto mm = [](const char* opt, int v) { return std::string(opt) + " " + std::to_string(v) + "mm"; };
  if (stage == "fitvox") return mm("--voxel", s.voxel_mm);
  if (stage == "cocone") {
    char buf[64];
    std::snprintf(buf, sizeof buf, "--max-area %.6g", s.max_area);
    return buf;
  }
  if (stage == "ncut") return mm("--radius", s.radius_mm) + " " + mm("--dense-radius", s.dense_radius_mm);
  return "";
}

}  // namespace canopy::common
