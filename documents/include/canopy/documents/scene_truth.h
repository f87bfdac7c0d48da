// A tile's ground truth: truth.json, format "canopy.scene_truth", version 1 (formats/README.md
// "Scene truth"): rangetrace writes it for a rendered tile (write_scene_truth), hand labels of a
// real tile (share/real/*.truth.json) are written in it; score, topview and report read it here.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

inline constexpr const char* kSceneTruthFormat = "canopy.scene_truth";
inline constexpr int kSceneTruthVersion = 1;

// A pose in tile coordinates: x y (m) always; z (m) and heading (degrees) when given.
struct TruthPose {
  double x = 0, y = 0;
  std::optional<double> z, heading;
};

struct TrueVehicle {
  std::int64_t instance = 0;                     // unique in the document
  std::string model, cls;                        // "model" and "class" ("" when null or absent)
  std::string visibility;                        // hand labels: clear, partial, ... ("" when absent)
  std::optional<TruthPose> pose;                 // bottom centre of the bounding box
  std::optional<double> canopy_cover;            // in [0, 1]
  std::vector<std::array<double, 2>> footprint;  // 3 to 64 corners; empty when absent
};

// An object the labeller could not decide (hand labels): its centre.
struct UncertainObject {
  double x = 0, y = 0;
};

// A clutter object of a rendered tile ("clutter": kind and box; issue 29's false alarms by
// kind): its centre x y, its box's length and width (along and across its heading, degrees).
struct TrueClutter {
  std::string kind;
  double x = 0, y = 0, length = 0, width = 0, heading = 0;
};

struct SceneTruth {
  std::optional<std::array<double, 2>> extent;  // X Y (m), both > 0
  std::vector<TrueVehicle> vehicles;
  std::vector<UncertainObject> uncertain;
  std::vector<TrueClutter> clutter;  // empty when absent (hand labels)
  // A sensor-mode render's measured density ("density": pulses_per_m2, returns_per_m2; rangetrace,
  // docs/decisions/sensor.md "Output"); absent for image-mode renders and hand labels.
  std::optional<double> pulses_per_m2, returns_per_m2;
};

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1, "vehicles" missing or not an array, a vehicle
// without an integer instance >= 0 or with one that repeats, a pose without finite x and y, a
// canopy_cover outside [0, 1], a footprint not 3 to 64 [x, y] corners, an extent that is not
// two positive numbers, an uncertain object without a pose, a "density" that is not an object
// or whose pulses_per_m2 / returns_per_m2 is not a number >= 0, a clutter object without a kind or
// a box (finite centre and heading, size of three numbers >= 0), any member of another type.
SceneTruth read_scene_truth(const std::string& text, const std::string& name);
SceneTruth read_scene_truth_file(const std::string& path);

// --- The truth of a rendered tile as rangetrace writes it: every member (positions in tile
// coordinates with the origin added, angles in degrees; the reader above reads the ones the
// tools use).
using Point3 = std::array<double, 3>;

struct RenderedVehicle {
  std::int64_t instance = 0;
  std::string model;
  std::string cls;  // "class": procedural family instances only ("" = not written)
  std::int64_t line = 0;
  double x = 0, y = 0, z = 0, heading = 0, pitch = 0, roll = 0;  // "pose"
  Point3 size{};
  std::vector<std::array<double, 2>> footprint;
  double canopy_cover = 0;
};

struct RenderedClutter {
  std::string kind;
  Point3 centre{}, size{};
  double heading = 0, pitch = 0, roll = 0;
};

struct RenderedImage {
  std::int64_t view_idx = 0;
  double heading = 0;
  std::int64_t flight_line = 0;
  double elevation = 0, azimuth = 0;
  Point3 toward_sensor{};
  double swath_area = 0;
};

struct RenderedFlightLine {
  std::int64_t point_source_id = 0;
  double heading = 0, offset = 0;
  Point3 start{}, end{};
  double t0 = 0, t1 = 0;  // "gps_time"
};

// Sensor mode: the sensor's keys, the flight lines and the measured density.
struct RenderedSensor {
  std::string preset;  // "" = null
  std::vector<std::pair<std::string, std::string>> keys;
  std::vector<RenderedFlightLine> flight_lines;
  double returns_per_m2 = 0, first_returns_per_m2 = 0, pulses_per_m2 = 0;
  std::vector<std::int64_t> pulses_by_returns;
};

struct RenderedTruth {
  std::string scene;
  double extent_x = 0, extent_y = 0;
  std::optional<Point3> origin;  // null when the recipe gives none
  std::string terrain, angles;
  std::vector<RenderedVehicle> vehicles;
  std::vector<RenderedClutter> clutter;
  std::int64_t broadleaf = 0, conifer = 0, bushes = 0, discs = 0;  // "vegetation"
  double canopy_cover = 0, canopy_spacing = 0;
  std::optional<RenderedSensor> sensor;  // sensor mode: sensor, flight_lines, density
  std::vector<RenderedImage> images;     // otherwise: the images in view_idx order
};

// The text rangetrace writes (two spaces indent, a final newline).
std::string write_scene_truth(const RenderedTruth& truth, const formats::Provenance& provenance);

}  // namespace canopy::documents
