// The unseen clutter kinds (issue 29): trailer, caravan, pipes, barriers, tent, rock. Each is a
// small generated mesh whose dimensions come from the object's seed; the bounds of each
// dimension are share/scenes/README.md's ("Clutter") and tests/rangetrace/test_clutter.cpp's.
#include "clutter_kinds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "canopy/common/math.h"

namespace canopy::sim {

using Eigen::Vector2d;
using Eigen::Vector3d;

TriMesh icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vector3d> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size() - 1);
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tri : f) {
      const int a = middle(tri[0], tri[1]), b = middle(tri[1], tri[2]), c = middle(tri[2], tri[0]);
      g.push_back({tri[0], a, c});
      g.push_back({tri[1], b, a});
      g.push_back({tri[2], c, b});
      g.push_back({a, b, c});
    }
    f = g;
  }
  TriMesh m;
  m.v = v;
  m.f = f;
  return m;
}

namespace {

// Rings of one convex cross-section (y, z) each at its x, joined in order, both ends capped.
void loft_x(TriMesh* m, const std::vector<std::pair<double, std::vector<Vector2d>>>& rings) {
  const int n = static_cast<int>(rings.front().second.size());
  const int base = static_cast<int>(m->v.size());
  for (const auto& [x, ring] : rings) {
    for (const Vector2d& p : ring) m->v.emplace_back(x, p.x(), p.y());
  }
  auto at = [&](std::size_t r, int k) { return base + static_cast<int>(r) * n + (k % n); };
  for (std::size_t r = 0; r + 1 < rings.size(); ++r) {
    for (int k = 0; k < n; ++k) {
      m->f.push_back({at(r, k), at(r, k + 1), at(r + 1, k + 1)});
      m->f.push_back({at(r, k), at(r + 1, k + 1), at(r + 1, k)});
    }
  }
  const std::size_t last = rings.size() - 1;
  for (int k = 1; k + 1 < n; ++k) {
    m->f.push_back({at(0, 0), at(0, k + 1), at(0, k)});
    m->f.push_back({at(last, 0), at(last, k), at(last, k + 1)});
  }
}

// A prism of the convex cross-section `profile` (y, z) from x0 to x1.
void prism_x(TriMesh* m, const std::vector<Vector2d>& profile, double x0, double x1) {
  loft_x(m, {{x0, profile}, {x1, profile}});
}

// A rectangle |y| <= hw, z in [z0, z1] with its top corners rounded by r and its bottom corners
// by rb (three segments each), counter-clockwise from the bottom right.
std::vector<Vector2d> rounded_section(double hw, double z0, double z1, double r, double rb) {
  std::vector<Vector2d> out;
  auto arc = [&](const Vector2d& c, double radius, double a0) {
    for (int k = 0; k <= 3; ++k) {
      const double a = a0 + common::kPi / 2 * k / 3;
      out.emplace_back(c.x() + radius * std::cos(a), c.y() + radius * std::sin(a));
    }
  };
  arc({hw - rb, z0 + rb}, rb, -common::kPi / 2);
  arc({hw - r, z1 - r}, r, 0);
  arc({-hw + r, z1 - r}, r, common::kPi / 2);
  arc({-hw + rb, z0 + rb}, rb, common::kPi);
  return out;
}

// One axle at x: two wheels of radius r and width 0.22 m inside |y| <= hw, and the axle.
void axle(TriMesh* m, double x, double hw, double r) {
  for (double s : {-1.0, 1.0}) m->limb({x, s * (hw - 0.24), r}, {x, s * (hw - 0.02), r}, r, r, 12);
  m->limb({x, -(hw - 0.24), r}, {x, hw - 0.24, r}, 0.04, 0.04, 6);
}

// A drawbar from the body's front (x = front, |y| = spread, height z) to a coupler whose tip is
// at x = tip, 0.38 - 0.5 m above the ground.
void drawbar(TriMesh* m, double front, double tip, double spread, double z) {
  const Vector3d hitch(tip - 0.2, 0, 0.45);
  for (double s : {-1.0, 1.0}) m->limb({front, s * spread, z}, hitch, 0.05, 0.05, 6);
  m->box({tip - 0.25, -0.07, 0.38}, {tip, 0.07, 0.5});
}

}  // namespace

TriMesh trailer_mesh(common::Rng& rng) {
  // A flatbed (side boards) or box trailer: body 3 - 6.2 m, drawbar 1 - 1.6 m, one axle.
  TriMesh m;
  const double body = rng.uniform(3.0, 6.2), bar = rng.uniform(1.0, 1.6);
  const double hl = (body + bar) / 2, hw = rng.uniform(1.9, 2.4) / 2;
  const double r = rng.uniform(0.33, 0.4), zb = 2 * r + 0.03, zt = zb + 0.12;
  const bool box = rng.uniform() < 0.5;
  const double back = -hl, front = -hl + body;
  m.box({back, -hw, zb}, {front, hw, zt});
  if (box) {
    m.box({back, -hw, zt}, {front, hw, zt + rng.uniform(1.5, 2.1)});
  } else {
    m.box({back, -hw, zt}, {front, -hw + 0.04, zt + 0.3});
    m.box({back, hw - 0.04, zt}, {front, hw, zt + 0.3});
    m.box({front - 0.04, -hw, zt}, {front, hw, zt + 0.3});
  }
  axle(&m, back + body / 2, hw, r);
  drawbar(&m, front, hl, 0.8 * hw, zb + 0.05);
  return m;
}

TriMesh caravan_mesh(common::Rng& rng) {
  // A touring caravan: a body rounded along its top and at both ends, one axle, a drawbar with a
  // gas-bottle box, a roof vent.
  TriMesh m;
  const double body = rng.uniform(4.0, 5.8), bar = rng.uniform(1.0, 1.2);
  const double hl = (body + bar) / 2, hw = rng.uniform(2.1, 2.5) / 2, h = rng.uniform(2.4, 2.8);
  const double r = rng.uniform(0.3, 0.36), zb = r + 0.15, top = h - 0.08, re = 0.3;
  const double back = -hl, front = -hl + body;
  std::vector<std::pair<double, std::vector<Vector2d>>> rings;
  for (int j = 0; j < 8; ++j) {
    const double a = common::kPi / 2 * (j < 4 ? j : 7 - j) / 3;  // 0 at the ends
    const double x = j < 4 ? back + re * (1 - std::cos(a)) : front - re * (1 - std::cos(a));
    const double e = re * (1 - std::sin(a));  // inset of the sides and the roof
    rings.emplace_back(x, rounded_section(hw - e, zb, top - e, 0.35, 0.08));
  }
  loft_x(&m, rings);
  m.box({-0.25, -0.25, top - 0.05}, {0.25, 0.25, h});  // roof vent
  axle(&m, back + body / 2, hw, r);
  drawbar(&m, front, hl, 0.5, zb + 0.05);
  m.box({front + 0.1, -0.3, 0.5}, {front + 0.5, 0.3, 0.95});  // gas-bottle box
  return m;
}

TriMesh pipes_mesh(common::Rng& rng) {
  // Parallel pipes 5 - 7 m long, radius 0.15 - 0.3 m, rows of n, n - 1, n - 2 (n = 3 - 5) on two
  // sleepers 12 cm high.
  TriMesh m;
  const double len = rng.uniform(5.0, 7.0), r = rng.uniform(0.15, 0.3);
  const int n = 3 + static_cast<int>(rng.below(3));
  const double hw = n * r + 0.1, z0 = 0.12;
  for (double x : {-len / 3, len / 3}) m.box({x - 0.075, -hw, 0}, {x + 0.075, hw, z0});
  for (int row = 0; row < 3 && n - row > 0; ++row) {
    const int k = n - row;
    for (int i = 0; i < k; ++i) {
      const double y = (i - (k - 1) / 2.0) * 2 * r, z = z0 + r + row * r * std::sqrt(3.0);
      const double jitter = rng.uniform(-0.1, 0.1);
      m.limb({-len / 2 + jitter, y, z}, {len / 2 + jitter, y, z}, r, r, 12);
    }
  }
  return m;
}

TriMesh barriers_mesh(common::Rng& rng) {
  // 2 - 3 concrete jersey barriers 3.8 - 4 m long, 0.61 m wide at the base, 0.8 - 1.07 m high, end
  // to end along x with gaps of 2 - 30 cm.
  TriMesh m;
  const int n = 2 + static_cast<int>(rng.below(2));
  const double h = rng.uniform(0.8, 1.07), s = h / 0.81;
  const std::vector<Vector2d> unit = {{0.305, 0},  {0.305, 0.075 * s}, {0.13, 0.33 * s},    {0.075, h},
                                      {-0.075, h}, {-0.13, 0.33 * s},  {-0.305, 0.075 * s}, {-0.305, 0}};
  std::vector<double> lengths, gaps;
  double total = 0;
  for (int k = 0; k < n; ++k) {
    lengths.push_back(rng.uniform(3.8, 4.0));
    gaps.push_back(k + 1 < n ? rng.uniform(0.02, 0.3) : 0);
    total += lengths.back() + gaps.back();
  }
  double x = -total / 2;
  for (int k = 0; k < n; ++k) {
    const double dy = rng.uniform(-0.04, 0.04);
    std::vector<Vector2d> profile = unit;
    for (auto& p : profile) p.x() += dy;
    prism_x(&m, profile, x, x + lengths[k]);
    x += lengths[k] + gaps[k];
  }
  return m;
}

TriMesh tent_mesh(common::Rng& rng) {
  // A dome tent (half ellipsoid, 3 - 4.5 m, 1.4 - 2 m high) or a ridge tent (3 - 5 m long, 2 - 3 m
  // wide, 1.5 - 2.2 m high).
  TriMesh m;
  if (rng.uniform() < 0.5) {
    const double rx = rng.uniform(3.0, 4.5) / 2, ry = rx * rng.uniform(0.8, 1.0), h = rng.uniform(1.4, 2.0);
    const int around = 16, rings = 6;
    for (int i = 0; i < rings; ++i) {
      const double a = common::kPi / 2 * i / rings;  // elevation
      for (int k = 0; k < around; ++k) {
        const double t = 2 * common::kPi * k / around;
        m.v.emplace_back(rx * std::cos(a) * std::cos(t), ry * std::cos(a) * std::sin(t), h * std::sin(a));
      }
    }
    m.v.emplace_back(0, 0, h);
    const int apex = static_cast<int>(m.v.size() - 1);
    for (int i = 0; i < rings; ++i) {
      for (int k = 0; k < around; ++k) {
        const int a = i * around + k, b = i * around + (k + 1) % around;
        if (i + 1 < rings) {
          m.f.push_back({a, b, b + around});
          m.f.push_back({a, b + around, a + around});
        } else {
          m.f.push_back({a, b, apex});
        }
      }
    }
    for (int k = 1; k + 1 < around; ++k) m.f.push_back({0, k + 1, k});  // the floor
  } else {
    const double len = rng.uniform(3.0, 5.0), hw = rng.uniform(2.0, 3.0) / 2, h = rng.uniform(1.5, 2.2);
    prism_x(&m, {{hw, 0}, {0, h}, {-hw, 0}}, -len / 2, len / 2);
  }
  return m;
}

TriMesh rock_mesh(common::Rng& rng) {
  // A car-sized rock: an ellipsoid of semi-axes 1.75 - 2.1, 0.9 - 1.15 and 0.75 - 0.9 m, each
  // vertex moved radially by +-8%, 10 cm buried.
  TriMesh m = icosphere(3);
  const Vector3d axes(rng.uniform(1.75, 2.1), rng.uniform(0.9, 1.15), rng.uniform(0.75, 0.9));
  for (auto& p : m.v) p = p.cwiseProduct(axes) * rng.uniform(0.92, 1.08);
  double zmin = 1e9;
  for (const auto& p : m.v) zmin = std::min(zmin, p.z());
  for (auto& p : m.v) p.z() -= zmin + 0.1;
  return m;
}

}  // namespace canopy::sim
