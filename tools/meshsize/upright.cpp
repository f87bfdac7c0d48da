#include "meshsize/upright.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_set>

#include "canopy/common/error.h"

namespace canopy::meshsize {
namespace {

namespace cm = canopy::common;
namespace fm = canopy::formats;

constexpr double kSideSymmetry = 0.85;  // horizontal mirror symmetry at or above: on its side
constexpr double kMaxSamples = 2e7;     // surface samples of the up check, at most (about 2 s)

}  // namespace

std::string fixed(double x, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, x);
  return b;
}

std::vector<Eigen::Vector3d> render_frame(const fm::TriangleMesh& mesh, double scale, const std::string& up,
                                          const std::string& input) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(mesh.vertices.size());
  for (const auto& p : mesh.vertices) {
    Eigen::Vector3d v = p * scale;
    if (!v.allFinite()) throw cm::DataError(input, "non-finite vertex coordinate");
    if (up == "y") v = Eigen::Vector3d(v.x(), -v.z(), v.y());  // as sim/src/models.cpp
    out.push_back(v);
  }
  return out;
}

Box bounds(const fm::TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& v) {
  Box box{Eigen::Vector3d::Constant(1e300), Eigen::Vector3d::Constant(-1e300)};
  for (const auto& f : mesh.faces) {
    for (int k : f) {
      box.lo = box.lo.cwiseMin(v[k]);
      box.hi = box.hi.cwiseMax(v[k]);
    }
  }
  return box;
}

// Samples the surface (16 points per voxel face area, a fixed xorshift stream: the same mesh
// gives the same answer) into voxels of 1/100 of the largest extent, and scores the best mirror
// plane z = c, c within 2.5% of the height of mid-height (quarter-voxel steps).
Upright upright(const fm::TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& v, const Box& box) {
  Upright u;
  const Eigen::Vector3d& lo = box.lo;
  u.size = box.size();
  const double cell = u.size.maxCoeff() / 100;
  if (!(cell > 0) || !std::isfinite(cell)) return u;
  u.on_end = u.size.z() > std::max(u.size.x(), u.size.y());
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto uniform = [&state] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  };
  auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) { return (i * 1024 + j) * 1024 + k; };
  std::unordered_set<std::int64_t> occupied;
  std::vector<std::array<std::int64_t, 3>> voxels;
  // Samples per face: 16 per voxel face area, in cell units (no overflow for huge coordinates);
  // at most kMaxSamples over the mesh (thinned alike on every face: faces spanning the whole box
  // would otherwise cost seconds each).
  auto samples = [&](const std::array<int, 3>& f) {
    const Eigen::Vector3d ab = (v[f[1]] - v[f[0]]) / cell, ac = (v[f[2]] - v[f[0]]) / cell;
    return 0.5 * ab.cross(ac).norm() * 16;
  };
  double total = 0;
  for (const auto& f : mesh.faces) total += samples(f);
  const double thin = total > kMaxSamples ? kMaxSamples / total : 1.0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = v[f[0]], b = v[f[1]], c = v[f[2]];
    const double n = samples(f) * thin;
    if (!std::isfinite(n)) continue;
    const long count = static_cast<long>(n) + (uniform() < n - std::floor(n) ? 1 : 0);
    for (long i = 0; i < count; ++i) {
      double s = uniform(), t = uniform();
      if (s + t > 1) s = 1 - s, t = 1 - t;
      const Eigen::Vector3d q = (a + s * (b - a) + t * (c - a) - lo) / cell;
      const std::array<std::int64_t, 3> ijk = {std::min<std::int64_t>(static_cast<std::int64_t>(q.x()), 100),
                                               std::min<std::int64_t>(static_cast<std::int64_t>(q.y()), 100),
                                               std::min<std::int64_t>(static_cast<std::int64_t>(q.z()), 100)};
      if (occupied.insert(key(ijk[0], ijk[1], ijk[2])).second) voxels.push_back(ijk);
    }
  }
  if (voxels.empty()) return u;
  const double nz = u.size.z() / cell;
  const int steps = static_cast<int>(std::ceil(0.1 * nz));
  for (int s = -steps; s <= steps; ++s) {
    const double twice_centre = nz + 0.5 * s;  // voxel k's centre k + 0.5 mirrors to 2c - k - 0.5
    std::size_t hit = 0;
    for (const auto& x : voxels) {
      const auto m = static_cast<std::int64_t>(std::floor(twice_centre - (x[2] + 0.5)));
      for (std::int64_t d = -1; d <= 1; ++d) {
        if (occupied.count(key(x[0], x[1], m + d))) {
          ++hit;
          break;
        }
      }
    }
    u.symmetry = std::max(u.symmetry, static_cast<double>(hit) / voxels.size());
  }
  u.on_side = u.symmetry >= kSideSymmetry;
  return u;
}

std::string up_problem(const std::string& up, const Upright& u, const Upright& other) {
  const std::string alt = up == "z" ? "y" : "z";
  std::string what = "read with --up " + up + " (make: MESH_UP=" + up + "), the vehicle ";
  if (u.on_end) {  // the extent is the surer sign (on its end, a bus is 0.84 front-back symmetric)
    what += "looks as if standing on its end: its height " + fixed(u.size.z(), 2) +
            " m is its largest extent (length " + fixed(u.size.x(), 2) + " m, width " + fixed(u.size.y(), 2) +
            " m)";
  } else {
    what += "looks as if lying on its side: it is mirror-symmetric about a horizontal plane (symmetry " +
            fixed(u.symmetry, 2) + ", >= " + fixed(kSideSymmetry, 2) +
            "; measured: 0.15-0.68 upright, 0.94-1.00 on the side)";
  }
  if (other.ok()) {
    what += "; with --up " + alt + " (MESH_UP=" + alt + ") it stands upright";
  } else if (!u.on_end && !other.on_end && u.on_side && other.on_side) {
    // Mirror-symmetric top to bottom whichever way: a box without wheels or cab (a container)
    // is; the check cannot tell which way is up.
    what += "; with --up " + alt + " (MESH_UP=" + alt +
            ") it is as symmetric: a shape like a plain box, whose up axis this check cannot tell";
  } else {
    what += "; with --up " + alt + " (MESH_UP=" + alt +
            ") it does not stand upright either: turn the mesh so that its up axis is z or y";
  }
  return what;
}

}  // namespace canopy::meshsize
