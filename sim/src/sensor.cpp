// Sensor presets and keys, the scan pattern and the discrete-return detector (sensor.h).
#include "canopy/sim/sensor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sys/stat.h>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "canopy/common/units.h"
#include "canopy/formats/ini.h"

namespace canopy::sim {

using common::UsageError;

namespace {

constexpr double kLight = 299792458.0;  // m/s
constexpr double kDeg = common::kPi / 180;

double number(const std::string& w) {
  if (w.empty() || common::decimal_prefix(w) != w.size() || !common::decimal_problem(w).empty()) {
    throw UsageError("'" + w + "' is not a decimal number");
  }
  return std::strtod(w.c_str(), nullptr);
}

void one(const std::vector<std::string>& w, const std::string& key) {
  if (w.size() != 1) throw UsageError("'" + key + "' takes one value");
}

void bound(double v, double lo, double hi, const std::string& key, const std::string& range) {
  if (!(v >= lo && v <= hi)) throw UsageError(key + " must lie in " + range);
}

int count(const std::string& w, int lo, int hi, const std::string& key) {
  if (w.empty() || w.size() > 6 ||
      !std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; }))
    throw UsageError(key + ": '" + w + "' is not a count");
  const int v = std::atoi(w.c_str());
  if (v < lo || v > hi)
    throw UsageError(key + " must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

const std::vector<std::string>& keys() {
  static const std::vector<std::string> k = {
      "pattern",     "altitude",    "speed",        "pulse_rate",     "scan_rate",          "scan_angle",
      "tilt",        "beams",       "beam_spread",  "divergence",     "footprint_samples",  "angle_step",
      "detector",    "pulse_width", "threshold",    "min_separation", "max_returns",        "photons",
      "range_noise", "sidelap",     "line_turn",    "reflect_ground", "reflect_vegetation", "reflect_clutter",
      "paint_min",   "paint_max",   "reflect_glass"};
  return k;
}

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

}  // namespace

bool is_sensor_key(const std::string& key) {
  return std::find(keys().begin(), keys().end(), key) != keys().end();
}

namespace {

// The reflectance keys (docs/decisions/sensor.md "Surfaces"): each a fraction in [0, 1].
double Sensor::*surface_key(const std::string& key) {
  static const std::pair<const char*, double Sensor::*> kKeys[] = {
      {"reflect_ground", &Sensor::reflect_ground},
      {"reflect_vegetation", &Sensor::reflect_vegetation},
      {"reflect_clutter", &Sensor::reflect_clutter},
      {"paint_min", &Sensor::paint_min},
      {"paint_max", &Sensor::paint_max},
      {"reflect_glass", &Sensor::reflect_glass}};
  for (const auto& [name, field] : kKeys)
    if (key == name) return field;
  return nullptr;
}

}  // namespace

void apply_sensor_key(Sensor* s, const std::string& key, const std::vector<std::string>& w) {
  using common::parse_angle;
  using common::parse_length;
  one(w, key);
  const std::string& v = w[0];
  if (key == "pattern") {
    if (v == "oscillating") {
      s->pattern = ScanPattern::kOscillating;
    } else if (v == "rotating") {
      s->pattern = ScanPattern::kRotating;
    } else {
      throw UsageError("pattern must be 'oscillating' or 'rotating'");
    }
  } else if (key == "detector") {
    if (v == "waveform") {
      s->detector = Detector::kWaveform;
    } else if (v == "photon") {
      s->detector = Detector::kPhoton;
    } else {
      throw UsageError("detector must be 'waveform' or 'photon'");
    }
  } else if (key == "altitude") {
    s->altitude = parse_length(v);
    bound(s->altitude, 20, 5000, key, "[20 m, 5000 m]");
  } else if (key == "speed") {
    s->speed = number(v);
    bound(s->speed, 1, 150, key, "[1, 150] m/s");
  } else if (key == "pulse_rate") {
    s->pulse_rate = number(v);
    bound(s->pulse_rate, 1e3, 5e6, key, "[1000, 5000000] Hz");
  } else if (key == "scan_rate") {
    s->scan_rate = number(v);
    bound(s->scan_rate, 1, 2000, key, "[1, 2000] Hz");
  } else if (key == "scan_angle") {
    s->scan_angle = parse_angle(v);
    bound(s->scan_angle, 0.5 * kDeg, 75 * kDeg + 1e-12, key, "[0.5 deg, 75 deg]");
  } else if (key == "tilt") {
    s->tilt = parse_angle(v);
    bound(s->tilt, -30 * kDeg - 1e-12, 30 * kDeg + 1e-12, key, "[-30 deg, 30 deg]");
  } else if (key == "beams") {
    s->beams = count(v, 1, 128, key);
  } else if (key == "beam_spread") {
    s->beam_spread = parse_angle(v);
    bound(s->beam_spread, 0, 40 * kDeg + 1e-12, key, "[0 deg, 40 deg]");
  } else if (key == "divergence") {
    s->divergence = number(v) * 1e-3;
    bound(s->divergence, 0.01e-3, 10e-3, key, "[0.01, 10] mrad");
  } else if (key == "footprint_samples") {
    s->footprint_samples = count(v, 1, 16, key);
  } else if (key == "angle_step") {
    s->angle_step = parse_angle(v);
    bound(s->angle_step, 0.1 * kDeg - 1e-12, 5 * kDeg + 1e-12, key, "[0.1 deg, 5 deg]");
  } else if (key == "pulse_width") {
    s->pulse_width = number(v) * 1e-9;
    bound(s->pulse_width, 0.1e-9, 20e-9, key, "[0.1, 20] ns");
  } else if (key == "threshold") {
    s->threshold = number(v);
    bound(s->threshold, 0.001, 1, key, "[0.001, 1]");
  } else if (key == "min_separation") {
    s->min_separation = parse_length(v);
    bound(s->min_separation, 0.05, 10, key, "[50 mm, 10 m]");
  } else if (key == "max_returns") {
    s->max_returns = count(v, 1, 15, key);
  } else if (key == "photons") {
    s->photons = number(v);
    bound(s->photons, 0.01, 1000, key, "[0.01, 1000]");
  } else if (key == "range_noise") {
    s->range_noise = parse_length(v);
    bound(s->range_noise, 0, 1, key, "[0 m, 1 m]");
  } else if (key == "sidelap") {
    s->sidelap = number(v);
    bound(s->sidelap, 0, 0.9, key, "[0, 0.9]");
  } else if (key == "line_turn") {
    s->line_turn = number(v);
    bound(s->line_turn, 0, 3600, key, "[0, 3600] s");
  } else if (double Sensor::*field = surface_key(key)) {
    const double r = number(v);
    bound(r, 0, 1, key, "[0, 1]");
    s->*field = r;
  } else {
    throw UsageError("unknown sensor key '" + key + "'");
  }
}

void check_sensor(const Sensor& s) {
  if (s.beams == 1 && s.beam_spread > 0) throw UsageError("beam_spread needs beams > 1");
  const double far = std::max(std::abs(s.tilt - s.beam_spread / 2), std::abs(s.tilt + s.beam_spread / 2));
  if (far > 40 * kDeg + 1e-12)
    throw UsageError("tilt and beam_spread aim a beam more than 40 deg along track");
  if (s.pattern == ScanPattern::kOscillating && s.scan_angle > 40 * kDeg + 1e-12) {
    throw UsageError("an oscillating mirror's scan_angle must lie in [0.5 deg, 40 deg]");
  }
  if (s.paint_min > s.paint_max) throw UsageError("paint_min must not exceed paint_max");
}

Sensor parse_sensor(const std::string& text, const std::string& file, const std::string& name) {
  Sensor s;
  s.name = name;
  formats::IniPolicy policy;  // '#' comments (anywhere), no sections, each key once
  policy.comments = "#";
  policy.kind = "a preset";
  const formats::IniFile ini = formats::parse_ini(text, file, policy);
  for (const formats::IniEntry& e : ini.entries) {
    if (!is_sensor_key(e.key)) ini.fail(e.line, "unknown sensor key '" + e.key + "'");
    try {
      apply_sensor_key(&s, e.key, formats::ini_words(e.value));
    } catch (const UsageError& err) { ini.fail(e.line, err.what()); }
  }
  try {
    check_sensor(s);
  } catch (const UsageError& e) { throw common::DataError(file, e.what()); }
  return s;
}

Sensor load_sensor_preset(const std::string& name) {
  if (name.empty() || name.size() > 64 || !std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
      })) {
    throw UsageError("sensor name '" + name +
                     "': letters, digits, '_' and '-' only (a preset of share/sensors/)");
  }
  const std::string path = common::share_dir() + "/sensors/" + name + ".ini";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    throw UsageError("no sensor preset '" + name + "' (" + path + ")");
  }
  return parse_sensor(common::read_file(path), path, name);
}

std::vector<std::pair<std::string, std::string>> sensor_keys(const Sensor& s) {
  return {{"pattern", s.pattern == ScanPattern::kOscillating ? "oscillating" : "rotating"},
          {"altitude", fmt(s.altitude) + "m"},
          {"speed", fmt(s.speed)},
          {"pulse_rate", fmt(s.pulse_rate)},
          {"scan_rate", fmt(s.scan_rate)},
          {"scan_angle", fmt(s.scan_angle / kDeg) + "deg"},
          {"tilt", fmt(s.tilt / kDeg) + "deg"},
          {"beams", std::to_string(s.beams)},
          {"beam_spread", fmt(s.beam_spread / kDeg) + "deg"},
          {"divergence", fmt(s.divergence * 1e3)},
          {"footprint_samples", std::to_string(s.footprint_samples)},
          {"angle_step", fmt(s.angle_step / kDeg) + "deg"},
          {"detector", s.detector == Detector::kWaveform ? "waveform" : "photon"},
          {"pulse_width", fmt(s.pulse_width * 1e9)},
          {"threshold", fmt(s.threshold)},
          {"min_separation", fmt(s.min_separation) + "m"},
          {"max_returns", std::to_string(s.max_returns)},
          {"photons", fmt(s.photons)},
          {"range_noise", fmt(s.range_noise) + "m"},
          {"sidelap", fmt(s.sidelap)},
          {"line_turn", fmt(s.line_turn)},
          {"reflect_ground", fmt(s.reflect_ground)},
          {"reflect_vegetation", fmt(s.reflect_vegetation)},
          {"reflect_clutter", fmt(s.reflect_clutter)},
          {"paint_min", fmt(s.paint_min)},
          {"paint_max", fmt(s.paint_max)},
          {"reflect_glass", fmt(s.reflect_glass)}};
}

// ---------------------------------------------------------------- scan geometry

std::pair<double, bool> scan_angle_at(const Sensor& s, double t) {
  const double phase = t * s.scan_rate - std::floor(t * s.scan_rate);
  if (s.pattern == ScanPattern::kRotating) return {2 * common::kPi * phase - common::kPi, true};
  // Constant angular speed between the turns: -A -> +A in the first half period, back in the second.
  const double a = s.scan_angle;
  if (phase < 0.5) return {-a + 4 * a * phase, true};
  return {a - 4 * a * (phase - 0.5), false};
}

Eigen::Vector3d beam_direction(const Eigen::Vector2d& f, double theta, double phi) {
  const Eigen::Vector3d right(f.y(), -f.x(), 0), fwd(f.x(), f.y(), 0);
  return std::cos(phi) * (-std::cos(theta) * Eigen::Vector3d::UnitZ() + std::sin(theta) * right) +
         std::sin(phi) * fwd;
}

double beam_angle(const Sensor& s, int beam) {
  if (s.beams <= 1) return s.tilt;
  return s.tilt - s.beam_spread / 2 + s.beam_spread * beam / (s.beams - 1);
}

// ---------------------------------------------------------------- detector

namespace {

std::vector<Return> waveform_returns(const Sensor& s, const std::vector<SubHit>& hits) {
  std::vector<Return> out;
  const double sigma = kLight * s.pulse_width / 2 / 2.354820045;  // range sigma of the pulse
  const double h = sigma / 4;                                     // waveform sample step
  const int half = 16;                                            // kernel half width: 4 sigma
  static thread_local std::vector<double> kernel;
  kernel.assign(2 * half + 1, 0);
  for (int j = -half; j <= half; ++j) kernel[j + half] = std::exp(-0.5 * (j * h / sigma) * (j * h / sigma));
  const double lo = hits.front().range - (half + 2) * h, hi = hits.back().range + (half + 2) * h;
  const auto n = static_cast<std::size_t>((hi - lo) / h) + 2;
  std::vector<double> dep(n, 0), w(n, 0);
  for (const auto& x : hits) {  // energy deposited linearly on the two nearest samples
    const double u = (x.range - lo) / h;
    const auto k = static_cast<std::size_t>(u);
    const double frac = u - k;
    dep[k] += x.energy * (1 - frac);
    dep[k + 1] += x.energy * frac;
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (dep[k] == 0) continue;
    for (int j = -half; j <= half; ++j) {
      const auto m = static_cast<std::ptrdiff_t>(k) + j;
      if (m >= 0 && m < static_cast<std::ptrdiff_t>(n)) w[m] += dep[k] * kernel[j + half];
    }
  }
  double last = -1e300;
  for (std::size_t k = 1; k + 1 < n && static_cast<int>(out.size()) < s.max_returns; ++k) {
    if (!(w[k] > w[k - 1] && w[k] >= w[k + 1] && w[k] >= s.threshold)) continue;
    const double den = w[k - 1] - 2 * w[k] + w[k + 1];
    const double d = den < 0 ? 0.5 * (w[k - 1] - w[k + 1]) / den : 0;
    const double pos = lo + (k + d) * h;
    if (pos - last < s.min_separation) continue;  // inside the dead zone of the previous return
    last = pos;
    Return r;
    r.range = pos;
    r.amplitude = w[k] - 0.25 * (w[k - 1] - w[k + 1]) * d;
    // FWHM: where the waveform falls below half the peak on either side (linear between samples).
    const double halfmax = r.amplitude / 2;
    std::size_t a = k, b = k;
    while (a > 0 && w[a - 1] >= halfmax) --a;
    while (b + 1 < n && w[b + 1] >= halfmax) ++b;
    const double left = a > 0 ? a - (w[a] - halfmax) / (w[a] - w[a - 1]) : 0.0;
    const double right = b + 1 < n ? b + (w[b] - halfmax) / (w[b] - w[b + 1]) : static_cast<double>(n - 1);
    r.width = (right - left) * h;
    double best = -1;
    for (const auto& x : hits) {
      const double c = x.energy * std::exp(-0.5 * ((x.range - pos) / sigma) * ((x.range - pos) / sigma));
      if (c > best) best = c, r.cls = x.cls, r.instance = x.instance;
    }
    out.push_back(r);
  }
  return out;
}

std::vector<Return> photon_returns(const Sensor& s, const std::vector<SubHit>& hits, std::uint64_t key) {
  std::vector<Return> out;
  const double sigma = kLight * s.pulse_width / 2 / 2.354820045;
  common::Rng rng(common::mix64(key));
  double last = -1e300;
  for (const auto& x : hits) {
    if (static_cast<int>(out.size()) >= s.max_returns) break;
    const double p = 1 - std::exp(-s.photons * x.energy);
    const double u = rng.uniform();
    const double jitter = sigma * rng.normal();  // arrival time within the pulse envelope
    if (u >= p || x.range - last < s.min_separation) continue;
    last = x.range;
    Return r;
    r.range = x.range + jitter;
    r.amplitude = p;
    r.cls = x.cls;
    r.instance = x.instance;
    out.push_back(r);
  }
  return out;
}

}  // namespace

std::vector<Return> detect_returns(const Sensor& s, std::vector<SubHit> hits, std::uint64_t rng_key) {
  if (hits.empty()) return {};
  std::stable_sort(hits.begin(), hits.end(),
                   [](const SubHit& a, const SubHit& b) { return a.range < b.range; });
  return s.detector == Detector::kWaveform ? waveform_returns(s, hits) : photon_returns(s, hits, rng_key);
}

// ---------------------------------------------------------------- surfaces

bool model_has_glass(const std::string& name) {
  if (name == "sedan") return true;
  // A family instance's model is named <class>-<instance> (families.h), its spec family:<class>:<n>.
  for (const std::string c : {"sedan", "hatchback", "suv", "pickup", "van"}) {
    if (name.rfind("family:" + c + ":", 0) == 0) return true;
    if (name.size() > c.size() + 1 && name.rfind(c + "-", 0) == 0 &&
        std::all_of(name.begin() + static_cast<std::ptrdiff_t>(c.size()) + 1, name.end(),
                    [](char d) { return d >= '0' && d <= '9'; }))
      return true;
  }
  return false;
}

double paint_reflectance(const Sensor& s, std::uint64_t seed, int instance) {
  common::Rng rng(
      common::mix64(common::derive_seed(seed, "sensor-paint") + static_cast<std::uint64_t>(instance)));
  return s.paint_min + (s.paint_max - s.paint_min) * rng.uniform();
}

double reflectance(const Sensor& s, Surface surface, double paint) {
  switch (surface) {
    case Surface::kGround: return s.reflect_ground;
    case Surface::kVegetation: return s.reflect_vegetation;
    case Surface::kClutter: return s.reflect_clutter;
    case Surface::kGlass: return s.reflect_glass;
    default: return paint;
  }
}

}  // namespace canopy::sim
