// Tile placement: the vehicles (given, then random), the clutter, the trees and bushes on the
// terrain, without overlaps and inside the tile (build_tile, tile.h).
#include <algorithm>
#include <cmath>
#include <map>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "canopy/common/units.h"
#include "canopy/sim/povray_run.h"
#include "canopy/sim/families.h"
#include "canopy/sim/tile.h"

namespace canopy::sim {

using common::DataError;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

using Quad = std::array<Vector2d, 4>;

// Top-view rectangle (heading-aligned) bounding the posed box [lo, hi] (local, anchor at 0).
Quad footprint_of(const Posed& pose, const Vector3d& lo, const Vector3d& hi) {
  const Vector2d f(std::cos(pose.heading), std::sin(pose.heading)), l(-f.y(), f.x());
  double a0 = 1e18, a1 = -1e18, b0 = 1e18, b1 = -1e18;
  for (int i = 0; i < 8; ++i) {
    const Vector3d c(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
    const Vector3d w = pose.anchor + pose.r * c;
    const Vector2d d = w.head<2>() - pose.anchor.head<2>();
    a0 = std::min(a0, d.dot(f));
    a1 = std::max(a1, d.dot(f));
    b0 = std::min(b0, d.dot(l));
    b1 = std::max(b1, d.dot(l));
  }
  const Vector2d o = pose.anchor.head<2>();
  return {o + a0 * f + b0 * l, o + a1 * f + b0 * l, o + a1 * f + b1 * l, o + a0 * f + b1 * l};
}

// Separating-axis test of two convex quads, each grown by `gap` / 2.
bool overlap(const Quad& a, const Quad& b, double gap) {
  for (const Quad* q : {&a, &b}) {
    for (int e = 0; e < 4; ++e) {
      const Vector2d d = (*q)[(e + 1) % 4] - (*q)[e];
      const Vector2d axis = Vector2d(-d.y(), d.x()).normalized();
      double amin = 1e18, amax = -1e18, bmin = 1e18, bmax = -1e18;
      for (const auto& p : a) {
        amin = std::min(amin, p.dot(axis));
        amax = std::max(amax, p.dot(axis));
      }
      for (const auto& p : b) {
        bmin = std::min(bmin, p.dot(axis));
        bmax = std::max(bmax, p.dot(axis));
      }
      if (amax + gap <= bmin || bmax + gap <= amin) return false;
    }
  }
  return true;
}

bool inside_tile(const Quad& q, const TileRecipe& t, double margin) {
  for (const auto& p : q) {
    if (p.x() < margin || p.y() < margin || p.x() > t.extent_x - margin || p.y() > t.extent_y - margin) {
      return false;
    }
  }
  return true;
}

double distance_to_quad(const Vector2d& p, const Quad& q) {
  if (in_polygon(p, q)) return 0;
  double best = 1e18;
  for (int e = 0; e < 4; ++e) {
    const Vector2d a = q[e], b = q[(e + 1) % 4];
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - p).norm());
  }
  return best;
}

std::string where(double x, double y) {
  return "(" + common::format_length(x) + ", " + common::format_length(y) + ")";
}

}  // namespace

bool in_polygon(const Vector2d& p, const std::array<Vector2d, 4>& poly) {
  // Convex, counter-clockwise: inside when left of (or on) every edge.
  for (int e = 0; e < 4; ++e) {
    const Vector2d a = poly[e], b = poly[(e + 1) % 4];
    if ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x() < 0) return false;
  }
  return true;
}

namespace {

// Builds a tile phase by phase: the models, the vehicles (given, then random), the clutter
// (given, then random), the trees (templates, given, concealment, random), the bushes, the top.
// Every random phase draws from its own derived seed, in the order written.
class TileBuilder {
 public:
  TileBuilder(const TileRecipe& recipe, const std::string& name, std::uint64_t seed, const std::string& povray)
      : recipe_(recipe),
        name_(name),
        seed_(seed),
        povray_(povray),
        terrain_(recipe, seed),
        trng_(common::derive_seed(seed, "trees")) {
    tile_.recipe = recipe;
    tile_.name = name;
    tile_.seed = seed;
  }

  Tile build() {
    load_models();
    place_given_vehicles();
    place_random_vehicles();
    place_clutter();
    plant_trees();
    plant_bushes();
    tile_.top = top();
    return std::move(tile_);
  }

 private:
  // Models: distinct (spec, units, up), in first-use order; files resolved against the recipe.
  void load_models();
  PlacedVehicle place_vehicle(int model, double x, double y, double heading, int line) const;
  void place_given_vehicles();
  void place_random_vehicles();
  std::pair<PlacedObject, Quad> make_object(const std::string& kind, double x, double y, double heading);
  void place_clutter();
  bool place_random_clutter(std::uint64_t stream, std::size_t& failed);
  void plant_trees();
  bool place_random_tree(const Vector2d& p, bool inside);
  void plant_bushes();
  double top() const;

  const TileRecipe& recipe_;
  const std::string& name_;
  const std::uint64_t seed_;
  const std::string& povray_;
  const TerrainModel terrain_;
  Tile tile_;
  std::vector<int> use_model_;  // per vehicle line, then per random model: index into tile_.models
  std::vector<Quad> taken_;     // footprints of vehicles and clutter
  common::Rng trng_;            // trees
  std::vector<Vector2d> trunks_;
};

void TileBuilder::load_models() {
  struct Use {
    std::string spec;
    MeshImport import;
    int line;
  };
  std::vector<Use> uses;
  for (const auto& v : recipe_.vehicles) uses.push_back({v.model, v.import, v.line});
  for (const auto& m : recipe_.random_models) uses.push_back({m, MeshImport{}, recipe_.random_line});
  std::vector<std::string> keys;
  use_model_.assign(uses.size(), 0);
  for (std::size_t u = 0; u < uses.size(); ++u) {
    const std::string key =
        uses[u].spec + "|" + std::to_string(uses[u].import.scale) + "|" + (uses[u].import.z_up ? "z" : "y");
    const auto it = std::find(keys.begin(), keys.end(), key);
    if (it != keys.end()) {
      use_model_[u] = static_cast<int>(it - keys.begin());
      continue;
    }
    bool builtin = false;
    for (const char* b : kBuiltinModels) builtin = builtin || uses[u].spec == b;
    builtin = builtin || is_family_spec(uses[u].spec);  // family:<class>:<n> (families.h)
    std::string path = uses[u].spec;
    if (!builtin && !path.empty() && path[0] != '/') path = recipe_.dir + path;
    try {
      tile_.models.push_back(load_model(path, uses[u].import));
    } catch (const common::Error& e) {
      throw DataError(name_, "line " + std::to_string(uses[u].line) + ": vehicle model '" + uses[u].spec +
                                 "': " + e.what());
    }
    keys.push_back(key);
    use_model_[u] = static_cast<int>(tile_.models.size() - 1);
  }
  if (!tile_.models.empty()) {
    TempDir tmp;
    tile_.model_bounds = models_extent(tile_.models, povray_, tmp);
    for (std::size_t m = 0; m < tile_.models.size(); ++m) {
      warn_model_size(tile_.models[m], tile_.model_bounds[m].second - tile_.model_bounds[m].first, nullptr);
    }
  }
}

PlacedVehicle TileBuilder::place_vehicle(int model, double x, double y, double heading, int line) const {
  const auto& [lo, hi] = tile_.model_bounds[model];
  const Vector3d size = hi - lo;
  PlacedVehicle v;
  v.instance = static_cast<int>(tile_.vehicles.size()) + 1;
  v.model_name = tile_.models[model].name;
  v.model_index = model;
  v.size = size;
  v.model_lo = lo;
  v.line = line;
  v.pose = stand_on(terrain_, x, y, heading, size.x() / 2, size.y() / 2);
  const Vector3d half(size.x() / 2, size.y() / 2, 0);
  v.footprint = footprint_of(v.pose, -half, half + Vector3d(0, 0, size.z()));
  return v;
}

void TileBuilder::place_given_vehicles() {
  for (std::size_t k = 0; k < recipe_.vehicles.size(); ++k) {
    const auto& s = recipe_.vehicles[k];
    PlacedVehicle v = place_vehicle(use_model_[k], s.x, s.y, s.heading, s.line);
    if (!inside_tile(v.footprint, recipe_, 0)) {
      throw DataError(name_, "line " + std::to_string(s.line) + ": vehicle '" + s.model + "' at " +
                                 where(s.x, s.y) + " reaches outside the tile");
    }
    for (const auto& o : tile_.vehicles) {
      if (overlap(v.footprint, o.footprint, 0)) {
        throw DataError(name_, "line " + std::to_string(s.line) + ": vehicle '" + s.model + "' at " +
                                   where(s.x, s.y) + " overlaps the vehicle of line " + std::to_string(o.line));
      }
    }
    tile_.vehicles.push_back(v);
    taken_.push_back(v.footprint);
  }
}

void TileBuilder::place_random_vehicles() {
  common::Rng rng(common::derive_seed(seed_, "vehicles"));
  const int first_random = static_cast<int>(recipe_.vehicles.size());
  for (int k = 0; k < recipe_.random_vehicles; ++k) {
    bool placed = false;
    for (int attempt = 0; attempt < 2000 && !placed; ++attempt) {
      const int model = use_model_[first_random + rng.below(recipe_.random_models.size())];
      const double x = rng.uniform(0, recipe_.extent_x), y = rng.uniform(0, recipe_.extent_y);
      const double heading = rng.uniform(0, 2 * common::kPi);
      PlacedVehicle v = place_vehicle(model, x, y, heading, recipe_.random_line);
      if (!inside_tile(v.footprint, recipe_, 1.0)) continue;
      bool clear = true;
      for (const auto& o : tile_.vehicles) clear = clear && !overlap(v.footprint, o.footprint, 2.0);
      if (!clear) continue;
      tile_.vehicles.push_back(v);
      taken_.push_back(v.footprint);
      placed = true;
    }
    if (!placed) {
      throw DataError(name_, "line " + std::to_string(recipe_.random_line) + ": cannot place " +
                                 std::to_string(recipe_.random_vehicles) +
                                 " vehicles without overlap in the tile (placed " + std::to_string(k) + ")");
    }
  }
}

// Each object its own mesh (boulders differ), appended to tile_.object_meshes.
std::pair<PlacedObject, Quad> TileBuilder::make_object(const std::string& kind, double x, double y,
                                                       double heading) {
  PlacedObject o;
  o.kind = kind;
  tile_.object_meshes.push_back(
      clutter_mesh(kind, common::derive_seed(seed_, "clutter-" + std::to_string(tile_.objects.size()))));
  o.template_index = static_cast<int>(tile_.object_meshes.size() - 1);
  Vector3d lo = Vector3d::Constant(1e18), hi = Vector3d::Constant(-1e18);
  for (const auto& p : tile_.object_meshes.back().v) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  o.size = hi - lo;
  o.lo = lo;
  o.pose = stand_on(terrain_, x, y, heading, std::max(std::abs(lo.x()), hi.x()),
                    std::max(std::abs(lo.y()), hi.y()));
  return std::make_pair(o, footprint_of(o.pose, lo, hi));
}

// Random poses tried per clutter object before "no room" (raised from 500 for issue 29's crowded
// tiles: a tile placed within 500 tries is placed exactly as before).
constexpr int kClutterAttempts = 5000;
// When one object finds no room, the random clutter is placed again from the start with the next
// round's stream: the objects placed first can fence the last one out (seeds 117 and 118 of the
// scene recipe's light cover: a tent, a caravan). A tile placed in round 0 is placed exactly as
// before; later rounds have their own derived streams, so the same seed still gives the same tile.
constexpr int kClutterRounds = 8;

// Clutter: hand-placed, then random per kind.
void TileBuilder::place_clutter() {
  for (const auto& s : recipe_.objects) {
    auto [o, q] = make_object(s.kind, s.x, s.y, s.heading);
    tile_.objects.push_back(o);
    taken_.push_back(q);
  }
  const std::size_t n_objects = tile_.objects.size(), n_taken = taken_.size(),
                    n_meshes = tile_.object_meshes.size();
  std::size_t failed = 0;  // the clutter line that found no room in the last round
  for (int round = 0; round < kClutterRounds; ++round) {
    tile_.objects.resize(n_objects);
    taken_.resize(n_taken);
    tile_.object_meshes.resize(n_meshes);
    if (place_random_clutter(round == 0 ? common::derive_seed(seed_, "clutter")
                                        : common::derive_seed(seed_, "clutter-round-" + std::to_string(round)),
                             failed))
      return;
  }
  const auto& [kind, n] = recipe_.clutter[failed];
  throw DataError(name_, "line " + std::to_string(recipe_.clutter_lines[failed]) + ": no room for " +
                             std::to_string(n) + " " + kind + " objects in the tile (" +
                             std::to_string(kClutterRounds) + " placements of the random clutter tried)");
}

// One round of the random clutter, every kind in the recipe's order; false (and the line that
// found no room in `failed`) when an object cannot be placed.
bool TileBuilder::place_random_clutter(std::uint64_t stream, std::size_t& failed) {
  common::Rng rng(stream);
  for (std::size_t c = 0; c < recipe_.clutter.size(); ++c) {
    const auto& [kind, n] = recipe_.clutter[c];
    for (int k = 0; k < n; ++k) {
      bool placed = false;
      for (int attempt = 0; attempt < kClutterAttempts && !placed; ++attempt) {
        const double x = rng.uniform(0, recipe_.extent_x), y = rng.uniform(0, recipe_.extent_y);
        const double heading = rng.uniform(0, 2 * common::kPi);
        auto [o, q] = make_object(kind, x, y, heading);
        bool clear = inside_tile(q, recipe_, 0.5);
        for (const auto& t : taken_) clear = clear && !overlap(q, t, 1.5);
        if (!clear) {
          tile_.object_meshes.pop_back();
          continue;
        }
        tile_.objects.push_back(o);
        taken_.push_back(q);
        placed = true;
      }
      if (!placed) {
        failed = c;
        return false;
      }
    }
  }
  return true;
}

// Trees: four broadleaf and four conifer templates, three bushes; instances rotated and
// scaled by +-15%. Trunks keep 0.6 m from vehicles and clutter, 1.5 m from each other.
void TileBuilder::plant_trees() {
  const std::uint64_t tseed = common::derive_seed(seed_, "tree-templates");
  for (int k = 0; k < 4; ++k)
    tile_.tree_meshes.push_back(broadleaf_template(common::derive_seed(tseed, "b" + std::to_string(k)), 17));
  for (int k = 0; k < 4; ++k)
    tile_.tree_meshes.push_back(conifer_template(common::derive_seed(tseed, "c" + std::to_string(k)), 20));
  for (int k = 0; k < 3; ++k)
    tile_.tree_meshes.push_back(
        bush_template(common::derive_seed(tseed, "u" + std::to_string(k)), 0.7 + 0.25 * k));
  for (const auto& s : recipe_.trees) {
    PlacedTree t;
    t.conifer = s.conifer;
    t.template_index = (s.conifer ? 4 : 0) + static_cast<int>(trng_.below(4));
    t.base = Vector3d(s.x, s.y, terrain_.height(s.x, s.y));
    t.rotation = trng_.uniform(0, 2 * common::kPi);
    t.scale = s.height / (s.conifer ? 20.0 : 17.0);
    tile_.trees.push_back(t);
    trunks_.emplace_back(s.x, s.y);
  }
  // Concealment: `hide` trees beside each vehicle, trunks 0.6-2 m out from its long sides.
  const int hide = recipe_.hide >= 0 ? recipe_.hide : recipe_.trees_per_ha > 0 ? 2 : 0;
  for (const auto& v : tile_.vehicles) {
    const Vector2d f(std::cos(v.pose.heading), std::sin(v.pose.heading)), l(-f.y(), f.x());
    for (int k = 0; k < hide; ++k) {
      for (int attempt = 0; attempt < 50; ++attempt) {
        const double side = (k % 2 == 0) ? 1 : -1;
        const Vector2d p = v.pose.anchor.head<2>() + trng_.uniform(-0.45, 0.45) * v.size.x() * f +
                           side * (v.size.y() / 2 + trng_.uniform(0.6, 2.0)) * l;
        const bool inside = p.x() >= 0 && p.y() >= 0 && p.x() <= recipe_.extent_x && p.y() <= recipe_.extent_y;
        if (place_random_tree(p, inside)) break;
      }
    }
  }
  const double area_ha = recipe_.extent_x * recipe_.extent_y / 1e4;
  const int n_trees = static_cast<int>(std::lround(recipe_.trees_per_ha * area_ha));
  for (int k = 0; k < n_trees; ++k) {
    for (int attempt = 0; attempt < 50; ++attempt) {
      const Vector2d p(trng_.uniform(0, recipe_.extent_x), trng_.uniform(0, recipe_.extent_y));
      if (place_random_tree(p, true)) break;
    }
  }
}

// A random tree at trunk position p: its kind, variant, rotation and scale are drawn (always,
// so the draws do not depend on the outcome), then it is planted when p is `inside` the tile,
// 0.6 m clear of every taken footprint and 1.5 m from every trunk.
bool TileBuilder::place_random_tree(const Vector2d& p, bool inside) {
  const bool conifer = trng_.uniform() < recipe_.conifer_share;
  const int variant = static_cast<int>(trng_.below(4));
  const double rot = trng_.uniform(0, 2 * common::kPi), scale = trng_.uniform(0.85, 1.15);
  bool clear = inside;
  for (const auto& q : taken_) clear = clear && distance_to_quad(p, q) >= 0.6;
  for (const auto& q : trunks_) clear = clear && (q - p).norm() >= 1.5;
  if (!clear) return false;
  PlacedTree t;
  t.conifer = conifer;
  t.template_index = (conifer ? 4 : 0) + variant;
  t.base = Vector3d(p.x(), p.y(), terrain_.height(p.x(), p.y()));
  t.rotation = rot;
  t.scale = scale;
  tile_.trees.push_back(t);
  trunks_.push_back(p);
  return true;
}

void TileBuilder::plant_bushes() {
  common::Rng brng(common::derive_seed(seed_, "bushes"));
  const double area_ha = recipe_.extent_x * recipe_.extent_y / 1e4;
  const int n_bushes = static_cast<int>(std::lround(recipe_.bushes_per_ha * area_ha));
  for (int k = 0; k < n_bushes; ++k) {
    for (int attempt = 0; attempt < 50; ++attempt) {
      const Vector2d p(brng.uniform(0, recipe_.extent_x), brng.uniform(0, recipe_.extent_y));
      const int variant = static_cast<int>(brng.below(3));
      const double rot = brng.uniform(0, 2 * common::kPi), scale = brng.uniform(0.8, 1.2);
      const double reach = (0.7 + 0.25 * variant) * scale + 0.4;
      bool clear = true;
      for (const auto& q : taken_) clear = clear && distance_to_quad(p, q) >= reach;
      if (!clear) continue;
      PlacedTree t;
      t.bush = true;
      t.template_index = 8 + variant;
      t.base = Vector3d(p.x(), p.y(), terrain_.height(p.x(), p.y()));
      t.rotation = rot;
      t.scale = scale;
      tile_.trees.push_back(t);
      break;
    }
  }
}

// The highest point of anything (sets the image extents).
double TileBuilder::top() const {
  double top = terrain_.hi();
  for (const auto& v : tile_.vehicles) top = std::max(top, v.pose.anchor.z() + v.size.norm());
  for (const auto& o : tile_.objects) top = std::max(top, o.pose.anchor.z() + o.size.norm());
  for (const auto& t : tile_.trees) top = std::max(top, t.base.z() + (t.bush ? 3.0 : 21.0 * t.scale));
  for (const auto& d : recipe_.discs) top = std::max(top, d.centre.z());
  return top;
}

}  // namespace

Tile build_tile(const TileRecipe& recipe, const std::string& name, std::uint64_t seed,
                const std::string& povray) {
  return TileBuilder(recipe, name, seed, povray).build();
}

}  // namespace canopy::sim
