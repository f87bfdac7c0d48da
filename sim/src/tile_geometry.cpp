// Tile geometry: tree, bush and clutter meshes, the terrain, poses on the terrain (placement:
// tile_placement.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "canopy/sim/tile.h"
#include "clutter_kinds.h"

namespace canopy::sim {

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
  // Icosphere (2 subdivisions), stretched and roughened, about a third buried.
  TriMesh m = icosphere(2);
  std::vector<Vector3d>& v = m.v;
  const double r = rng.uniform(0.5, 1.0);
  const Vector3d scale(r, r * rng.uniform(0.6, 1.0), r * rng.uniform(0.5, 0.8));
  for (auto& p : v) p = p.cwiseProduct(scale) * rng.uniform(0.88, 1.12);
  double zmin = 1e9;
  for (const auto& p : v) zmin = std::min(zmin, p.z());
  for (auto& p : v) p.z() -= zmin + 0.3 * scale.z();
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
  if (kind == "trailer") return trailer_mesh(rng);
  if (kind == "caravan") return caravan_mesh(rng);
  if (kind == "pipes") return pipes_mesh(rng);
  if (kind == "barriers") return barriers_mesh(rng);
  if (kind == "tent") return tent_mesh(rng);
  if (kind == "rock") return rock_mesh(rng);
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

}  // namespace canopy::sim
