// Synthetic meshes with known parts for the ncut tests and benchmark: sampled planar
// patches (vertices at cell centres, as fitvox keeps one sample per voxel), zipped together
// across creases the way a reconstruction bridges two faces.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <vector>

#include "canopy/common/rng.h"
#include "ncut/ncut.h"

namespace canopy::ncut::testing {

struct TestMesh {
  Input in;
  std::vector<int> part;  // ground-truth face id per vertex

  // Grid of nu x nv samples at cell centres of the parallelogram origin + [0,1] U + [0,1] V.
  // Returns grid[i][j]. Triangulated inside; normal = the given one.
  std::vector<std::vector<int>> add_grid(const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
                                         const Eigen::Vector3d& v, int nu, int nv,
                                         const Eigen::Vector3d& normal, int part_id) {
    std::vector<std::vector<int>> g(nu, std::vector<int>(nv));
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {
        g[i][j] = static_cast<int>(in.points.size());
        in.points.push_back(origin + (i + 0.5) / nu * u + (j + 0.5) / nv * v);
        in.normals.push_back(normal.normalized());
        part.push_back(part_id);
      }
    }
    for (int i = 0; i + 1 < nu; ++i) {
      for (int j = 0; j + 1 < nv; ++j) {
        in.faces.push_back({g[i][j], g[i + 1][j], g[i + 1][j + 1]});
        in.faces.push_back({g[i][j], g[i + 1][j + 1], g[i][j + 1]});
      }
    }
    return g;
  }

  // Ladder of triangles between two rows of equal length.
  void zip(const std::vector<int>& a, const std::vector<int>& b) {
    for (std::size_t k = 0; k + 1 < a.size(); ++k) {
      in.faces.push_back({a[k], a[k + 1], b[k + 1]});
      in.faces.push_back({a[k], b[k + 1], b[k]});
    }
  }
};

inline std::vector<int> row_i(const std::vector<std::vector<int>>& g, int i) { return g[i]; }
inline std::vector<int> row_j(const std::vector<std::vector<int>>& g, int j) {
  std::vector<int> r;
  for (const auto& col : g) r.push_back(col[j]);
  return r;
}

// Two unit squares meeting at 90 degrees along the y axis: floor z = 0 (normal +z, part 0)
// and wall x = 0 (normal +x, part 1), spacing h.
inline TestMesh two_planes(double side, double h) {
  TestMesh m;
  const int n = static_cast<int>(std::lround(side / h));
  auto floor = m.add_grid({0, 0, 0}, {side, 0, 0}, {0, side, 0}, n, n, {0, 0, 1}, 0);
  auto wall = m.add_grid({0, 0, 0}, {0, 0, side}, {0, side, 0}, n, n, {1, 0, 0}, 1);
  m.zip(row_i(floor, 0), row_i(wall, 0));
  return m;
}

// Axis-aligned box [0,L] sampled at spacing h on each face, outward normals, faces zipped
// across the 12 edges. Part id = 2 * axis + (sign > 0). `bottom` = include the z- face.
inline TestMesh box(const Eigen::Vector3d& size, double h, bool bottom = true) {
  TestMesh m;
  int count[3];
  for (int k = 0; k < 3; ++k) count[k] = static_cast<int>(std::lround(size[k] / h));
  std::vector<std::vector<int>> grid[3][2];
  bool present[3][2];
  for (int a = 0; a < 3; ++a) {
    for (int s = 0; s < 2; ++s) {
      present[a][s] = bottom || !(a == 2 && s == 0);
      if (!present[a][s]) continue;
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      Eigen::Vector3d origin = Eigen::Vector3d::Zero();
      origin[a] = s ? size[a] : 0;
      Eigen::Vector3d eu = Eigen::Vector3d::Zero(), ev = Eigen::Vector3d::Zero(),
                      nrm = Eigen::Vector3d::Zero();
      eu[u] = size[u];
      ev[v] = size[v];
      nrm[a] = s ? 1 : -1;
      grid[a][s] = m.add_grid(origin, eu, ev, count[u], count[v], nrm, 2 * a + s);
    }
  }
  // The row of face (a, sa) next to face (b, sb), running along the third axis.
  auto edge_row = [&](int a, int sa, int b, int sb) {
    const auto& g = grid[a][sa];
    const int u = (a + 1) % 3;
    if (b == u) return row_i(g, sb ? count[u] - 1 : 0);
    const int v = (a + 2) % 3;
    return row_j(g, sb ? count[v] - 1 : 0);
  };
  for (int a = 0; a < 3; ++a) {
    for (int b = a + 1; b < 3; ++b) {
      for (int sa = 0; sa < 2; ++sa) {
        for (int sb = 0; sb < 2; ++sb) {
          if (!present[a][sa] || !present[b][sb]) continue;
          m.zip(edge_row(a, sa, b, sb), edge_row(b, sb, a, sa));
        }
      }
    }
  }
  return m;
}

// Perturbs positions by isotropic Gaussian noise (sigma_p, m) and normals by a random
// rotation of Gaussian angle (sigma_a, rad). Seeded.
inline void add_noise(TestMesh* m, double sigma_p, double sigma_a, std::uint64_t seed) {
  common::Rng rng(seed);
  for (std::size_t i = 0; i < m->in.points.size(); ++i) {
    m->in.points[i] += sigma_p * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    Eigen::Vector3d& n = m->in.normals[i];
    n = (n + sigma_a * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal())).normalized();
  }
}

}  // namespace canopy::ncut::testing
