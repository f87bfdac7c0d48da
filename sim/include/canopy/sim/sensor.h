// Sensor realism for tiles (issue 28; docs/decisions/sensor.md, share/sensors/README.md):
// sensor presets, the scan pattern (flight lines, mirror or rotating head), pulses with a beam
// footprint sampled by sub-rays, the returned waveform and the discrete-return detector.
//
// POV-Ray stays the ray tracer: the pulses of one flight line are grouped by scan direction
// into bins of `angle_step`; each bin is one orthographic image along the bin's direction at a
// pixel spacing of (footprint diameter / footprint_samples), and a pulse's sub-rays are the
// pixels whose centres lie inside its footprint. Nothing here runs POV-Ray or touches a file
// except load_sensor_preset.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace canopy::sim {

enum class ScanPattern { kOscillating, kRotating };
enum class Detector { kWaveform, kPhoton };

struct Sensor {
  std::string name;  // preset name ("" = the built-in defaults changed by keys)
  ScanPattern pattern = ScanPattern::kOscillating;
  double altitude = 900;          // m above the tile centre's ground
  double speed = 60;              // m/s over ground
  double pulse_rate = 500e3;      // Hz, all beams together
  double scan_rate = 100;         // Hz: mirror periods (two scan lines each) or head revolutions
  double scan_angle = 0.3490659;  // rad, half field of view across track (rotating: kept about nadir)
  double tilt = 0;                // rad, fixed along-track tilt of the beam (+ = forward)
  int beams = 1;                  // beams fired in turn (a multi-beam head)
  double beam_spread = 0;         // rad, full along-track fan of the beams
  double divergence = 0.22e-3;    // rad, full angle at 1/e^2 of the beam's energy
  int footprint_samples = 5;      // sub-ray pixels across the footprint's diameter at nadir
  double angle_step = 0.0174533;  // rad, scan-direction bin (one image per bin and line)
  Detector detector = Detector::kWaveform;
  double pulse_width = 4e-9;    // s, FWHM of the emitted pulse (waveform detector)
  double threshold = 0.03;      // peak of the returned energy detected at >= this share of a full-
                                // footprint hit on a white (reflectance 1) Lambertian surface
  double min_separation = 0.7;  // m of range between two returns of one pulse (dead zone)
  int max_returns = 8;
  double photons = 5;  // photon detector: mean signal photons of a full-footprint hit on a white surface
  double range_noise = 0.02;  // m, 1 sigma along the beam
  double sidelap = 0.3;       // share of the swath that neighbouring lines overlap
  double line_turn = 60;      // s between the end of one line and the start of the next
  // Surfaces (reflectance at the laser's wavelength, share of a white Lambertian target): the
  // energy a sub-ray returns is the energy it intercepts times the reflectance of what it hit.
  // All 1 = no reflectance term (every surface returns what it intercepts).
  double reflect_ground = 0.3;
  double reflect_vegetation = 0.45;
  double reflect_clutter = 0.3;
  double paint_min = 0.05, paint_max = 0.6;  // a vehicle's paint: uniform in [min, max] per vehicle
  double reflect_glass = 0.02;               // a car's glazing (windscreen, side and rear windows)
};

// A sensor key applied to `s` (words = the value split at blanks); throws common::UsageError.
// Keys and bounds: share/sensors/README.md.
void apply_sensor_key(Sensor* s, const std::string& key, const std::vector<std::string>& words);
// Checks what depends on several keys (e.g. beam_spread with beams); throws UsageError.
void check_sensor(const Sensor& s);
// Reads share/sensors/<name>.ini; DataError naming the file and line on any problem.
Sensor load_sensor_preset(const std::string& name);
// Parses a preset's text; `file` is used in errors.
Sensor parse_sensor(const std::string& text, const std::string& file, const std::string& name);
bool is_sensor_key(const std::string& key);
// The keys as "key value" text (truth.json, provenance), in a fixed order.
std::vector<std::pair<std::string, std::string>> sensor_keys(const Sensor& s);

// ---------------------------------------------------------------- scan geometry

// Scan angle (rad, + = right of the flight direction) and scan direction flag at time t.
std::pair<double, bool> scan_angle_at(const Sensor& s, double t);
// Unit direction of a beam (from the sensor) with scan angle theta and along-track angle phi,
// for flight direction f (horizontal unit vector).
Eigen::Vector3d beam_direction(const Eigen::Vector2d& f, double theta, double phi);
// Along-track angle of beam b (tilt + its place in the fan).
double beam_angle(const Sensor& s, int beam);
// 1/e^2 footprint radius at range r.
inline double footprint_radius(const Sensor& s, double range) { return range * std::tan(s.divergence / 2); }

// ---------------------------------------------------------------- detector

// One sub-ray of a pulse that hit something: range from the sensor, the share of the pulse's
// energy it carries (weights of all sub-rays of the pulse, hit or not, sum to 1), and what it hit.
struct SubHit {
  double range = 0;
  double energy = 0;
  std::uint32_t cls = 0;
  std::int32_t instance = 0;
};

struct Return {
  double range = 0;       // m from the sensor, before range noise
  double amplitude = 0;   // waveform peak as a share of a full hit (photon: photons detected / photons)
  double width = 0;       // m, FWHM of the waveform peak in range (photon: 0)
  std::uint32_t cls = 0;  // of the sub-ray contributing most at the peak
  std::int32_t instance = 0;
};

// The discrete returns of one pulse, in range order (at most max_returns). Waveform: the sum of
// the sub-rays' energies each spread as the emitted Gaussian pulse in range; local maxima at or
// above `threshold`, taken in range order, each at least `min_separation` beyond the previous.
// Photon: each sub-ray detects with probability 1 - exp(-photons * energy) in range order, a
// detection blinding the detector for `min_separation` of range. `rng_key` seeds the photon
// draws (same key, same returns).
std::vector<Return> detect_returns(const Sensor& s, std::vector<SubHit> hits, std::uint64_t rng_key);

// ---------------------------------------------------------------- surfaces

// What a sub-ray hit, for its reflectance.
enum class Surface { kGround, kVegetation, kClutter, kPaint, kGlass };
// The glazing of a car: the greenhouse between `glass_lo` and `glass_hi` of the vehicle's height
// (bounding box of its model), i.e. above the bonnet and boot, below the roof panel. Only the
// models that have one: the built-in sedan and the car/van families (families.cpp).
bool model_has_glass(const std::string& model_name);
constexpr double kGlassLo = 0.66, kGlassHi = 0.97;
// A vehicle's paint reflectance, uniform in [paint_min, paint_max], drawn from (seed, instance).
double paint_reflectance(const Sensor& s, std::uint64_t seed, int instance);
double reflectance(const Sensor& s, Surface surface, double paint);

}  // namespace canopy::sim
