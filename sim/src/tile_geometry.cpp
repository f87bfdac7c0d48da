// Tile geometry: terrain, poses on the terrain, tree/bush/clutter meshes, placement.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "canopy/common/units.h"
#include "rangetrace/povray_run.h"
#include "rangetrace/families.h"
#include "rangetrace/tile.h"

namespace canopy::rangetrace {

using common::DataError;
using Eigen::Vector2d;
using Eigen::Vector3d;

// ---------------------------------------------------------------- meshes

void TriMesh::triangle(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const int n = static_cast<int>(v.size());
  v.push_back(a);
  v.push_back(b);
  v.push_back(c);
  f.push_back({n, n + 1, n + 2});
}

void TriMesh::box(const Vector3d& lo, const Vector3d& hi) {
  const int n = static_cast<int>(v.size());
  for (int i = 0; i < 8; ++i) {
    v.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  }
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& s : q) {
    f.push_back({n + s[0], n + s[1], n + s[2]});
    f.push_back({n + s[0], n + s[2], n + s[3]});
  }
}

void TriMesh::limb(const Vector3d& a, const Vector3d& b, double ra, double rb, int sides) {
  const Vector3d axis = (b - a).normalized();
  const Vector3d helper = std::abs(axis.z()) < 0.9 ? Vector3d::UnitZ() : Vector3d::UnitX();
  const Vector3d p = axis.cross(helper).normalized(), q = axis.cross(p);
  const int n = static_cast<int>(v.size());
  for (int k = 0; k < sides; ++k) {
    const double t = 2 * common::kPi * k / sides;
    const Vector3d d = std::cos(t) * p + std::sin(t) * q;
    v.push_back(a + ra * d);
    v.push_back(b + rb * d);
  }
  v.push_back(a);
  v.push_back(b);
  const int ca = n + 2 * sides, cb = ca + 1;
  for (int k = 0; k < sides; ++k) {
    const int k2 = (k + 1) % sides;
    f.push_back({n + 2 * k, n + 2 * k2, n + 2 * k2 + 1});
    f.push_back({n + 2 * k, n + 2 * k2 + 1, n + 2 * k + 1});
    f.push_back({ca, n + 2 * k2, n + 2 * k});
    f.push_back({cb, n + 2 * k + 1, n + 2 * k2 + 1});
  }
}

void TriMesh::append(const TriMesh& o) {
  const int n = static_cast<int>(v.size());
  v.insert(v.end(), o.v.begin(), o.v.end());
  for (const auto& t : o.f) f.push_back({t[0] + n, t[1] + n, t[2] + n});
}

std::string mesh_declare(const std::string& name, const TriMesh& mesh) {
  return mesh2_declare(name, mesh.v, mesh.f, true);
}

namespace {

Vector3d random_unit(common::Rng& rng) {
  Vector3d n;
  do { n = Vector3d(rng.normal(), rng.normal(), rng.normal()); } while (n.norm() < 1e-9);
  return n.normalized();
}

// A leaf: a triangle of circumradius r centred at c with a random orientation.
void leaf(TriMesh* m, common::Rng& rng, const Vector3d& c, double r, double aspect = 1.0) {
  const Vector3d n = random_unit(rng);
  const Vector3d helper = std::abs(n.z()) < 0.9 ? Vector3d::UnitZ() : Vector3d::UnitX();
  const Vector3d a = n.cross(helper).normalized(), b = n.cross(a);
  const double t0 = rng.uniform(0, 2 * common::kPi);
  Vector3d p[3];
  for (int k = 0; k < 3; ++k) {
    const double t = t0 + 2 * common::kPi * k / 3;
    p[k] = c + r * std::cos(t) * a + r * aspect * std::sin(t) * b;
  }
  m->triangle(p[0], p[1], p[2]);
}

Vector3d in_ball(common::Rng& rng) {
  Vector3d p;
  do {
    p = Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  } while (p.squaredNorm() > 1);
  return p;
}

}  // namespace

TriMesh broadleaf_template(std::uint64_t seed, double h) {
  common::Rng rng(seed);
  TriMesh m;
  m.limb({0, 0, -0.6}, {0, 0, 0.62 * h}, 0.24, 0.11, 7);
  const Vector3d c(0, 0, 0.66 * h);
  const double rh = 0.23 * h, rv = 0.3 * h;
  auto on_crown = [&](const Vector3d& d, double f) {
    return Vector3d(c.x() + f * rh * d.x(), c.y() + f * rh * d.y(), c.z() + f * rv * d.z());
  };
  std::vector<std::pair<Vector3d, Vector3d>> twigs;  // (start, end) carrying leaf clusters
  const int branches = 9 + static_cast<int>(rng.below(4));
  for (int b = 0; b < branches; ++b) {
    Vector3d d = random_unit(rng);
    d.z() = std::abs(d.z()) * 0.8 + 0.1;
    d.normalize();
    const Vector3d s(0, 0, rng.uniform(0.42, 0.6) * h);
    const Vector3d e = on_crown(d, 0.85);
    m.limb(s, e, 0.09, 0.03, 5);
    twigs.emplace_back(s + 0.5 * (e - s), e);
    for (int k = 0; k < 3; ++k) {
      const Vector3d from = s + rng.uniform(0.4, 0.8) * (e - s);
      const Vector3d to = on_crown((d + 0.7 * random_unit(rng)).normalized(), rng.uniform(0.75, 0.95));
      m.limb(from, to, 0.04, 0.015, 4);
      twigs.emplace_back(from + 0.3 * (to - from), to);
    }
  }
  // Leaf clusters along the outer parts of the twigs: 6720 leaves, circumradius 14 cm.
  const int clusters = 280;
  for (int k = 0; k < clusters; ++k) {
    const auto& [s, e] = twigs[rng.below(twigs.size())];
    const Vector3d centre = s + rng.uniform() * (e - s);
    for (int l = 0; l < 24; ++l) leaf(&m, rng, centre + 0.5 * in_ball(rng), 0.14);
  }
  return m;
}

TriMesh conifer_template(std::uint64_t seed, double h) {
  common::Rng rng(seed);
  TriMesh m;
  m.limb({0, 0, -0.6}, {0, 0, h}, 0.26, 0.03, 7);
  const double zb = 0.28 * h, rb = 0.16 * h;
  for (double z = zb; z < h - 0.4; z += 0.5) {
    const double reach = rb * (h - z) / (h - zb) + 0.25;
    const int n = 5 + static_cast<int>(rng.below(3));
    const double a0 = rng.uniform(0, 2 * common::kPi);
    for (int b = 0; b < n; ++b) {
      const double a = a0 + 2 * common::kPi * (b + rng.uniform(-0.2, 0.2)) / n;
      const double len = reach * rng.uniform(0.8, 1.0);
      const Vector3d s(0, 0, z), e(len * std::cos(a), len * std::sin(a), z - 0.2 * len);
      m.limb(s, e, 0.035, 0.012, 4);
      // Needle tufts: thin triangles (30 x 8 cm) around points along the branch.
      for (double t = 0.3; t <= 1.0; t += 0.23) {
        const Vector3d centre = s + t * (e - s);
        for (int l = 0; l < 10; ++l) leaf(&m, rng, centre + 0.2 * in_ball(rng), 0.18, 0.27);
      }
    }
  }
  return m;
}

TriMesh bush_template(std::uint64_t seed, double r) {
  common::Rng rng(seed);
  TriMesh m;
  const Vector3d c(0, 0, 0.8 * r);
  for (int s = 0; s < 4; ++s) {
    Vector3d d = random_unit(rng);
    d.z() = std::abs(d.z());
    m.limb({0, 0, -0.2}, c + 0.7 * r * d, 0.04, 0.015, 4);
  }
  for (int k = 0; k < 45; ++k) {
    Vector3d p = in_ball(rng);
    p = c + Vector3d(r * p.x(), r * p.y(), 0.8 * r * p.z());
    for (int l = 0; l < 18; ++l) leaf(&m, rng, p + 0.25 * in_ball(rng), 0.08);
  }
  return m;
}

namespace {

TriMesh boulder_mesh(common::Rng& rng) {
  TriMesh m;
  // Icosphere (2 subdivisions), stretched and roughened, about a third buried.
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vector3d> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int level = 0; level < 2; ++level) {
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
  const double r = rng.uniform(0.5, 1.0);
  const Vector3d scale(r, r * rng.uniform(0.6, 1.0), r * rng.uniform(0.5, 0.8));
  for (auto& p : v) p = p.cwiseProduct(scale) * rng.uniform(0.88, 1.12);
  double zmin = 1e9;
  for (const auto& p : v) zmin = std::min(zmin, p.z());
  for (auto& p : v) p.z() -= zmin + 0.3 * scale.z();
  m.v = v;
  m.f = f;
  return m;
}

TriMesh shed_mesh() {
  TriMesh m;
  m.box({-2, -1.5, -0.2}, {2, 1.5, 2.3});
  m.box({-0.45, -1.56, -0.2}, {0.45, -1.5, 2.0});  // door
  const double x0 = -2.2, x1 = 2.2, y0 = -1.75, y1 = 1.75, z0 = 2.2, zr = 3.2;
  const Vector3d a0(x0, y0, z0), a1(x1, y0, z0), b0(x0, 0, zr), b1(x1, 0, zr), c0(x0, y1, z0), c1(x1, y1, z0);
  m.triangle(a0, a1, b1);
  m.triangle(a0, b1, b0);
  m.triangle(c0, b0, b1);
  m.triangle(c0, b1, c1);
  m.triangle(a0, c0, c1);  // underside of the roof
  m.triangle(a0, c1, a1);
  m.triangle(a0, b0, c0);  // gables
  m.triangle(a1, c1, b1);
  return m;
}

TriMesh container_mesh() {
  TriMesh m;
  // ISO 20 ft container: 6.06 x 2.44 x 2.59 m, corner posts and side corrugations.
  const double hl = 3.03, hw = 1.22, h = 2.59;
  m.box({-hl + 0.02, -hw + 0.02, 0}, {hl - 0.02, hw - 0.02, h});
  for (int i = 0; i < 4; ++i) {
    const double x = i & 1 ? hl - 0.16 : -hl, y = i & 2 ? hw - 0.16 : -hw;
    m.box({x, y, 0}, {x + 0.16, y + 0.16, h});
  }
  for (double x = -hl + 0.3; x < hl - 0.3; x += 0.28) {
    m.box({x, -hw + 0.0, 0.15}, {x + 0.12, -hw + 0.03, h - 0.15});
    m.box({x, hw - 0.03, 0.15}, {x + 0.12, hw, h - 0.15});
  }
  return m;
}

TriMesh fence_mesh() {
  TriMesh m;
  // 10 m of post-and-rail fence along x.
  for (int k = 0; k <= 4; ++k) {
    const double x = -5 + 2.5 * k;
    m.box({x - 0.06, -0.06, -0.4}, {x + 0.06, 0.06, 1.5});
  }
  for (double z : {0.45, 0.9, 1.35}) m.box({-5.05, 0.06, z - 0.05}, {5.05, 0.1, z + 0.05});
  return m;
}

TriMesh logs_mesh(common::Rng& rng) {
  TriMesh m;
  // Stacked logs, 4 m long along x, radius 18 cm: rows of 5, 4, 3, 2.
  const double r = 0.18;
  for (int row = 0; row < 4; ++row) {
    const int n = 5 - row;
    for (int k = 0; k < n; ++k) {
      const double y = (k - (n - 1) / 2.0) * 2 * r;
      const double z = r + row * r * std::sqrt(3.0);
      const double jitter = rng.uniform(-0.15, 0.15);
      m.limb({-2 + jitter, y, z}, {2 + jitter, y, z}, r * rng.uniform(0.9, 1.05), r * rng.uniform(0.9, 1.05),
             10);
    }
  }
  return m;
}

}  // namespace

TriMesh clutter_mesh(const std::string& kind, std::uint64_t seed) {
  common::Rng rng(seed);
  if (kind == "boulder") return boulder_mesh(rng);
  if (kind == "shed") return shed_mesh();
  if (kind == "container") return container_mesh();
  if (kind == "fence") return fence_mesh();
  if (kind == "logs") return logs_mesh(rng);
  throw common::Error("unknown clutter kind '" + kind + "'");
}

// ---------------------------------------------------------------- terrain

TerrainModel::TerrainModel(const TileRecipe& tile, std::uint64_t seed) {
  cx_ = tile.extent_x / 2;
  cy_ = tile.extent_y / 2;
  if (tile.terrain == Terrain::kSlope) {
    const double g = std::tan(tile.slope);
    plane_n_ = Vector3d(-g * std::cos(tile.slope_azimuth), -g * std::sin(tile.slope_azimuth), 1).normalized();
  }
  if (tile.terrain != Terrain::kRolling) {
    planar_ = true;
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i < 4; ++i) {
      const double z = height(i & 1 ? tile.extent_x : 0, i & 2 ? tile.extent_y : 0);
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
    lo_ = lo;
    hi_ = hi;
    return;
  }
  planar_ = false;
  // Sum of six seeded plane waves, shifted to mean 0 and scaled to +-amplitude over the grid.
  common::Rng rng(common::derive_seed(seed, "terrain"));
  struct Wave {
    double kx, ky, phase, a;
  };
  std::vector<Wave> waves;
  for (int k = 0; k < 6; ++k) {
    const double dir = rng.uniform(0, 2 * common::kPi);
    const double kk = 2 * common::kPi / (tile.rolling_wavelength * rng.uniform(0.7, 1.4));
    waves.push_back(
        {kk * std::cos(dir), kk * std::sin(dir), rng.uniform(0, 2 * common::kPi), rng.uniform(0.5, 1.0)});
  }
  const double margin = 10;
  step_ = 1.0;
  x0_ = -margin;
  y0_ = -margin;
  nx_ = static_cast<int>(std::ceil((tile.extent_x + 2 * margin) / step_));
  ny_ = static_cast<int>(std::ceil((tile.extent_y + 2 * margin) / step_));
  h_.resize(static_cast<std::size_t>(nx_ + 1) * (ny_ + 1));
  double mean = 0;
  for (int j = 0; j <= ny_; ++j) {
    for (int i = 0; i <= nx_; ++i) {
      const double x = x0_ + i * step_, y = y0_ + j * step_;
      double z = 0;
      for (const auto& w : waves) z += w.a * std::sin(w.kx * x + w.ky * y + w.phase);
      h_[static_cast<std::size_t>(j) * (nx_ + 1) + i] = z;
      mean += z;
    }
  }
  mean /= static_cast<double>(h_.size());
  double peak = 1e-12;
  for (auto& z : h_) peak = std::max(peak, std::abs(z -= mean));
  for (auto& z : h_) z *= tile.rolling_amplitude / peak;
  lo_ = *std::min_element(h_.begin(), h_.end());
  hi_ = *std::max_element(h_.begin(), h_.end());
}

double TerrainModel::grid(int i, int j) const {
  i = std::clamp(i, 0, nx_);
  j = std::clamp(j, 0, ny_);
  return h_[static_cast<std::size_t>(j) * (nx_ + 1) + i];
}

double TerrainModel::height(double x, double y) const {
  if (planar_) return -(plane_n_.x() * (x - cx_) + plane_n_.y() * (y - cy_)) / plane_n_.z();
  // Cells split along the diagonal (i, j)-(i+1, j+1), as in pov().
  const double u = std::clamp((x - x0_) / step_, 0.0, nx_ - 1e-9);
  const double w = std::clamp((y - y0_) / step_, 0.0, ny_ - 1e-9);
  const int i = static_cast<int>(u), j = static_cast<int>(w);
  const double fx = u - i, fy = w - j;
  const double h00 = grid(i, j), h10 = grid(i + 1, j), h01 = grid(i, j + 1), h11 = grid(i + 1, j + 1);
  if (fx >= fy) return h00 + fx * (h10 - h00) + fy * (h11 - h10);
  return h00 + fy * (h01 - h00) + fx * (h11 - h01);
}

Vector3d TerrainModel::normal(double x, double y) const {
  if (planar_) return plane_n_;
  const double e = 0.05;
  const double gx = (height(x + e, y) - height(x - e, y)) / (2 * e);
  const double gy = (height(x, y + e) - height(x, y - e)) / (2 * e);
  return Vector3d(-gx, -gy, 1).normalized();
}

std::string TerrainModel::pov() const {
  char buf[160];
  if (planar_) {
    // plane { normal, d }: points p with p . normal = d (POV-Ray frame; dot products are
    // preserved by pov_frame). The plane passes through (cx, cy, 0).
    const Vector3d n = pov_frame(plane_n_);
    const double d = plane_n_.dot(Vector3d(cx_, cy_, 0));
    std::snprintf(buf, sizeof buf, "plane { <%.12g, %.12g, %.12g>, %.12g }\n", n.x(), n.y(), n.z(), d);
    return std::string("#declare Ground = ") + buf;
  }
  TriMesh m;
  for (int j = 0; j <= ny_; ++j) {
    for (int i = 0; i <= nx_; ++i) m.v.emplace_back(x0_ + i * step_, y0_ + j * step_, grid(i, j));
  }
  const auto at = [&](int i, int j) { return j * (nx_ + 1) + i; };
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      m.f.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.f.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh_declare("Ground", m);
}

// ---------------------------------------------------------------- poses

Eigen::Affine3d Posed::transform() const {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.linear() = r;
  t.translation() = anchor;
  return t;
}

Posed stand_on(const TerrainModel& terrain, double x, double y, double heading, double hl, double hw) {
  const Vector2d f(std::cos(heading), std::sin(heading)), l(-f.y(), f.x());
  // Least-squares plane z = a + b (x - x0) + c (y - y0) through the ground under a 5 x 3 grid.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  std::vector<Vector2d> samples;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -1; j <= 1; ++j) samples.push_back(Vector2d(x, y) + (i / 2.0) * hl * f + j * hw * l);
  }
  for (const auto& s : samples) {
    const Vector3d row(1, s.x() - x, s.y() - y);
    ata += row * row.transpose();
    atb += row * terrain.height(s.x(), s.y());
  }
  const Vector3d abc = ata.ldlt().solve(atb);
  const Vector3d n = Vector3d(-abc[1], -abc[2], 1).normalized();
  // Forward: the heading direction lifted onto the plane (keeps the azimuth exactly).
  Vector3d fwd(f.x(), f.y(), 0);
  fwd.z() = -(fwd.x() * n.x() + fwd.y() * n.y()) / n.z();
  fwd.normalize();
  const Vector3d left = n.cross(fwd).normalized();
  Posed p;
  p.r.col(0) = fwd;
  p.r.col(1) = left;
  p.r.col(2) = n;
  p.anchor = Vector3d(x, y, abc[0]);
  double lift = 0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -1; j <= 1; ++j) {
      const Vector3d q = p.anchor + p.r * Vector3d(i / 2.0 * hl, j * hw, 0);
      lift = std::max(lift, terrain.height(q.x(), q.y()) - q.z());
    }
  }
  p.anchor.z() += lift;
  p.heading = std::atan2(p.r(1, 0), p.r(0, 0));
  p.pitch = std::asin(std::clamp(-p.r(2, 0), -1.0, 1.0));
  p.roll = std::atan2(p.r(2, 1), p.r(2, 2));
  return p;
}

// ---------------------------------------------------------------- placement

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
  TileBuilder(const TileRecipe& recipe, const std::string& name, const Params& params)
      : recipe_(recipe),
        name_(name),
        params_(params),
        terrain_(recipe, params.seed),
        trng_(common::derive_seed(params.seed, "trees")) {
    tile_.recipe = recipe;
    tile_.name = name;
    tile_.seed = params.seed;
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
  void plant_trees();
  bool place_random_tree(const Vector2d& p, bool inside);
  void plant_bushes();
  double top() const;

  const TileRecipe& recipe_;
  const std::string& name_;
  const Params& params_;
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
    tile_.model_bounds = models_extent(tile_.models, params_, tmp);
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
  common::Rng rng(common::derive_seed(params_.seed, "vehicles"));
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
  tile_.object_meshes.push_back(clutter_mesh(
      kind, common::derive_seed(params_.seed, "clutter-" + std::to_string(tile_.objects.size()))));
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

// Clutter: hand-placed, then random per kind.
void TileBuilder::place_clutter() {
  for (const auto& s : recipe_.objects) {
    auto [o, q] = make_object(s.kind, s.x, s.y, s.heading);
    tile_.objects.push_back(o);
    taken_.push_back(q);
  }
  common::Rng rng(common::derive_seed(params_.seed, "clutter"));
  for (std::size_t c = 0; c < recipe_.clutter.size(); ++c) {
    const auto& [kind, n] = recipe_.clutter[c];
    for (int k = 0; k < n; ++k) {
      bool placed = false;
      for (int attempt = 0; attempt < 500 && !placed; ++attempt) {
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
        throw DataError(name_, "line " + std::to_string(recipe_.clutter_lines[c]) + ": no room for " +
                                   std::to_string(n) + " " + kind + " objects in the tile");
      }
    }
  }
}

// Trees: four broadleaf and four conifer templates, three bushes; instances rotated and
// scaled by +-15%. Trunks keep 0.6 m from vehicles and clutter, 1.5 m from each other.
void TileBuilder::plant_trees() {
  const std::uint64_t tseed = common::derive_seed(params_.seed, "tree-templates");
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
  common::Rng brng(common::derive_seed(params_.seed, "bushes"));
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

Tile build_tile(const TileRecipe& recipe, const std::string& name, const Params& params) {
  return TileBuilder(recipe, name, params).build();
}

}  // namespace canopy::rangetrace
