// The density rule of the model-level stages (common/density_scale.h): known densities give
// known voxels, areas and radii computed by hand from the rule; the dense end is the
// parameter files' values.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/density_scale.h"
#include "canopy/common/units.h"
#include "canopy/formats/ini.h"

using canopy::common::density_scale;
using canopy::common::density_scale_options;
using canopy::common::DensityScale;

namespace {

// key -> value of a share/params ini file (formats/ini.h, as CLI11's --config reads it).
std::map<std::string, std::string> ini(const std::string& name) {
  const std::string path = std::string(CANOPY_SOURCE_DIR) + "/share/params/" + name;
  std::map<std::string, std::string> kv;
  for (const auto& e : canopy::formats::parse_ini(canopy::common::read_file(path), path, {}).entries)
    kv[e.key] = e.value;
  return kv;
}

int mm(const std::string& length) {
  return static_cast<int>(std::lround(canopy::common::parse_length(length) * 1000));
}

}  // namespace

TEST_CASE("density rule: the dense end is the tile chain's parameter files") {
  const auto fit = ini("fitvox-tile.ini");
  CHECK(mm(fit.at("voxel")) == canopy::common::kDenseVoxelMm);
  // 370 points/m² is the density at which a 128 mm voxel holds fitvox-tile.ini's min-points.
  CHECK(std::stoi(fit.at("min-points")) == 6);
  CHECK(0.128 * 0.128 * canopy::common::kDenseDensity >= 6);
  CHECK(0.128 * 0.128 * canopy::common::kDenseDensity < 6.1);
  CHECK(std::stod(ini("cocone.ini").at("max-area")) == canopy::common::kDenseMaxArea);
  const auto ncut = ini("ncut.ini");
  CHECK(mm(ncut.at("radius")) == canopy::common::kDenseRadiusMm);
  CHECK(mm(ncut.at("dense-radius")) == canopy::common::kDenseDenseRadiusMm);
}

TEST_CASE("density rule: at and above 370 points/m², or unknown, today's values and no options") {
  for (double d : {370.0, 371.0, 800.0, 2800.0, 0.0, -5.0, std::numeric_limits<double>::quiet_NaN(),
                   std::numeric_limits<double>::infinity()}) {
    const DensityScale s = density_scale(d);
    CHECK(s.dense_end());
    CHECK(s.voxel_mm == 128);
    CHECK(s.factor == 1);
    CHECK(s.radius_mm == 512);
    for (const char* stage : {"fitvox", "cocone", "ncut", "gmatch", "verify"})
      CHECK(density_scale_options(s, stage).empty());
  }
}

TEST_CASE("density rule: known densities give known scales") {
  // 92.5 = 370 / 4: the spacing doubles, so every length doubles exactly and areas quadruple.
  const DensityScale q = density_scale(92.5);
  CHECK(q.voxel_mm == 256);
  CHECK(q.factor == 2);
  CHECK(q.max_area == Approx(0.16));
  CHECK(q.radius_mm == 1024);
  CHECK(q.dense_radius_mm == 350);
  CHECK(density_scale_options(q, "fitvox") == "--voxel 256mm");
  CHECK(density_scale_options(q, "cocone") == "--max-area 0.16");
  CHECK(density_scale_options(q, "ncut") == "--radius 1024mm --dense-radius 350mm");
  CHECK(density_scale_options(q, "gmatch").empty());  // relative scales: unchanged
  CHECK(density_scale_options(q, "verify").empty());  // distances to the 128 mm modelbase
  // 200: 128 x sqrt(1.85) = 174.10 mm -> 175 mm (whole mm, upwards: never fewer points than
  // the dense end's per voxel); f = 175 / 128 = 1.3671875.
  const DensityScale s = density_scale(200);
  CHECK(s.voxel_mm == 175);
  CHECK(s.factor == 1.3671875);
  CHECK(s.max_area == Approx(0.04 * 1.3671875 * 1.3671875));
  CHECK(s.radius_mm == 700);        // 512 f = 700.0
  CHECK(s.dense_radius_mm == 239);  // 175 f = 239.26
  CHECK(density_scale_options(s, "cocone") == "--max-area 0.0747681");
  // Just below the dense end: one millimetre more.
  CHECK(density_scale(369).voxel_mm == 129);
  CHECK_FALSE(density_scale(369).dense_end());
}

TEST_CASE("density rule: a voxel keeps the dense end's points per voxel, and grows with the spacing") {
  int last = 0;
  for (double d = 1000; d >= 5; d *= 0.93) {
    const DensityScale s = density_scale(d);
    const double v = s.voxel_mm / 1000.0;
    CHECK(v * v * d >= 6.0);                    // fitvox's floor on a surface of that density
    CHECK((s.dense_end() || v * v * d < 6.2));  // and not much more (the whole-mm rounding)
    CHECK(s.voxel_mm >= last);                  // sparser: never a smaller voxel
    last = s.voxel_mm;
  }
}

TEST_CASE("density rule: the make default of the model level is the header's") {
  std::ifstream in(std::string(CANOPY_SOURCE_DIR) + "/mk/scenes.mk");
  REQUIRE(in);
  std::string line, value;
  while (std::getline(in, line)) {
    if (line.rfind("TILE_MODEL_DENSITY ?= ", 0) == 0) value = line.substr(22);
  }
  REQUIRE_FALSE(value.empty());
  CHECK(std::stod(value) == canopy::common::kModelLevelDensity);
  // The rule reaches down to it: a voxel there still holds the dense end's points.
  const DensityScale s = density_scale(canopy::common::kModelLevelDensity);
  CHECK(s.voxel_mm == 551);  // 128 x sqrt(370 / 20) = 550.55
}
