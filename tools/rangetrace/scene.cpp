// Scene recipes, camera views and seeded foliage (no I/O except load_scene).
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
#include "canopy/sim/sandbox.h"
#include "rangetrace/rangetrace.h"
#include "rangetrace/tile.h"

namespace canopy::rangetrace {

using common::DataError;

std::vector<View> circle_views(int count, double elevation) {
  std::vector<View> views;
  for (int k = 0; k < count; ++k) views.push_back({2 * common::kPi * k / count, elevation});
  return views;
}

std::vector<View> flyby_views(int per_pass, double elevation, double start_bearing) {
  // Camera ground tracks are the lines x = +1 (in front of the nose) and x = -1 (behind the
  // tail), in units of the track's distance from the vehicle; views are evenly spaced along
  // each line between bearings +-start off the long axis.
  std::vector<View> views;
  const double half = std::tan(start_bearing);
  for (int pass = 0; pass < 2; ++pass) {
    const double x = pass == 0 ? 1.0 : -1.0;
    for (int k = 0; k < per_pass; ++k) {
      const double t = per_pass == 1 ? 0.0 : 1.0 - 2.0 * k / (per_pass - 1);
      const double y = pass == 0 ? half * t : -half * t;
      views.push_back({std::atan2(y, x), elevation});
    }
  }
  return views;
}

std::vector<View> dodecahedron_views() {
  // Standard dodecahedron vertices, rotated so that the face with normal (0, phi, 1) points up
  // (+z), then about z so that the first upper vertex lies at azimuth 0.
  const double p = (1 + std::sqrt(5.0)) / 2, q = 1 / p;
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  for (int i = 0; i < 4; ++i) {
    const double a = i & 1 ? 1 : -1, b = i & 2 ? 1 : -1;
    v.emplace_back(0, a * q, b * p);
    v.emplace_back(a * q, b * p, 0);
    v.emplace_back(a * p, 0, b * q);
  }
  const Eigen::Vector3d up = Eigen::Vector3d(0, p, 1).normalized();
  const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<View> views;
  for (const auto& vertex : v) {
    const Eigen::Vector3d d = (r * vertex).normalized();
    if (d.z() > 1e-9) views.push_back({std::atan2(d.y(), d.x()), std::asin(d.z())});
  }
  // Deterministic order: upper ring first, then by azimuth; azimuths relative to the first.
  std::sort(views.begin(), views.end(), [](const View& a, const View& b) {
    if (std::abs(a.elevation - b.elevation) > 1e-6) return a.elevation > b.elevation;
    return a.azimuth < b.azimuth;
  });
  const double a0 = views.front().azimuth;
  for (auto& w : views) {
    w.azimuth = std::remainder(w.azimuth - a0, 2 * common::kPi);
    if (std::abs(w.azimuth) < 1e-12) w.azimuth = 0;
  }
  std::sort(views.begin(), views.end(), [](const View& a, const View& b) {
    if (std::abs(a.elevation - b.elevation) > 1e-6) return a.elevation > b.elevation;
    const double aa = a.azimuth < -1e-9 ? a.azimuth + 2 * common::kPi : a.azimuth;
    const double bb = b.azimuth < -1e-9 ? b.azimuth + 2 * common::kPi : b.azimuth;
    return aa < bb;
  });
  return views;
}

namespace {

// Throws the DataError "<name>: line <n>: <why>" of a recipe line (control bytes escaped).
struct LineError {
  const std::string& name;
  int line = 0;
  [[noreturn]] void operator()(const std::string& why) const {
    throw DataError(printable(name), "line " + std::to_string(line) + ": " + printable(why));
  }
};

// A count: decimal digits only (no sign, no "0x10", no trailing text); its value, saturated
// at 10^18, or -1 when `w` is not a count.
long long count_value(const std::string& w) {
  if (w.empty() || !std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; })) return -1;
  return w.size() > 18 ? 1000000000000000000LL : std::strtoll(w.c_str(), nullptr, 10);
}

// One single-vehicle key (foliage_*, views, view) with its value's words.
void apply_single_key(SceneRecipe* scene, const std::string& key, const std::vector<std::string>& words,
                      const LineError& fail) {
  auto number = [&](std::size_t i, int max) {
    if (i >= words.size()) fail("'" + key + "' needs more values");
    const long long n = count_value(words[i]);
    if (n < 1) fail("'" + words[i] + "' is not a count >= 1");
    if (n > max) fail("'" + key + "': " + words[i] + " exceeds the limit of " + std::to_string(max));
    return static_cast<int>(n);
  };
  auto angle = [&](std::size_t i) {
    if (i >= words.size()) fail("'" + key + "' needs more values");
    return common::parse_angle(words[i]);
  };
  if (key.rfind("foliage_", 0) == 0 && words.size() != 1) fail("expected '" + key + " = VALUE' (one value)");
  if (key == "foliage_count") {
    scene->foliage_count = count_value(words[0]) == 0 ? 0 : number(0, 100000);
  } else if (key == "foliage_radius") {
    scene->foliage_radius = common::parse_length(words[0]);
  } else if (key == "foliage_band") {
    scene->foliage_band = common::parse_length(words[0]);
  } else if (key == "foliage_square") {
    scene->foliage_square = common::parse_length(words[0]);
  } else if (key == "views") {
    std::vector<View> add;
    if (words[0] == "circle" && words.size() == 3) {
      add = circle_views(number(1, 1000), angle(2));
    } else if (words[0] == "flyby" && words.size() == 4) {
      add = flyby_views(number(1, 1000), angle(2), angle(3));
    } else if (words[0] == "dodecahedron" && words.size() == 1) {
      add = dodecahedron_views();
    } else {
      fail("views: expected 'circle N ELEV', 'flyby N ELEV START' or 'dodecahedron'");
    }
    if (scene->views.size() + add.size() > 10000) fail("more than 10000 views");
    scene->views.insert(scene->views.end(), add.begin(), add.end());
  } else if (key == "view") {
    if (scene->views.size() >= 10000) fail("more than 10000 views");
    if (words.size() != 2) fail("view: expected 'AZIMUTH ELEVATION'");
    scene->views.push_back({angle(0), angle(1)});
  } else {
    fail("unknown key '" + key + "'");
  }
}

// A single-vehicle recipe once read: views above the ground, at least one, foliage sizes.
void check_single(const SceneRecipe& scene, const std::string& name) {
  for (const auto& v : scene.views) {
    if (!(v.elevation > 0 && v.elevation < common::kPi / 2)) {
      throw DataError(name, "view elevation must lie strictly between 0 and 90 degrees");
    }
  }
  if (scene.views.empty()) throw DataError(name, "no views (add 'views = ...' lines)");
  if (!(scene.foliage_radius > 0) || !(scene.foliage_band >= 0) || !(scene.foliage_square > 0)) {
    throw DataError(name, "foliage radius and square must be > 0, band >= 0");
  }
}

// The recipe's kind is set by its first key: a tile key and a single-vehicle key never mix.
struct RecipeKind {
  int single_line = 0;  // first single-vehicle key (foliage_*, views, view)
  int tile_line = 0;    // first tile key
};

void apply_key(SceneRecipe* scene, RecipeKind* kind, const std::string& key,
               const std::vector<std::string>& words, const LineError& fail) {
  if (is_tile_key(key)) {
    if (!scene->tile) scene->tile = std::make_shared<TileRecipe>();
    if (kind->tile_line == 0) kind->tile_line = fail.line;
    if (kind->single_line != 0) {
      fail("'" + key + "' is a tile key, but line " + std::to_string(kind->single_line) +
           " holds a single-vehicle key (foliage_*, views, view): use one kind of recipe");
    }
    apply_tile_key(scene->tile.get(), key, words, fail.line);
    return;
  }
  if (key != "foliage_count" && key != "foliage_radius" && key != "foliage_band" && key != "foliage_square" &&
      key != "views" && key != "view") {
    fail("unknown key '" + key + "'");
  }
  if (kind->single_line == 0) kind->single_line = fail.line;
  if (kind->tile_line != 0) {
    fail("'" + key + "' is a single-vehicle key, but line " + std::to_string(kind->tile_line) +
         " made this a tile recipe");
  }
  apply_single_key(scene, key, words, fail);
}

}  // namespace

SceneRecipe parse_scene(const std::string& text, const std::string& name) {
  SceneRecipe scene;
  scene.name = name;
  formats::IniPolicy policy;  // '#' comments (anywhere), no sections, keys once but the repeatable
  policy.comments = "#";
  policy.repeatable = is_repeatable_key;
  policy.kind = "a recipe";
  LineError fail{name, 0};
  RecipeKind kind;
  for (const formats::IniEntry& e : formats::parse_ini(text, name, policy).entries) {
    fail.line = e.line;
    try {
      apply_key(&scene, &kind, e.key, formats::ini_words(e.value), fail);
    } catch (const common::UsageError& err) { fail(err.what()); } catch (const std::logic_error&) {
      fail("malformed value in '" + e.key + " = " + e.value + "'");
    }
  }
  if (scene.tile) {
    resolve_sensor(scene.tile.get(), name);
    check_tile(*scene.tile, name);
    return scene;
  }
  check_single(scene, name);
  return scene;
}

SceneRecipe load_scene(const std::string& name_or_path) {
  // A short name (no '/', no '.') is a recipe of share/scenes/ when one exists by that name:
  // the thesis scenes (circle, flyby, unoccluded) and tiles such as forest.
  std::string path = name_or_path;
  std::string name = name_or_path;
  if (!name_or_path.empty() && name_or_path.find_first_of("/.") == std::string::npos) {
    const std::string shared = common::share_dir() + "/scenes/" + name_or_path + ".scene";
    struct stat st {};
    if (::stat(shared.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
      path = shared;
    } else if (::stat(name_or_path.c_str(), &st) != 0) {
      throw common::UsageError("--scene '" + name_or_path + "': no such file, nor a recipe " +
                               common::share_dir() + "/scenes/" + name_or_path + ".scene");
    }
  }
  SceneRecipe s = parse_scene(common::read_file(path), path);
  if (path != name_or_path) s.name = name;
  if (s.tile) {
    const auto slash = path.find_last_of('/');
    s.tile->dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  }
  return s;
}

std::vector<Disc> make_foliage(const SceneRecipe& scene, const Pose& pose, double top, std::uint64_t seed) {
  common::Rng rng(common::derive_seed(seed, "foliage"));
  const double c = std::cos(pose.heading), s = std::sin(pose.heading);
  const double half = scene.foliage_square / 2;
  std::vector<Disc> discs;
  discs.reserve(static_cast<std::size_t>(scene.foliage_count));
  for (int i = 0; i < scene.foliage_count; ++i) {
    const double u = rng.uniform(-half, half), v = rng.uniform(-half, half);
    const double z = top + scene.foliage_band * rng.uniform();
    Eigen::Vector3d n;
    do { n = Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal()); } while (n.norm() < 1e-9);
    discs.push_back({Eigen::Vector3d(pose.position.x() + c * u - s * v, pose.position.y() + s * u + c * v, z),
                     n.normalized(), scene.foliage_radius});
  }
  return discs;
}

}  // namespace canopy::rangetrace
