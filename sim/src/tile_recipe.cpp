// Tile recipe keys (share/scenes/README.md). Every value is bounded here, so a short recipe
// can never ask for unbounded work or memory.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/units.h"
#include "canopy/sim/tile.h"

namespace canopy::sim {

using common::UsageError;

const char* const kClutterKinds[kClutterKindCount] = {"boulder",  "shed",    "container", "fence",
                                                      "logs",     "trailer", "caravan",   "pipes",
                                                      "barriers", "tent",    "rock"};

namespace {

const std::set<std::string>& tile_keys() {
  static const std::set<std::string> keys = {
      "extent",         "terrain",     "trees",       "hide",     "conifer_share", "bushes",
      "tree",           "canopy_disc", "vehicle",     "vehicles", "object",        "clutter",
      "flight_lines",   "headings",    "looks",       "altitude", "spacing",       "swath_overlap",
      "canopy_spacing", "origin",      "swath_offset"};
  return keys;
}

// A decimal number, [+-]digits[.digits][e[+-]digits], finite: no hexadecimal ("0x10"), no
// "inf" or "nan", no trailing text.
double number(const std::string& w) {
  if (w.empty() || common::decimal_prefix(w) != w.size())
    throw UsageError("'" + w + "' is not a decimal number");
  const double v = std::strtod(w.c_str(), nullptr);
  if (!std::isfinite(v)) throw UsageError("'" + w + "' is not a finite number");
  return v;
}

// A count: decimal digits only (no sign, no "0x10", no trailing text).
int count(const std::string& w, int max) {
  if (w.empty() || !std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    throw UsageError("'" + w + "' is not a count >= 0");
  }
  if (w.size() > 9 || std::strtol(w.c_str(), nullptr, 10) > max) {
    throw UsageError("count " + w + " exceeds the limit of " + std::to_string(max));
  }
  return static_cast<int>(std::strtol(w.c_str(), nullptr, 10));
}

void need(const std::vector<std::string>& words, std::size_t lo, std::size_t hi, const std::string& form) {
  if (words.size() < lo || words.size() > hi) throw UsageError("expected '" + form + "'");
}

bool is_kind(const std::string& k) {
  return std::find_if(std::begin(kClutterKinds), std::end(kClutterKinds),
                      [&](const char* c) { return k == c; }) != std::end(kClutterKinds);
}

std::string kinds() {
  std::string s;
  for (const char* k : kClutterKinds) s += std::string(s.empty() ? "" : ", ") + k;
  return s;
}

// terrain = flat | slope ANGLE [AZIMUTH] | rolling [AMPLITUDE [WAVELENGTH]]
void apply_terrain(TileRecipe* t, const std::vector<std::string>& w) {
  using common::parse_angle;
  using common::parse_length;
  if (w[0] == "flat" && w.size() == 1) {
    t->terrain = Terrain::kFlat;
  } else if (w[0] == "slope" && (w.size() == 2 || w.size() == 3)) {
    t->terrain = Terrain::kSlope;
    t->slope = parse_angle(w[1]);
    t->slope_azimuth = w.size() == 3 ? parse_angle(w[2]) : 0;
    if (!(t->slope >= 0 && t->slope <= 15 * common::kPi / 180 + 1e-12)) {
      throw UsageError("slope must lie in [0, 15 deg]");
    }
  } else if (w[0] == "rolling" && w.size() <= 3) {
    t->terrain = Terrain::kRolling;
    if (w.size() >= 2) t->rolling_amplitude = parse_length(w[1]);
    if (w.size() == 3) t->rolling_wavelength = parse_length(w[2]);
    if (!(t->rolling_amplitude >= 0 && t->rolling_amplitude <= 2 + 1e-12)) {
      throw UsageError("rolling amplitude must lie in [0, 2 m]");
    }
    if (!(t->rolling_wavelength >= 5 && t->rolling_wavelength <= 200)) {
      throw UsageError("rolling wavelength must lie in [5 m, 200 m]");
    }
  } else {
    throw UsageError(
        "expected 'terrain = flat', 'slope ANGLE [AZIMUTH]' or 'rolling "
        "[AMPLITUDE [WAVELENGTH]]'");
  }
}

// vehicle = MODEL X Y HEADING [units=mm|cm|m] [up=z|y]
void add_vehicle(TileRecipe* t, const std::vector<std::string>& w, int line) {
  using common::parse_angle;
  using common::parse_length;
  need(w, 4, 6, "vehicle = MODEL X Y HEADING [units=mm|cm|m] [up=z|y]");
  VehicleSpec v;
  v.model = w[0];
  v.x = parse_length(w[1]);
  v.y = parse_length(w[2]);
  v.heading = parse_angle(w[3]);
  for (std::size_t i = 4; i < w.size(); ++i) {
    if (w[i] == "units=mm")
      v.import.scale = 1e-3;
    else if (w[i] == "units=cm")
      v.import.scale = 1e-2;
    else if (w[i] == "units=m")
      v.import.scale = 1;
    else if (w[i] == "up=y")
      v.import.z_up = false;
    else if (w[i] == "up=z")
      v.import.z_up = true;
    else
      throw UsageError("unknown vehicle option '" + w[i] + "' (units=mm|cm|m, up=z|y)");
  }
  v.line = line;
  if (t->vehicles.size() >= 200) throw UsageError("more than 200 vehicles");
  t->vehicles.push_back(v);
}

// looks = ELEVATION[/AZIMUTH] ...
void apply_looks(TileRecipe* t, const std::vector<std::string>& w) {
  using common::parse_angle;
  if (w.size() > 16) throw UsageError("at most 16 looks");
  t->looks.clear();
  for (const auto& s : w) {
    const auto slash = s.find('/');
    Look l;
    l.elevation = parse_angle(s.substr(0, slash));
    l.azimuth = slash == std::string::npos ? 0 : parse_angle(s.substr(slash + 1));
    if (!(l.elevation >= 30 * common::kPi / 180 - 1e-12 && l.elevation <= common::kPi / 2 + 1e-12)) {
      throw UsageError("look elevation must lie in [30 deg, 90 deg]");
    }
    t->looks.push_back(l);
  }
}

// The ground and the vegetation: extent, terrain, trees, bushes, hide, conifer_share, tree,
// canopy_disc.
bool apply_ground_key(TileRecipe* t, const std::string& key, const std::vector<std::string>& w, int line) {
  using common::parse_length;
  if (key == "extent") {
    need(w, 1, 2, "extent = X [Y]");
    t->extent_x = parse_length(w[0]);
    t->extent_y = w.size() == 2 ? parse_length(w[1]) : t->extent_x;
    for (double e : {t->extent_x, t->extent_y}) {
      if (!(e >= 5 && e <= 100)) throw UsageError("extent must lie in [5 m, 100 m]");
    }
  } else if (key == "terrain") {
    apply_terrain(t, w);
  } else if (key == "trees" || key == "bushes") {
    need(w, 1, 1, key + " = PER_HECTARE");
    const double v = number(w[0]);
    const double max = key == "trees" ? 2000 : 5000;
    if (!(v >= 0 && v <= max)) {
      throw UsageError(key + " per hectare must lie in [0, " + std::to_string(int(max)) + "]");
    }
    (key == "trees" ? t->trees_per_ha : t->bushes_per_ha) = v;
  } else if (key == "hide") {
    need(w, 1, 1, "hide = TREES_PER_VEHICLE");
    t->hide = count(w[0], 8);
  } else if (key == "conifer_share") {
    need(w, 1, 1, "conifer_share = FRACTION");
    t->conifer_share = number(w[0]);
    if (!(t->conifer_share >= 0 && t->conifer_share <= 1)) {
      throw UsageError("conifer_share must lie in [0, 1]");
    }
  } else if (key == "tree") {
    need(w, 3, 4, "tree = broadleaf|conifer X Y [HEIGHT]");
    if (w[0] != "broadleaf" && w[0] != "conifer") throw UsageError("tree kind must be broadleaf or conifer");
    TreeSpec s;
    s.conifer = w[0] == "conifer";
    s.x = parse_length(w[1]);
    s.y = parse_length(w[2]);
    s.height = w.size() == 4 ? parse_length(w[3]) : 16;
    if (!(s.height >= 4 && s.height <= 30)) throw UsageError("tree height must lie in [4 m, 30 m]");
    s.line = line;
    if (t->trees.size() >= 10000) throw UsageError("more than 10000 'tree' lines");
    t->trees.push_back(s);
  } else if (key == "canopy_disc") {
    need(w, 4, 4, "canopy_disc = X Y Z RADIUS");
    CanopyDisc d;
    d.centre = {parse_length(w[0]), parse_length(w[1]), parse_length(w[2])};
    d.radius = parse_length(w[3]);
    if (!(d.radius > 0 && d.radius <= 50)) throw UsageError("disc radius must lie in (0, 50 m]");
    if (t->discs.size() >= 10000) throw UsageError("more than 10000 'canopy_disc' lines");
    t->discs.push_back(d);
  } else {
    return false;
  }
  return true;
}

// What stands on the ground: vehicle, vehicles, object, clutter.
bool apply_object_key(TileRecipe* t, const std::string& key, const std::vector<std::string>& w, int line) {
  using common::parse_angle;
  using common::parse_length;
  if (key == "vehicle") {
    add_vehicle(t, w, line);
  } else if (key == "vehicles") {
    if (w.size() != 4 || w[0] != "random" || w[2] != "from") {
      throw UsageError("expected 'vehicles = random N from MODEL,MODEL,...'");
    }
    t->random_vehicles = count(w[1], 200);
    t->random_models.clear();
    std::string m;
    for (char c : w[3] + ",") {
      if (c != ',') {
        m += c;
      } else if (!m.empty()) {
        t->random_models.push_back(m);
        m.clear();
      }
    }
    if (t->random_models.empty()) throw UsageError("no model after 'from'");
    t->random_line = line;
  } else if (key == "object") {
    need(w, 4, 4, "object = KIND X Y HEADING");
    if (!is_kind(w[0])) throw UsageError("unknown clutter kind '" + w[0] + "' (" + kinds() + ")");
    ObjectSpec o;
    o.kind = w[0];
    o.x = parse_length(w[1]);
    o.y = parse_length(w[2]);
    o.heading = parse_angle(w[3]);
    o.line = line;
    if (t->objects.size() >= 1000) throw UsageError("more than 1000 objects");
    t->objects.push_back(o);
  } else if (key == "clutter") {
    if (w.size() % 2 != 0) throw UsageError("expected 'clutter = KIND COUNT [KIND COUNT ...]'");
    for (std::size_t i = 0; i < w.size(); i += 2) {
      if (!is_kind(w[i])) throw UsageError("unknown clutter kind '" + w[i] + "' (" + kinds() + ")");
      t->clutter.emplace_back(w[i], count(w[i + 1], 200));
      t->clutter_lines.push_back(line);
    }
  } else {
    return false;
  }
  return true;
}

// The flight and the output: flight_lines, headings, looks, altitude, spacing, canopy_spacing,
// swath_overlap, origin.
bool apply_flight_key(TileRecipe* t, const std::string& key, const std::vector<std::string>& w, int) {
  using common::parse_angle;
  using common::parse_length;
  if (key == "flight_lines") {
    need(w, 1, 1, "flight_lines = COUNT");
    t->flight_lines = count(w[0], 50);
    if (t->flight_lines < 1) throw UsageError("flight_lines must be >= 1");
  } else if (key == "headings") {
    if (w.size() > 16) throw UsageError("at most 16 headings");
    t->headings.clear();
    for (const auto& s : w) t->headings.push_back(parse_angle(s));
  } else if (key == "looks") {
    apply_looks(t, w);
  } else if (key == "altitude") {
    need(w, 1, 1, "altitude = LENGTH");
    t->altitude = parse_length(w[0]);
    if (!(t->altitude >= 60 && t->altitude <= 5000)) throw UsageError("altitude must lie in [60 m, 5000 m]");
  } else if (key == "spacing" || key == "canopy_spacing") {
    need(w, 1, 1, key + " = LENGTH");
    const double s = parse_length(w[0]);
    if (!(s >= 0.005 && s <= 2)) throw UsageError(key + " must lie in [5 mm, 2 m]");
    (key == "spacing" ? t->spacing : t->canopy_spacing) = s;
  } else if (key == "swath_overlap") {
    need(w, 1, 1, "swath_overlap = FRACTION");
    t->swath_overlap = number(w[0]);
    if (!(t->swath_overlap >= 0 && t->swath_overlap <= 2))
      throw UsageError("swath_overlap must lie in [0, 2]");
  } else if (key == "swath_offset") {
    need(w, 1, 1, "swath_offset = LENGTH");
    t->swath_offset = parse_length(w[0]);
    if (!(std::abs(t->swath_offset) <= 5000)) throw UsageError("swath_offset must lie in [-5000 m, 5000 m]");
  } else if (key == "origin") {
    need(w, 2, 3, "origin = EASTING NORTHING [HEIGHT]");
    t->has_origin = true;
    t->origin = {number(w[0]), number(w[1]), w.size() == 3 ? number(w[2]) : 0.0};
    if (t->origin.cwiseAbs().maxCoeff() > 1e8) throw UsageError("origin coordinates beyond 1e8 m");
  } else {
    return false;
  }
  return true;
}

}  // namespace

bool is_tile_key(const std::string& key) {
  return tile_keys().count(key) > 0 || key == "sensor" || key.rfind("sensor.", 0) == 0;
}

bool is_repeatable_key(const std::string& key) {
  return key == "tree" || key == "canopy_disc" || key == "vehicle" || key == "object" || key == "clutter" ||
         key == "views" || key == "view";
}

void apply_tile_key(TileRecipe* t, const std::string& key, const std::vector<std::string>& w, int line) {
  if (key == "sensor") {
    need(w, 1, 1, "sensor = PRESET");
    t->sensor_name = w[0];
    t->sensor_line = line;
    t->lines.emplace(key, line);
    return;
  }
  if (key.rfind("sensor.", 0) == 0) {
    const std::string k = key.substr(7);
    if (!is_sensor_key(k)) throw UsageError("unknown sensor key '" + k + "' (share/sensors/README.md)");
    Sensor probe;
    apply_sensor_key(&probe, k, w);  // the value's own bounds now, naming this line
    t->sensor_lines.push_back({k, w, line});
    t->lines.emplace(key, line);
    return;
  }
  if (!apply_ground_key(t, key, w, line) && !apply_object_key(t, key, w, line) &&
      !apply_flight_key(t, key, w, line)) {
    throw UsageError("unknown key '" + key + "'");
  }
  if (!is_repeatable_key(key)) t->lines.emplace(key, line);
}

void resolve_sensor(TileRecipe* t, const std::string& name) {
  const auto at = [&](int line) { return "line " + std::to_string(line) + ": "; };
  if (t->sensor_name.empty() && t->sensor_lines.empty()) {
    const auto it = t->lines.find("swath_offset");
    if (it != t->lines.end())
      throw common::DataError(name, at(it->second) +
                                        "'swath_offset' places the tile in a sensor's swath: it needs "
                                        "'sensor = NAME' or sensor.KEY lines");
    return;
  }
  for (const char* k : {"looks", "spacing", "swath_overlap", "flight_lines", "altitude"}) {
    const auto it = t->lines.find(k);
    if (it != t->lines.end()) {
      throw common::DataError(name, at(it->second) + "'" + k +
                                        "' sets the image scan; with a sensor the flight is planned from the "
                                        "sensor's keys (sensor.altitude, sensor.sidelap, ...)");
    }
  }
  Sensor s;
  if (!t->sensor_name.empty()) {
    try {
      s = load_sensor_preset(t->sensor_name);
    } catch (const UsageError& e) { throw common::DataError(name, at(t->sensor_line) + e.what()); }
  }
  for (const auto& l : t->sensor_lines) {
    try {
      apply_sensor_key(&s, l.key, l.words);
    } catch (const UsageError& e) { throw common::DataError(name, at(l.line) + e.what()); }
  }
  try {
    check_sensor(s);
  } catch (const UsageError& e) {
    throw common::DataError(
        name, at(t->sensor_lines.empty() ? t->sensor_line : t->sensor_lines.back().line) + e.what());
  }
  if (std::abs(t->swath_offset) > s.altitude * std::tan(s.scan_angle)) {
    throw common::DataError(name, at(t->lines.at("swath_offset")) + "swath_offset " +
                                      common::format_length(t->swath_offset) +
                                      " lies beyond the half swath (" +
                                      common::format_length(s.altitude * std::tan(s.scan_angle)) + ")");
  }
  // One flight direction unless the recipe gives headings (the image mode's default is two).
  if (!t->lines.count("headings")) t->headings = {0};
  t->sensor = s;
}

void check_tile(const TileRecipe& t, const std::string& name) {
  if (t.headings.empty()) throw common::DataError(name, "'headings' is empty");
  if (t.looks.empty()) throw common::DataError(name, "'looks' is empty");
  const auto check_xy = [&](double x, double y, int line, const std::string& what) {
    if (!(x >= 0 && x <= t.extent_x && y >= 0 && y <= t.extent_y)) {
      throw common::DataError(name, "line " + std::to_string(line) + ": " + what +
                                        " lies outside the tile [0, " + common::format_length(t.extent_x) +
                                        "] x [0, " + common::format_length(t.extent_y) + "]");
    }
  };
  for (const auto& v : t.vehicles) check_xy(v.x, v.y, v.line, "vehicle '" + v.model + "'");
  for (const auto& o : t.objects) check_xy(o.x, o.y, o.line, "object '" + o.kind + "'");
  for (const auto& s : t.trees) check_xy(s.x, s.y, s.line, "tree");
  // The images' size before anything is built or rendered: those of the flat tile with nothing
  // on it, which the real terrain and trees can only enlarge (their height range adds to an
  // oblique image's height). run_tile checks the real tile again.
  std::vector<TileView> views = t.sensor ? plan_sensor(t, {}, 0, 0, name).views : tile_views(t, 0, 0);
  views.insert(views.begin(), canopy_view(t, 0, 0));
  check_tile_budget(views, t, name);
}

}  // namespace canopy::sim
