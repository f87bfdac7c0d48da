// rangetrace sensor mode (issue 28): presets and keys, the detector on hand-made waveforms, and
// physics on tiny analytic tiles rendered by POV-Ray (flat plate, 50%-open grid of discs over
// the ground, slanted plate), checked against closed-form answers.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/las.h"
#include "canopy/formats/trajectory.h"
#include "rangetrace/tile.h"
#include "support/cli.h"

using namespace canopy;
using namespace canopy::rangetrace;

namespace {

constexpr double kLight = 299792458.0;
const double kDeg = canopy::common::kDegree;

void write_text(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string slurp(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

Params small_params() {
  Params p;
  p.seed = 5;
  p.threads = 2;
  return p;
}

// Builds and scans a recipe given as text.
struct Scanned {
  Tile tile;
  TileScan scan;
};
Scanned scan_recipe(const std::string& dirname, const std::string& text) {
  const auto dir = test::fresh_dir("rangetrace", dirname);
  write_text(dir / "t.scene", text);
  const SceneRecipe s = load_scene((dir / "t.scene").string());
  Scanned out{build_tile(*s.tile, "t.scene", small_params()), {}};
  out.scan = run_tile(&out.tile, small_params());
  return out;
}

std::string sensor_error(const std::string& text) {
  try {
    parse_sensor(text, "x.ini", "x");
  } catch (const common::DataError& e) { return e.what(); }
  return "";
}

std::string recipe_error(const std::string& text) {
  try {
    parse_scene(text, "r.scene");
  } catch (const common::Error& e) { return e.what(); }
  return "";
}

// Pulse FWHM in range (m) and its sigma.
double pulse_sigma(const Sensor& s) { return kLight * s.pulse_width / 2 / 2.354820045; }

// FWHM of the echo of a plane at incidence i: the Gaussian pulse (sigma_p) convolved with the
// range spread of the beam's footprint. A point x r along the plane's slope direction inside
// the footprint (r = 1/e^2 radius, profile exp(-2 rho^2) truncated at rho = 1) lies x a further
// in range, a = r tan i; x has density exp(-2 x^2) erf(sqrt(2 (1 - x^2))) on [-1, 1].
double echo_fwhm(double sigma_p, double a) {
  const int nx = 200;
  std::vector<double> px(nx), off(nx);
  for (int k = 0; k < nx; ++k) {
    const double x = -1 + (k + 0.5) * 2.0 / nx;
    off[k] = x * a;
    px[k] = std::exp(-2 * x * x) * std::erf(std::sqrt(2 * (1 - x * x)));
  }
  const double span = a + 4 * sigma_p, step = span / 1000;
  std::vector<double> w;
  for (double d = -span; d <= span; d += step) {
    double v = 0;
    for (int k = 0; k < nx; ++k)
      v += px[k] * std::exp(-0.5 * (d - off[k]) * (d - off[k]) / (sigma_p * sigma_p));
    w.push_back(v);
  }
  const double peak = *std::max_element(w.begin(), w.end());
  std::size_t lo = 0, hi = w.size() - 1;
  while (w[lo] < peak / 2) ++lo;
  while (w[hi] < peak / 2) --hi;
  return (hi - lo) * step;
}

}  // namespace

TEST_CASE("sensor presets: every preset parses; keys are bounded; errors name file and line") {
  for (const char* name : {"als_qL1", "geiger_wide", "uav_multibeam", "thesis_ladar"}) {
    const std::string path = std::string(CANOPY_SOURCE_DIR) + "/share/sensors/" + name + ".ini";
    const Sensor s = parse_sensor(slurp(path), path, name);
    CHECK(s.name == name);
  }
  CHECK_THAT(sensor_error("speed = 60\nbogus = 1\n"), Catch::Contains("x.ini") && Catch::Contains("line 2") &&
                                                          Catch::Contains("unknown sensor key 'bogus'"));
  CHECK_THAT(sensor_error("pulse_rate = 10\n"), Catch::Contains("line 1") && Catch::Contains("pulse_rate"));
  CHECK_THAT(sensor_error("speed = 60\nspeed = 61\n"), Catch::Contains("given twice"));
  // formats/ini.h (docs/decisions/ini.md): '=' needs no blanks around it (before: an error); BOM
  // and CRLF read as text; ';' is no comment in a preset.
  CHECK(parse_sensor("speed=61\n", "x.ini", "x").speed == 61);
  CHECK(parse_sensor("\xEF\xBB\xBF"
                     "speed = 62 # m/s\r\n",
                     "x.ini", "x")
            .speed == 62);
  CHECK_THAT(sensor_error("speed = 60 ; m/s\n"), Catch::Contains("x.ini: line 1: "));
  CHECK_THAT(sensor_error("speed =\n"), Catch::Contains("x.ini: line 1: key 'speed' has no value"));
  CHECK_THAT(sensor_error("scan_angle = 50deg\n"), Catch::Contains("oscillating"));
  CHECK_THAT(sensor_error("max_returns = 16\n"), Catch::Contains("max_returns"));
  CHECK_THAT(sensor_error("divergence = 0x10\n"), Catch::Contains("not a decimal number"));
  CHECK_THAT(sensor_error("beam_spread = 10deg\n"), Catch::Contains("beams > 1"));
  // In a recipe: an unknown preset, a bad override and an image-mode key each name the line.
  CHECK_THAT(recipe_error("extent = 10m\nsensor = nosuch\n"),
             Catch::Contains("r.scene") && Catch::Contains("line 2") && Catch::Contains("nosuch"));
  CHECK_THAT(recipe_error("extent = 10m\nsensor = als_qL1\nsensor.speed = 0\n"),
             Catch::Contains("line 3") && Catch::Contains("speed"));
  CHECK_THAT(recipe_error("extent = 10m\nsensor.frobnicate = 1\n"), Catch::Contains("line 2"));
  CHECK_THAT(recipe_error("extent = 10m\nsensor = als_qL1\nlooks = 90deg\n"),
             Catch::Contains("line 3") && Catch::Contains("looks"));
  // A flight that would fire too many pulses is refused before any work.
  CHECK_THAT(recipe_error("extent = 100m\nsensor.speed = 1\nsensor.pulse_rate = 5000000\n"),
             Catch::Contains("r.scene") && Catch::Contains("5e7 pulses"));
  // Keys override the preset.
  const SceneRecipe r =
      parse_scene("extent = 10m\nsensor.pulse_rate = 250000\nsensor = als_qL1\n", "r.scene");
  REQUIRE(r.tile->sensor);
  CHECK(r.tile->sensor->pulse_rate == 250000);
  CHECK(r.tile->sensor->speed == 60);
}

TEST_CASE("sensor detector: returns from hand-made waveforms") {
  Sensor s;  // waveform, 4 ns pulse, threshold 0.03, min separation 0.7 m, 8 returns
  const double fwhm = kLight * s.pulse_width / 2;
  // One surface with all the energy: one return at its range, amplitude 1, the pulse's width.
  auto r = detect_returns(s, {{300.0, 1.0, 0, 0}}, 1);
  REQUIRE(r.size() == 1);
  CHECK(r[0].range == Approx(300).margin(0.005));
  CHECK(r[0].amplitude == Approx(1).margin(0.01));
  CHECK(r[0].width == Approx(fwhm).epsilon(0.03));
  // Half the energy 5 m above the other half: two returns of amplitude 0.5, in range order.
  r = detect_returns(s, {{305.0, 0.5, 0, 0}, {300.0, 0.5, 1, 0}}, 1);
  REQUIRE(r.size() == 2);
  CHECK(r[0].range == Approx(300).margin(0.005));
  CHECK(r[0].cls == 1);
  CHECK(r[1].range == Approx(305).margin(0.005));
  CHECK(r[0].amplitude == Approx(0.5).margin(0.01));
  CHECK(r[1].amplitude == Approx(0.5).margin(0.01));
  // Two surfaces 1.0 m apart (resolved as two peaks: 1.0 m = 3.9 sigma of the 4 ns pulse): two
  // returns with a 0.7 m dead zone (the default), one with 1.5 m (the second is in the dead zone).
  REQUIRE(s.min_separation == Approx(0.7));
  r = detect_returns(s, {{300.0, 0.5, 0, 0}, {301.0, 0.5, 0, 0}}, 1);
  REQUIRE(r.size() == 2);
  CHECK(r[1].range - r[0].range == Approx(1.0).margin(0.01));
  Sensor wide = s;
  wide.min_separation = 1.5;
  CHECK(detect_returns(wide, {{300.0, 0.5, 0, 0}, {301.0, 0.5, 0, 0}}, 1).size() == 1);
  // Below the threshold: nothing; nine surfaces: at most max_returns (8 by default, then 4).
  CHECK(detect_returns(s, {{300.0, 0.02, 0, 0}}, 1).empty());
  std::vector<SubHit> nine;
  for (int k = 0; k < 9; ++k) nine.push_back({300.0 + 3 * k, 0.11, 0, 0});
  CHECK(detect_returns(s, nine, 1).size() == 8);
  Sensor four = s;
  four.max_returns = 4;
  CHECK(detect_returns(four, nine, 1).size() == 4);
  // Photon detector: detection probability 1 - exp(-photons * energy) (measured over pulses).
  Sensor p;
  p.detector = Detector::kPhoton;
  p.photons = 1;
  int detected = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) detected += detect_returns(p, {{300.0, 0.5, 0, 0}}, k).empty() ? 0 : 1;
  const double want = 1 - std::exp(-0.5);  // 0.393; 4000 draws: sd 0.0077
  CHECK(detected / double(n) == Approx(want).margin(0.03));
}

TEST_CASE("sensor surfaces: paint draws, glazing models, bounded keys") {
  Sensor s;
  s.paint_min = 0.1;
  s.paint_max = 0.3;
  double lo = 1, hi = 0, sum = 0;
  const int n = 2000;
  for (int k = 1; k <= n; ++k) {
    const double p = sim::paint_reflectance(s, 7, k);
    CHECK(p == sim::paint_reflectance(s, 7, k));  // same seed and instance, same paint
    lo = std::min(lo, p), hi = std::max(hi, p), sum += p;
  }
  CHECK(lo >= 0.1);
  CHECK(hi <= 0.3);
  CHECK(sum / n == Approx(0.2).margin(0.005));  // uniform: mean 0.2, sd of the mean 0.0013
  CHECK(sim::paint_reflectance(s, 7, 1) != sim::paint_reflectance(s, 8, 1));
  for (const char* m : {"sedan", "sedan-501", "hatchback-2", "suv-603", "pickup-1", "van-604", "family:van:3"})
    CHECK(sim::model_has_glass(m));
  for (const char* m : {"semi", "tank", "earthmover", "obj1", "tank-3", "bus-2", "sedan-x", "my.ply"})
    CHECK_FALSE(sim::model_has_glass(m));
  CHECK(sim::reflectance(s, sim::Surface::kPaint, 0.25) == 0.25);
  CHECK(sim::reflectance(s, sim::Surface::kGlass, 0.25) == s.reflect_glass);
  CHECK_THAT(sensor_error("reflect_glass = 1.5\n"),
             Catch::Contains("line 1") && Catch::Contains("reflect_glass"));
  CHECK_THAT(sensor_error("paint_min = 0.5\npaint_max = 0.4\n"), Catch::Contains("paint_min"));
}

TEST_CASE("sensor physics: a flat plate gives one return per pulse at PRF / (speed x swath)") {
  const std::string base =
      "extent = 20m 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n";
  const Scanned a = scan_recipe("sensor_plate", base);
  const Sensor& s = *a.tile.recipe.sensor;
  const double swath = 2 * s.altitude * std::tan(s.scan_angle);
  const double want = s.pulse_rate / (s.speed * swath);  // 12.72 pulses/m^2
  CHECK(a.tile.fired_per_m2 == Approx(want).epsilon(0.05));
  CHECK(a.tile.returns_per_m2 == Approx(a.tile.fired_per_m2).epsilon(0.01));
  // Every pulse: exactly one return, on the ground, within 5 sigma of range noise of z = 0.
  CHECK(a.tile.pulses_by_returns[0] == 0);
  CHECK(a.tile.pulses_by_returns[2] == 0);
  const auto& c = a.scan.cloud;
  REQUIRE(c.size() > 2000);
  for (std::size_t i = 0; i < c.size(); ++i) {
    CHECK(c.col("number_of_returns")[i] == 1);
    CHECK(c.col("classification")[i] == 2);
    CHECK(std::abs(c.col("z")[i]) < 5 * s.range_noise + 0.002);
    CHECK(std::abs(c.col("scan_angle")[i]) <= 20.0001);
  }
  // Half the pulse rate, half the density.
  const Scanned b = scan_recipe("sensor_plate_half", base + "sensor.pulse_rate = 250000\n");
  CHECK(b.tile.fired_per_m2 / a.tile.fired_per_m2 == Approx(0.5).epsilon(0.05));
  // Twice the speed, half the density; twice the altitude (twice the swath), half again.
  const Scanned f = scan_recipe("sensor_plate_fast", base + "sensor.speed = 120\n");
  CHECK(f.tile.fired_per_m2 / a.tile.fired_per_m2 == Approx(0.5).epsilon(0.05));
}

TEST_CASE("sensor physics: a 50%-open grid of discs over the ground gives two returns of half energy") {
  // Discs of radius 0.25 m on a square lattice of pitch 0.25 sqrt(2 pi) m cover half the area,
  // 5 m above flat ground. A 3 mrad beam at 900 m has a 2.7 m footprint spanning many discs, so
  // each pulse puts about half its energy on the discs and half on the ground: two returns,
  // first on the canopy, amplitudes about 0.5 each.
  std::string text =
      "extent = 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n"
      "sensor.divergence = 3\nsensor.footprint_samples = 16\nsensor.range_noise = 0m\n";
  const double pitch = 0.25 * std::sqrt(2 * canopy::common::kPi);
  for (double x = -2 * pitch; x < 12; x += pitch) {
    for (double y = -2 * pitch; y < 12; y += pitch) {
      text += "canopy_disc = " + std::to_string(x) + " " + std::to_string(y) + " 5m 0.25m\n";
    }
  }
  const auto dir = test::fresh_dir("rangetrace", "sensor_grid");
  write_text(dir / "t.scene", text);
  SceneRecipe s = load_scene((dir / "t.scene").string());
  Tile tile = build_tile(*s.tile, "t.scene", small_params());
  const TileScan scan = run_tile(&tile, small_params());
  const auto& c = scan.cloud;
  std::size_t pulses = 0, two = 0;
  double a1 = 0, a2 = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.col("return_number")[i] != 1) continue;
    // Away from the tile's edges, so that a pulse's ground return (up to 1.8 m aside from its
    // canopy return at a 20 deg scan angle) is inside the tile too.
    if (std::abs(c.col("x")[i] - 5) > 3 || std::abs(c.col("y")[i] - 5) > 3) continue;
    ++pulses;
    if (c.col("number_of_returns")[i] != 2 || i + 1 >= c.size() || c.col("return_number")[i + 1] != 2)
      continue;
    ++two;
    CHECK(c.col("label")[i] == formats::kLabelFoliage);
    CHECK(c.col("label")[i + 1] == formats::kLabelGround);
    CHECK(c.col("z")[i] == Approx(5).margin(0.05));
    CHECK(c.col("z")[i + 1] == Approx(0).margin(0.05));
    a1 += c.col("intensity")[i] / 65535;
    a2 += c.col("intensity")[i + 1] / 65535;
  }
  REQUIRE(pulses > 200);
  CHECK(two / double(pulses) > 0.95);
  // The returned energy: half the footprint times the surface's reflectance (preset: 0.45, 0.3).
  const Sensor& sn = *tile.recipe.sensor;
  CHECK(a1 / two == Approx(0.5 * sn.reflect_vegetation).margin(0.03));
  CHECK(a2 / two == Approx(0.5 * sn.reflect_ground).margin(0.03));
}

namespace {

// The 50%-open grid of discs of the test above at height `h`, with extra sensor lines; returns
// the pulses whose first return lies in the tile's middle, by their number of returns.
std::vector<std::size_t> grid_pulses(const std::string& name, double h, const std::string& extra) {
  std::string text =
      "extent = 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n"
      "sensor.divergence = 3\nsensor.footprint_samples = 16\nsensor.range_noise = 0m\n" +
      extra;
  const double pitch = 0.25 * std::sqrt(2 * canopy::common::kPi);
  for (double x = -2 * pitch; x < 12; x += pitch) {
    for (double y = -2 * pitch; y < 12; y += pitch) {
      text += "canopy_disc = " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(h) +
              "m 0.25m\n";
    }
  }
  const Scanned a = scan_recipe(name, text);
  std::vector<std::size_t> by(9, 0);
  const auto& c = a.scan.cloud;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.col("return_number")[i] != 1) continue;
    if (std::abs(c.col("x")[i] - 5) > 3 || std::abs(c.col("y")[i] - 5) > 3) continue;
    ++by[static_cast<std::size_t>(c.col("number_of_returns")[i])];
  }
  return by;
}

}  // namespace

TEST_CASE(
    "sensor physics: discs 1.0 m above the ground give two returns with a 0.7 m dead zone, one with 1.5 m") {
  // Half the footprint on discs 1.0 m up, half on the ground (pulses within 2 deg of nadir:
  // range difference 1.0 m / cos(theta) within 0.1 %).
  const auto near = grid_pulses("sensor_dz07", 1.0, "");
  const auto far = grid_pulses("sensor_dz15", 1.0, "sensor.min_separation = 1.5m\n");
  const std::size_t n07 = near[1] + near[2], n15 = far[1] + far[2];
  REQUIRE(n07 > 200);
  CHECK(near[2] / double(n07) > 0.95);
  CHECK(far[1] / double(n15) > 0.95);
}

TEST_CASE("sensor physics: the detection threshold acts on the returned energy (reflectance)") {
  // Discs (half the footprint) of reflectance 0.05 return 0.025 < threshold 0.03: no canopy
  // return, so one return per pulse (the ground's 0.5 x 0.3 = 0.15 passes).
  const auto dim = grid_pulses("sensor_dimveg", 5.0, "sensor.reflect_vegetation = 0.05\n");
  REQUIRE(dim[1] > 200);
  CHECK(dim[2] == 0);
  // A plate of reflectance r: a full-footprint hit returns r (intensity = r x 65535); below the
  // threshold it returns nothing.
  const std::string plate =
      "extent = 20m 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n";
  const Scanned bright = scan_recipe("sensor_refl", plate + "sensor.reflect_ground = 0.4\n");
  REQUIRE(bright.scan.cloud.size() > 2000);
  CHECK(bright.tile.pulses_by_returns[0] == 0);
  double mean = 0;
  for (std::size_t i = 0; i < bright.scan.cloud.size(); ++i) mean += bright.scan.cloud.col("intensity")[i];
  CHECK(mean / bright.scan.cloud.size() / 65535 == Approx(0.4).margin(0.005));
  const Scanned dark = scan_recipe("sensor_dark", plate + "sensor.reflect_ground = 0.025\n");
  CHECK(dark.scan.cloud.size() == 0);
  CHECK(dark.tile.pulses_by_returns[0] > 2000);
  // Photon detector on a plate of reflectance r: a pulse detects with probability
  // 1 - exp(-photons x r) (one sub-ray sample per pulse: footprint_samples = 1).
  const Scanned ph =
      scan_recipe("sensor_photon_plate",
                  plate +
                      "sensor.detector = photon\nsensor.photons = 2\nsensor.footprint_samples = 1\n"
                      "sensor.reflect_ground = 0.25\n");
  std::size_t fired = 0;
  for (auto n : ph.tile.pulses_by_returns) fired += n;
  REQUIRE(fired > 2000);
  const double share = 1 - ph.tile.pulses_by_returns[0] / double(fired);
  const double want = 1 - std::exp(-2 * 0.25);  // 0.393; sd over 2500 pulses ~ 0.01
  CHECK(share == Approx(want).margin(0.04));
}

TEST_CASE("sensor physics: car glazing and paint below the threshold drop out") {
  // One built-in sedan on flat ground, paint 0.5: with glass as bright as the paint, returns
  // from its greenhouse band (0.66 - 0.97 of its height); with reflect_glass = 0 none from
  // there, the rest of the car unchanged; paint and glass below the threshold: no car returns.
  const std::string base =
      "extent = 12m 10m\ntrees = 0\nbushes = 0\nhide = 0\ncanopy_spacing = 0.5m\n"
      "vehicle = sedan 6 5 10deg\nsensor = als_qL1\nsensor.range_noise = 0m\n";
  const std::string paint = "sensor.paint_min = 0.5\nsensor.paint_max = 0.5\n";
  auto count = [](const Scanned& a, std::size_t* band) {
    const auto& v = a.tile.vehicles.at(0);
    const auto& lo = a.tile.model_bounds[v.model_index].first;
    const auto& hi = a.tile.model_bounds[v.model_index].second;
    const Eigen::Vector3d anchor((lo.x() + hi.x()) / 2, (lo.y() + hi.y()) / 2, lo.z());
    const Eigen::Affine3d to_model = (v.pose.transform() * Eigen::Translation3d(-anchor)).inverse();
    std::size_t all = 0;
    *band = 0;
    const auto& c = a.scan.cloud;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (c.col("instance")[i] != 1) continue;
      ++all;
      const double z = (to_model * Eigen::Vector3d(c.col("x")[i], c.col("y")[i], c.col("z")[i])).z();
      const double rel = (z - lo.z()) / (hi.z() - lo.z());
      // inside the band, 2 cm from its edges (the detector's range interpolation)
      if (rel > sim::kGlassLo + 0.02 / (hi.z() - lo.z()) && rel < sim::kGlassHi - 0.02 / (hi.z() - lo.z()))
        ++*band;
    }
    return all;
  };
  std::size_t band_clear = 0, band_glass = 0, band_dark = 0;
  const std::size_t clear =
      count(scan_recipe("sensor_glass1", base + paint + "sensor.reflect_glass = 0.5\n"), &band_clear);
  const std::size_t glass =
      count(scan_recipe("sensor_glass0", base + paint + "sensor.reflect_glass = 0\n"), &band_glass);
  INFO("car returns " << clear << " (band " << band_clear << ") -> " << glass << " (band " << band_glass
                      << ")");
  CHECK(band_clear > 10);
  CHECK(band_glass == 0);
  CHECK(clear - band_clear == Approx(glass).epsilon(0.1));
  const std::size_t dark = count(
      scan_recipe("sensor_darkcar",
                  base + "sensor.paint_min = 0.02\nsensor.paint_max = 0.02\nsensor.reflect_glass = 0.02\n"),
      &band_dark);
  CHECK(dark == 0);
}

TEST_CASE("sensor physics: swath_offset puts the tile off the swath's centre") {
  // Lines 100 m to the left of the tile (heading +x): the tile lies right of line 1, at scan
  // angles about atan(100 / 900) = 6.34 deg (+ = right), +-0.32 deg across its 10 m; the next
  // line (458.6 m away) does not reach it.
  const std::string plate =
      "extent = 20m 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n";
  const Scanned a = scan_recipe("sensor_offset", plate + "swath_offset = 100m\n");
  const auto& c = a.scan.cloud;
  REQUIRE(c.size() > 2000);
  double mean = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    CHECK(c.col("point_source_id")[i] == 1);
    CHECK(c.col("scan_angle")[i] > 5.9);
    CHECK(c.col("scan_angle")[i] < 6.8);
    mean += c.col("scan_angle")[i];
  }
  CHECK(mean / c.size() == Approx(std::atan(100.0 / 900) / kDeg).margin(0.05));
  REQUIRE(a.tile.flight_lines.size() == 1);
  CHECK(a.tile.flight_lines[0].offset == Approx(100));
  // Density at scan angle theta: pulses uniform in the mirror's angle (constant angular speed
  // 4 A x scan_rate), ground position H tan(theta): PRF cos^2(theta) / (speed x 2 A H).
  const Sensor& s = *a.tile.recipe.sensor;
  const double th = std::atan(100.0 / 900);
  const double want = s.pulse_rate * std::cos(th) * std::cos(th) / (s.speed * 2 * s.scan_angle * s.altitude);
  CHECK(a.tile.fired_per_m2 == Approx(want).epsilon(0.03));
  CHECK_THAT(recipe_error("extent = 10m\nswath_offset = 100m\n"),
             Catch::Contains("line 2") && Catch::Contains("sensor"));
  CHECK_THAT(recipe_error("extent = 10m\nsensor = als_qL1\nswath_offset = 400m\n"),
             Catch::Contains("line 3") && Catch::Contains("half swath"));
}

TEST_CASE("sensor physics: on a slanted plate the echo widens as the footprint spreads in range") {
  // The echo of a slanted plane is wider than the pulse by the footprint's spread in range
  // (echo_fwhm); on a level plane at the scan's small incidences it is about the pulse.
  const std::string base =
      "extent = 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n"
      "sensor.divergence = 6\nsensor.footprint_samples = 12\nsensor.range_noise = 0m\n";
  for (double slope : {0.0, 15.0}) {
    const Scanned a = scan_recipe("sensor_slope", base + "terrain = slope " + std::to_string(slope) + "deg\n");
    const Sensor& s = *a.tile.recipe.sensor;
    const auto& c = a.scan.cloud;
    REQUIRE(c.size() > 500);
    double got = 0, want = 0;
    const double alpha = slope * kDeg;
    for (std::size_t i = 0; i < c.size(); ++i) {
      const double theta = c.col("scan_angle")[i] * kDeg;
      // Beam (0, sin theta, -cos theta) on the plane rising toward +x by alpha.
      const double incidence = std::acos(std::cos(theta) * std::cos(alpha));
      const double range = (s.altitude - c.col("z")[i]) / std::cos(theta);
      const double r = range * std::tan(s.divergence / 2);
      want += echo_fwhm(pulse_sigma(s), r * std::tan(incidence));
      got += c.col("echo_width")[i];
    }
    got /= c.size();
    want /= c.size();
    INFO("slope " << slope << ": echo width " << got << " m, expected " << want << " m");
    CHECK(got == Approx(want).epsilon(0.02));
    if (slope > 0) CHECK(got > 1.4 * 2.354820045 * pulse_sigma(s));  // clearly wider than the pulse
    if (slope == 0) CHECK(got == Approx(2.354820045 * pulse_sigma(s)).epsilon(0.05));
  }
}

TEST_CASE("rangetrace CLI: a sensor tile as LAS 1.4 format 6 with its trajectory beside it") {
  const auto dir = test::fresh_dir("rangetrace", "sensor_cli");
  write_text(dir / "s.scene",
             "extent = 10m\ntrees = 0\nbushes = 0\ncanopy_spacing = 0.5m\nsensor = als_qL1\n"
             "origin = 500000 4400000 100\nvehicle = sedan 5 5 0\nsensor.paint_min = 0.5\n");
  std::string err;
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/rangetrace";
  std::filesystem::create_directories(dir / "again");
  const std::string cmd = bin + " --scene ../s.scene --truth truth.json --seed 2 -o s.las";
  REQUIRE(test::sh("cd " + dir.string() + "/again && " + cmd, dir / "err.txt", &err) == 0);
  std::filesystem::create_directories(dir / "run");
  REQUIRE(test::sh("cd " + dir.string() + "/run && " + cmd, dir / "err.txt", &err) == 0);
  for (const char* f : {"s.las", "s.traj", "truth.json"}) {
    CHECK(slurp(dir / "run" / f) == slurp(dir / "again" / f));  // same seed, same bytes
  }
  const std::string las = slurp(dir / "run" / "s.las");
  CHECK(static_cast<int>(static_cast<unsigned char>(las[104])) == 6);  // point data format
  const formats::PointCloud c = formats::read_las((dir / "run" / "s.las").string());
  for (const char* col : {"return_number", "number_of_returns", "scan_angle", "gps_time", "point_source_id",
                          "classification", "label", "instance", "echo_width"}) {
    CHECK(c.has(col));
  }
  const formats::Trajectory t = formats::read_trajectory((dir / "run" / "s.traj").string());
  std::size_t vehicle = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto pos = formats::trajectory_position(t, c.col("gps_time")[i], 0, "s.traj");
    CHECK(pos[2] == Approx(1000).margin(1e-6));  // 900 m above the origin's 100 m
    CHECK(c.col("point_source_id")[i] == 1);
    if (c.col("label")[i] == formats::kLabelTarget) {
      ++vehicle;
      CHECK(c.col("instance")[i] == 1);
      CHECK(c.col("classification")[i] == 1);
    } else {
      CHECK(c.col("instance")[i] == 0);
    }
  }
  CHECK(vehicle > 50);  // 4.8 x 2 m at ~12.7 pulses/m^2
  const std::string truth = slurp(dir / "run" / "truth.json");
  CHECK_THAT(truth, Catch::Contains("\"density\"") && Catch::Contains("\"returns_per_m2\"") &&
                        Catch::Contains("\"preset\": \"als_qL1\"") && Catch::Contains("\"flight_lines\""));
}
