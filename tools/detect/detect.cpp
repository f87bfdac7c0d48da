#include "detect/detect.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>
#include <utility>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/progressive_morphological_filter.h>

#include "canopy/common/error.h"
#include "canopy/common/geometry.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/labels.h"

namespace canopy::detect {
namespace {

using common::DataError;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kMaxCells = 2e7;                // DTM raster limit (bounded memory)
constexpr double kFreeCells = 4e6;               // DTM cells any tile may have (1 km x 1 km at 0.5 m) ...
constexpr double kCellsPerPoint = 16;            // ... and these per point beyond (a sparse tile)
constexpr int kNearData = 2;                     // relaxed DTM holes: this many cells from a point
constexpr double kFloat32ExactLimit = 131072.0;  // 2^17: float32 steps reach 15.6 mm beyond
constexpr int kMaxSplitDepth = 6;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// ---------------------------------------------------------------------------------------
// DTM raster

struct Raster {
  double x0 = 0, y0 = 0, cell = 1;  // lower-left corner (local frame)
  int nx = 0, ny = 0;
  std::vector<double> z;  // cell-centre ground height (local frame), row-major (j * nx + i)

  int ix(double x) const { return std::clamp(int(std::floor((x - x0) / cell)), 0, nx - 1); }
  int iy(double y) const { return std::clamp(int(std::floor((y - y0) / cell)), 0, ny - 1); }
  std::size_t at(int i, int j) const { return std::size_t(j) * std::size_t(nx) + std::size_t(i); }

  // Bilinear between cell centres.
  double height(double x, double y) const {
    const double fx = (x - x0) / cell - 0.5, fy = (y - y0) / cell - 0.5;
    int i0 = nx > 1 ? std::clamp(int(std::floor(fx)), 0, nx - 2) : 0;
    int j0 = ny > 1 ? std::clamp(int(std::floor(fy)), 0, ny - 2) : 0;
    // Linear extrapolation over the outer half cell (points beyond the outermost centres).
    const double tx = nx > 1 ? std::clamp(fx - i0, -0.5, 1.5) : 0.0;
    const double ty = ny > 1 ? std::clamp(fy - j0, -0.5, 1.5) : 0.0;
    const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
    return (1 - ty) * ((1 - tx) * z[at(i0, j0)] + tx * z[at(i1, j0)]) +
           ty * ((1 - tx) * z[at(i0, j1)] + tx * z[at(i1, j1)]);
  }
};

// True when one of the 8-neighbours of cell (i, j) is known.
bool next_to_known(const Raster& r, const std::vector<char>& known, int i, int j) {
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int a = i + di, b = j + dj;
      if (a >= 0 && b >= 0 && a < r.nx && b < r.ny && known[r.at(a, b)]) return true;
    }
  return false;
}

// Mean height of the known 8-neighbours of cell c.
double known_mean(const Raster& r, const std::vector<char>& known, std::size_t c) {
  const int i = int(c % std::size_t(r.nx)), j = int(c / std::size_t(r.nx));
  double sum = 0;
  int n = 0;
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int a = i + di, b = j + dj;
      if (a >= 0 && b >= 0 && a < r.nx && b < r.ny && known[r.at(a, b)]) {
        sum += r.z[r.at(a, b)];
        ++n;
      }
    }
  return sum / n;
}

// The unknown 8-neighbours of the frontier's cells not queued yet (now queued).
std::vector<std::size_t> next_layer(const Raster& r, const std::vector<char>& known,
                                    std::vector<char>& queued, const std::vector<std::size_t>& frontier) {
  std::vector<std::size_t> next;
  for (std::size_t c : frontier) {
    const int i = int(c % std::size_t(r.nx)), j = int(c / std::size_t(r.nx));
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const int a = i + di, b = j + dj;
        if (a < 0 || b < 0 || a >= r.nx || b >= r.ny) continue;
        const std::size_t d = r.at(a, b);
        if (!known[d] && !queued[d]) {
          queued[d] = 1;
          next.push_back(d);
        }
      }
  }
  return next;
}

// Harmonic relaxation of the filled cells (Gauss-Seidel on the 4-neighbour Laplacian, the
// known cells fixed): planes and slopes continue under a hole instead of flattening. Only the
// filled cells with `near` set move (all when it is empty); the others keep their
// breadth-first value and act as fixed boundary values (Ground::near_data says which).
void relax_holes(Raster& r, const std::vector<char>& filled, const std::vector<char>& near) {
  std::vector<std::size_t> holes;
  for (std::size_t c = 0; c < r.z.size(); ++c) {
    if (filled[c] && (near.empty() || near[c])) holes.push_back(c);
  }
  for (int it = 0; it < 1000 && !holes.empty(); ++it) {
    double change = 0;
    for (std::size_t c : holes) {
      const int i = int(c % std::size_t(r.nx)), j = int(c / std::size_t(r.nx));
      double sum = 0;
      int n = 0;
      if (i > 0) {
        sum += r.z[c - 1];
        ++n;
      }
      if (i + 1 < r.nx) {
        sum += r.z[c + 1];
        ++n;
      }
      if (j > 0) {
        sum += r.z[c - std::size_t(r.nx)];
        ++n;
      }
      if (j + 1 < r.ny) {
        sum += r.z[c + std::size_t(r.nx)];
        ++n;
      }
      const double v = sum / n;
      change = std::max(change, std::abs(v - r.z[c]));
      r.z[c] = v;
    }
    if (change < 1e-4) break;
  }
}

// Fills the NaN cells breadth-first from the known ones: each newly reached cell takes the
// mean of its 8-neighbours known before its layer; then relax_holes on those `near` data.
// Returns the number of filled cells.
std::size_t fill_holes(Raster& r, const std::vector<char>& near) {
  std::vector<std::size_t> frontier;
  std::vector<char> known(r.z.size());
  for (std::size_t c = 0; c < r.z.size(); ++c) known[c] = !std::isnan(r.z[c]);
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i) {
      if (!known[r.at(i, j)] && next_to_known(r, known, i, j)) frontier.push_back(r.at(i, j));
    }
  }
  std::size_t filled = 0;
  std::vector<char> queued(r.z.size(), 0);
  for (std::size_t c : frontier) queued[c] = 1;
  while (!frontier.empty()) {
    std::vector<double> values(frontier.size());
    for (std::size_t f = 0; f < frontier.size(); ++f) values[f] = known_mean(r, known, frontier[f]);
    for (std::size_t f = 0; f < frontier.size(); ++f) {
      r.z[frontier[f]] = values[f];
      known[frontier[f]] = 1;
      ++filled;
    }
    frontier = next_layer(r, known, queued, frontier);
  }
  relax_holes(r, queued, near);
  return filled;
}

// ---------------------------------------------------------------------------------------
// Footprints

struct Footprint {
  Vector2d centre = Vector2d::Zero();  // local frame
  Vector2d axis = Vector2d::UnitX();   // unit, long side
  double length = 0, width = 0;
};

double cross(const Vector2d& o, const Vector2d& a, const Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; counter-clockwise, no collinear points.
std::vector<Vector2d> convex_hull(std::vector<Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Vector2d& a, const Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Minimum-area enclosing rectangle: one side lies on a hull edge (Freeman & Shapira 1975).
Footprint min_area_rectangle(const std::vector<Vector2d>& points) {
  const std::vector<Vector2d> hull = convex_hull(points);
  Footprint best;
  double best_area = std::numeric_limits<double>::infinity();
  auto consider = [&](const Vector2d& u) {
    const Vector2d v(-u.y(), u.x());
    const auto [umin, umax, vmin, vmax] = common::extent_along(hull, u, v);
    const double area = (umax - umin) * (vmax - vmin);
    if (area < best_area - 1e-12) {
      best_area = area;
      const Vector2d c = 0.5 * (umin + umax) * u + 0.5 * (vmin + vmax) * v;
      best.centre = c;
      if (umax - umin >= vmax - vmin) {
        best.axis = u;
        best.length = umax - umin;
        best.width = vmax - vmin;
      } else {
        best.axis = v;
        best.length = vmax - vmin;
        best.width = umax - umin;
      }
    }
  };
  if (hull.size() < 3) {
    if (hull.size() == 2 && (hull[1] - hull[0]).norm() > 0) {
      consider((hull[1] - hull[0]).normalized());
    } else {
      consider(Vector2d::UnitX());
    }
  } else {
    for (std::size_t e = 0; e < hull.size(); ++e) {
      const Vector2d d = hull[(e + 1) % hull.size()] - hull[e];
      if (d.norm() > 0) consider(d.normalized());
    }
  }
  // Canonical direction: heading in (-pi/2, pi/2].
  if (best.axis.x() < 0 || (best.axis.x() == 0 && best.axis.y() < 0)) best.axis = -best.axis;
  return best;
}

// ---------------------------------------------------------------------------------------
// Clustering: occupied voxels, 26-connected.

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

constexpr std::uint64_t kVoxelMask = (1u << 21) - 1;

// The occupied voxels of edge v: their packed keys ascending, and the voxel of each entry of idx.
struct Voxels {
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> voxel_of;
};

// Thrown when the points span more voxels along an axis than a key holds (kVoxelMask - 1).
struct VoxelOverflow {
  double extent = 0;  // the largest extent along an axis (m)
};

Voxels occupied_voxels(const std::vector<std::uint32_t>& idx, const std::vector<double>& px,
                       const std::vector<double>& py, const std::vector<double>& pz, double v) {
  double xmin = 1e300, ymin = 1e300, zmin = 1e300, xmax = -1e300, ymax = -1e300, zmax = -1e300;
  for (std::uint32_t p : idx) {
    xmin = std::min(xmin, px[p]);
    ymin = std::min(ymin, py[p]);
    zmin = std::min(zmin, pz[p]);
    xmax = std::max(xmax, px[p]);
    ymax = std::max(ymax, py[p]);
    zmax = std::max(zmax, pz[p]);
  }
  constexpr std::uint64_t kMask = kVoxelMask;
  // Checked before converting: a huge quotient is no valid integer.
  const double extent = std::max({xmax - xmin, ymax - ymin, zmax - zmin});
  if (!(std::floor(extent / v) + 1 < double(kMask))) throw VoxelOverflow{extent};
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(idx.size());
  for (std::size_t n = 0; n < idx.size(); ++n) {
    const std::uint32_t p = idx[n];
    const auto i = std::uint64_t(std::floor((px[p] - xmin) / v)) + 1;
    const auto j = std::uint64_t(std::floor((py[p] - ymin) / v)) + 1;
    const auto k = std::uint64_t(std::floor((pz[p] - zmin) / v)) + 1;
    keyed[n] = {(i << 42) | (j << 21) | k, std::uint32_t(n)};
  }
  std::sort(keyed.begin(), keyed.end());
  Voxels out;
  out.voxel_of.resize(idx.size());
  for (const auto& [key, n] : keyed) {
    if (out.keys.empty() || out.keys.back() != key) out.keys.push_back(key);
    out.voxel_of[n] = std::uint32_t(out.keys.size() - 1);
  }
  return out;
}

// Unites 26-connected voxels by looking up each voxel's 13 forward neighbours.
void unite_grid_neighbours(const std::vector<std::uint64_t>& keys, UnionFind& uf) {
  constexpr std::uint64_t kMask = kVoxelMask;
  std::unordered_map<std::uint64_t, std::uint32_t> lookup;
  lookup.reserve(keys.size() * 2);
  for (std::size_t u = 0; u < keys.size(); ++u) lookup.emplace(keys[u], std::uint32_t(u));
  for (std::size_t u = 0; u < keys.size(); ++u) {
    const std::uint64_t i = keys[u] >> 42, j = (keys[u] >> 21) & kMask, k = keys[u] & kMask;
    // The 13 forward neighbours (the other 13 see this voxel as theirs).
    for (int di = 0; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          if (di == 0 && (dj < 0 || (dj == 0 && dk <= 0))) continue;
          const std::uint64_t key = ((i + di) << 42) | ((j + dj) << 21) | (k + dk);
          const auto it = lookup.find(key);
          if (it != lookup.end()) uf.unite(std::uint32_t(u), it->second);
        }
  }
}

// Unites the voxels PCL's Euclidean clustering puts together (voxel centres, tolerance 1.8 v).
void unite_euclidean_clusters(const std::vector<std::uint64_t>& keys, double v, UnionFind& uf) {
  constexpr std::uint64_t kMask = kVoxelMask;
  pcl::PointCloud<pcl::PointXYZ>::Ptr centres(new pcl::PointCloud<pcl::PointXYZ>);
  centres->resize(keys.size());
  for (std::size_t u = 0; u < keys.size(); ++u) {
    (*centres)[u] = pcl::PointXYZ(float(double(keys[u] >> 42) * v), float(double((keys[u] >> 21) & kMask) * v),
                                  float(double(keys[u] & kMask) * v));
  }
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(centres);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(float(v * 1.8));  // between sqrt(3) v and 2 v: the 26-neighbourhood
  ec.setMinClusterSize(1);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(tree);
  ec.setInputCloud(centres);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);
  for (const auto& c : found) {
    for (std::size_t m = 1; m < c.indices.size(); ++m) {
      uf.unite(std::uint32_t(c.indices[0]), std::uint32_t(c.indices[m]));
    }
  }
}

// Clusters the points `idx` (coordinates in px, py, pz) with voxel edge `v`. Returns the
// clusters as lists of entries of idx, ordered by their smallest voxel key, points in idx order.
std::vector<std::vector<std::uint32_t>> cluster_points(const std::vector<std::uint32_t>& idx,
                                                       const std::vector<double>& px,
                                                       const std::vector<double>& py,
                                                       const std::vector<double>& pz, double v,
                                                       Clustering method) {
  std::vector<std::vector<std::uint32_t>> out;
  if (idx.empty()) return out;
  const Voxels vox = occupied_voxels(idx, px, py, pz, v);
  const std::vector<std::uint64_t>& keys = vox.keys;
  UnionFind uf(keys.size());
  if (method == Clustering::kGrid) {
    unite_grid_neighbours(keys, uf);
  } else {
    unite_euclidean_clusters(keys, v, uf);
  }
  // Root = smallest voxel index of the component (unite keeps the smaller), so ordering by
  // root orders clusters by their smallest voxel key.
  std::map<std::uint32_t, std::size_t> cluster_of_root;
  for (std::size_t u = 0; u < keys.size(); ++u) {
    const std::uint32_t r = uf.find(std::uint32_t(u));
    if (!cluster_of_root.count(r)) cluster_of_root.emplace(r, cluster_of_root.size());
  }
  out.resize(cluster_of_root.size());
  for (std::size_t n = 0; n < idx.size(); ++n) {
    out[cluster_of_root.at(uf.find(vox.voxel_of[n]))].push_back(idx[n]);
  }
  return out;
}

// ---------------------------------------------------------------------------------------

// Planar share and area of an object (planar_shape below).
struct Shape {
  double share = 0, area = 0;
};

struct Object {
  std::vector<std::uint32_t> points;
  Footprint fp;
  double height = 0;
  Shape shape;
};

struct Context {
  const Params& p;
  const std::vector<double>& x;  // local frame
  const std::vector<double>& y;
  const std::vector<double>& z;
  const std::vector<float>& h;
  const std::vector<double>& zr;  // local frame z (true geometry, for the shape test)
  Stats& stats;
  std::vector<Object> accepted;
  // 2-D voxel columns (i, j at `voxel`, packed) holding a point just above the band: a
  // cluster reaching the band's top under them is the bottom of something taller (a crown).
  std::unordered_map<std::uint64_t, char> above;
};

std::uint64_t column_key(double x, double y, double v) {
  const auto i = std::int64_t(std::floor(x / v)) + (std::int64_t(1) << 30);
  const auto j = std::int64_t(std::floor(y / v)) + (std::int64_t(1) << 30);
  return (std::uint64_t(i) << 32) | std::uint64_t(j);
}

// True when most of the cluster's points in the band's top voxel layer have points right
// above the band over them (within one voxel column): a crown or building cut by the band.
bool continues_upward(const Context& c, const std::vector<std::uint32_t>& pts) {
  const double v = c.p.voxel, top = c.p.max_height - v;
  std::size_t in_top = 0, under = 0;
  for (std::uint32_t q : pts) {
    if (c.h[q] < top) continue;
    ++in_top;
    bool hit = false;
    for (int di = -1; di <= 1 && !hit; ++di)
      for (int dj = -1; dj <= 1 && !hit; ++dj)
        hit = c.above.count(column_key(c.x[q] + di * v, c.y[q] + dj * v, v)) > 0;
    under += hit;
  }
  return in_top >= 10 && under * 2 >= in_top;
}

Footprint footprint_of(const Context& c, const std::vector<std::uint32_t>& pts) {
  std::vector<Vector2d> xy(pts.size());
  for (std::size_t n = 0; n < pts.size(); ++n) xy[n] = Vector2d(c.x[pts[n]], c.y[pts[n]]);
  return min_area_rectangle(xy);
}

// Finer voxel (half the edge): parts of `pts` that only touch come apart. Returns the parts
// holding at least max(min_points, min_share of the points) when there are two or more.
std::vector<std::vector<std::uint32_t>> finer_parts(const Context& c, const std::vector<std::uint32_t>& pts,
                                                    double min_share = 0.1) {
  std::vector<std::vector<std::uint32_t>> parts;
  try {
    parts = cluster_points(pts, c.x, c.y, c.z, c.p.voxel / 2, Clustering::kGrid);
  } catch (const VoxelOverflow&) {
    return {};  // too large for the finer voxel: no finer parts
  }
  const std::size_t big = std::max(c.p.min_points, std::size_t(double(pts.size()) * min_share));
  std::vector<std::vector<std::uint32_t>> kept;
  for (auto& part : parts) {
    if (part.size() >= big) kept.push_back(std::move(part));
  }
  if (kept.size() < 2) kept.clear();
  return kept;
}

// Cut position across `axis` at a clear valley, leaving at least `min_side` on each side; NaN
// if none. A valley is an empty gap (a slab holding at most 35% of the median slab's points)
// or a drop of the top surface between two higher parts (the highest
// point of the bin at least max(0.3 m, 20% of the lower part) below the highest on either
// side): two car roofs side by side. The deepest valley wins, then the one nearest the middle.
double valley_cut(const Context& c, const std::vector<std::uint32_t>& pts, const Vector2d& axis,
                  double min_side) {
  double smin = 1e300, smax = -1e300;
  std::vector<double> s(pts.size());
  for (std::size_t n = 0; n < pts.size(); ++n) {
    s[n] = Vector2d(c.x[pts[n]], c.y[pts[n]]).dot(axis);
    smin = std::min(smin, s[n]);
    smax = std::max(smax, s[n]);
  }
  // Bins of 0.05 m, widened (up to 0.2 m) until they hold 20 points on average.
  double bin = 0.05;
  while (bin < 0.2 && double(pts.size()) * bin / std::max(1e-9, smax - smin) < 20) bin *= 2;
  const int nb = std::max(1, int(std::ceil((smax - smin) / bin)));
  std::vector<double> slab(std::size_t(nb), 0.0), top(std::size_t(nb), 0.0);
  for (std::size_t n = 0; n < pts.size(); ++n) {
    const int b = std::min(nb - 1, int((s[n] - smin) / bin));
    slab[std::size_t(b)] += 1;
    top[std::size_t(b)] = std::max(top[std::size_t(b)], double(c.h[pts[n]]));
  }
  std::vector<double> sorted = slab;
  std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<double> left(std::size_t(nb), 0.0), right(std::size_t(nb), 0.0);
  for (int b = 1; b < nb; ++b)
    left[std::size_t(b)] = std::max(left[std::size_t(b - 1)], top[std::size_t(b - 1)]);
  for (int b = nb - 2; b >= 0; --b)
    right[std::size_t(b)] = std::max(right[std::size_t(b + 1)], top[std::size_t(b + 1)]);
  double best_depth = 0, best_off = 1e300, cut = std::numeric_limits<double>::quiet_NaN();
  const double mid = 0.5 * (smin + smax);
  for (int b = 0; b < nb; ++b) {
    const double centre = smin + (b + 0.5) * bin;
    if (centre - smin < min_side || smax - centre < min_side) continue;
    const double lower = std::min(left[std::size_t(b)], right[std::size_t(b)]);
    const double drop = lower - top[std::size_t(b)];
    const bool empty = slab[std::size_t(b)] <= 0.35 * median;
    const bool dip = drop >= std::max(0.3, 0.2 * lower);
    if (!empty && !dip) continue;
    const double depth = empty ? lower : drop;
    const double off = std::abs(centre - mid);
    if (depth > best_depth + 1e-9 || (std::abs(depth - best_depth) <= 1e-9 && off < best_off)) {
      best_depth = depth;
      best_off = off;
      cut = centre;
    }
  }
  return cut;
}

void examine(Context& c, std::vector<std::uint32_t> pts, int depth) {
  const Params& p = c.p;
  if (pts.size() < p.min_points) {
    ++c.stats.rejected_small;
    return;
  }
  Object o;
  o.fp = footprint_of(c, pts);
  for (std::uint32_t q : pts) o.height = std::max(o.height, double(c.h[q]));
  if (o.fp.length < p.min_length || o.fp.width < p.min_width || o.height < p.min_height) {
    ++c.stats.rejected_small;
    return;
  }
  if (continues_upward(c, pts)) {
    // A vehicle close under a crown may hang on to its bottom: a finer voxel parts them.
    auto parts = depth < kMaxSplitDepth ? finer_parts(c, pts, 0.0) : std::vector<std::vector<std::uint32_t>>{};
    if (parts.empty() && depth < kMaxSplitDepth) {
      // Or hang on to a trunk: drop the columns under points just above the band and look
      // at what stays connected.
      std::vector<std::uint32_t> rest;
      for (std::uint32_t q : pts) {
        if (!c.above.count(column_key(c.x[q], c.y[q], c.p.voxel))) rest.push_back(q);
      }
      if (rest.size() >= c.p.min_points && rest.size() < pts.size()) {
        parts = cluster_points(rest, c.x, c.y, c.z, c.p.voxel, Clustering::kGrid);
      }
    }
    if (parts.empty()) {
      ++c.stats.rejected_canopy;
      return;
    }
    ++c.stats.splits;
    for (auto& part : parts) examine(c, std::move(part), depth + 1);
    return;
  }
  const bool too_long = o.fp.length > p.max_length, too_wide = o.fp.width > p.max_width;
  // Wider than two narrow vehicles, or oversized: objects that only touch come apart with a
  // finer voxel.
  const bool two_wide = o.fp.width > 2 * p.min_width + 1.0;
  if ((too_long || too_wide || two_wide) && depth < kMaxSplitDepth) {
    auto parts = finer_parts(c, pts);
    if (!parts.empty()) {
      ++c.stats.splits;
      for (auto& part : parts) examine(c, std::move(part), depth + 1);
      return;
    }
  }
  // Cuts the object at a clear valley across axis `a` (pieces at least `min_part` wide) and
  // examines both sides; false when there is no such valley.
  auto split_at_valley = [&](const Vector2d& a, double min_part) {
    const double cut = valley_cut(c, pts, a, min_part);
    if (std::isnan(cut)) return false;
    std::vector<std::uint32_t> lo, hi;
    for (std::uint32_t q : pts) (Vector2d(c.x[q], c.y[q]).dot(a) < cut ? lo : hi).push_back(q);
    ++c.stats.splits;
    examine(c, std::move(lo), depth + 1);
    examine(c, std::move(hi), depth + 1);
    return true;
  };
  if (two_wide && !too_long && depth < kMaxSplitDepth) {
    // Side by side and touching: a valley across the width.
    if (split_at_valley(Vector2d(-o.fp.axis.y(), o.fp.axis.x()), p.min_width)) return;
  }
  if (too_long || too_wide) {
    // Oversized: cut at a clear valley across the oversized axis.
    if (depth < kMaxSplitDepth) {
      const Vector2d a = too_wide ? Vector2d(-o.fp.axis.y(), o.fp.axis.x()) : o.fp.axis;
      if (split_at_valley(a, too_wide ? p.min_width : p.min_length)) return;
    }
    // No clean split: a vehicle with a bush against it stays a candidate (recall first) when
    // it is at most a quarter beyond the ranges.
    if (o.fp.length > 1.25 * p.max_length || o.fp.width > 1.25 * p.max_width) {
      ++c.stats.rejected_large;
      return;
    }
  }
  o.points = std::move(pts);
  c.accepted.push_back(std::move(o));
}

// ---------------------------------------------------------------------------------------
// Shape: vehicles are made of planes, vegetation is volumetric scatter.

// How much of an object's surface lies in locally planar neighbourhoods. Its points are
// averaged into `kPlanarVoxel` cubes (so the neighbour set is about as dense at 40 mm as at
// 80 mm pixel spacing, and bounded); for each centroid, its neighbours within `radius` (PCL's
// k-d tree) and the eigenvalues l1 >= l2 >= l3 of their covariance: the centroid is planar
// when sqrt(l3 / l2) <= `ratio` (a plane with noise sigma gives about sigma / (radius / 2); a
// line, a branch or a rail, has l2 ~ l3 and is not planar). Centroids with fewer than
// kPlanarMinNeighbours neighbours are not counted. share = planar / counted centroids (0 for
// an object too small to tell); area = planar centroids x kPlanarVoxel^2 (m^2, about the
// planar surface seen: a vehicle under a bush keeps its panels' area while the bush's points
// lower its share).
constexpr double kPlanarVoxel = 0.1;
constexpr int kPlanarMinNeighbours = 8;

Shape planar_shape(const Context& c, const std::vector<std::uint32_t>& pts, double radius, double ratio) {
  std::unordered_map<std::uint64_t, std::uint32_t> slot;
  std::vector<Vector3d> sum;
  std::vector<std::uint32_t> cnt;
  slot.reserve(pts.size());
  for (std::uint32_t q : pts) {
    const auto i = std::uint64_t(std::int64_t(std::floor(c.x[q] / kPlanarVoxel)) + (1 << 20));
    const auto j = std::uint64_t(std::int64_t(std::floor(c.y[q] / kPlanarVoxel)) + (1 << 20));
    const auto k = std::uint64_t(std::int64_t(std::floor(c.zr[q] / kPlanarVoxel)) + (1 << 20));
    const auto [it, fresh] = slot.emplace((i << 42) | (j << 21) | k, std::uint32_t(sum.size()));
    if (fresh) {
      sum.emplace_back(Vector3d::Zero());
      cnt.push_back(0);
    }
    sum[it->second] += Vector3d(c.x[q], c.y[q], c.zr[q]);
    ++cnt[it->second];
  }
  if (sum.size() < std::size_t(kPlanarMinNeighbours)) return {};
  // Centroids relative to the first one (float32 for PCL; slots in first-seen order: deterministic).
  const Vector3d ref = sum[0] / double(cnt[0]);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(sum.size());
  for (std::size_t u = 0; u < sum.size(); ++u) {
    const Vector3d m = sum[u] / double(cnt[u]) - ref;
    (*cloud)[u] = pcl::PointXYZ(float(m.x()), float(m.y()), float(m.z()));
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  std::size_t planar = 0, counted = 0;
  pcl::Indices nb;
  std::vector<float> d2;
  for (std::size_t u = 0; u < cloud->size(); ++u) {
    if (tree.radiusSearch((*cloud)[u], radius, nb, d2) < kPlanarMinNeighbours) continue;
    Vector3d mean = Vector3d::Zero();
    for (const auto k : nb) mean += (*cloud)[std::size_t(k)].getVector3fMap().cast<double>();
    mean /= double(nb.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto k : nb) {
      const Vector3d d = (*cloud)[std::size_t(k)].getVector3fMap().cast<double>() - mean;
      cov += d * d.transpose();
    }
    const Vector3d l =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
    ++counted;
    planar += l[0] <= ratio * ratio * l[1];  // ascending: l[0] is the smallest
  }
  Shape out;
  out.share = counted ? double(planar) / double(counted) : 0.0;
  out.area = double(planar) * kPlanarVoxel * kPlanarVoxel;
  return out;
}

// ---------------------------------------------------------------------------------------
// The phases of run(), in order: local frame, ground (DTM), objects, candidates.

// The tile in its local frame: bounds (tile coordinates), the integer-metre origin, and every
// point's coordinates minus the origin.
struct LocalFrame {
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  Vector3d origin = Vector3d::Zero();
  std::vector<double> x, y, z;
};

// DataError when a float32 coordinate column reaches magnitudes where float32 is not exact.
void check_float32_exact(const formats::PointCloud& tile, const LocalFrame& l, const std::string& name) {
  for (const char* axis : {"x", "y", "z"}) {
    const int a = axis[0] - 'x';
    const double mag = std::max(std::abs(l.lo[a]), std::abs(l.hi[a]));
    if (tile.type(axis) == formats::kFloat32 && mag >= kFloat32ExactLimit) {
      throw DataError(
          name, std::string("coordinate ") + axis + " is stored as float32 at magnitudes up to " +
                    fmt("%.0f", mag) + " m, where float32 steps are " +
                    fmt("%.3g", std::ldexp(1.0, int(std::floor(std::log2(mag))) - 23)) +
                    " m: the tile is already quantised; store coordinates as float64 (PCD TYPE F SIZE 8)");
    }
  }
}

LocalFrame local_frame(const formats::PointCloud& tile, const std::string& name) {
  LocalFrame l;
  for (const Vector3d& q : formats::finite_vectors(tile, name)) {
    l.lo = l.lo.cwiseMin(q);
    l.hi = l.hi.cwiseMax(q);
  }
  check_float32_exact(tile, l, name);
  l.origin = Vector3d(std::floor(0.5 * (l.lo.x() + l.hi.x())), std::floor(0.5 * (l.lo.y() + l.hi.y())),
                      std::floor(l.lo.z()));
  const std::size_t n = tile.size();
  const auto& tx = tile.col("x");
  const auto& ty = tile.col("y");
  const auto& tz = tile.col("z");
  l.x.resize(n);
  l.y.resize(n);
  l.z.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    l.x[i] = tx[i] - l.origin.x();
    l.y[i] = ty[i] - l.origin.y();
    l.z[i] = tz[i] - l.origin.z();
  }
  return l;
}

// Ground: the DTM, every point's cell, and the cells whose lowest point PMF calls ground.
struct Ground {
  Raster dtm;
  std::vector<std::uint32_t> cell_of;
  std::vector<char> is_ground_cell;
  // The filled cells the hole relaxation moves (relax_holes): all (empty vector) when there are
  // at most kCellsPerPoint per point; else, for a few points spread wide, those within
  // kNearData cells of a cell holding a point, where the DTM is read. 1000 sweeps over every
  // empty cell of such a tile took minutes (2e7 cells for 10 points); this bounds the work by
  // the points, not by the extent.
  std::vector<char> near_data;
  std::size_t cells() const { return std::size_t(dtm.nx) * std::size_t(dtm.ny); }
};

// The DTM raster over the tile's bounds, heights not set; DataError when it has too many cells.
Raster dtm_raster(const LocalFrame& l, const Params& params, const std::string& name) {
  Raster dtm;
  dtm.cell = params.cell;
  dtm.x0 = l.lo.x() - l.origin.x();
  dtm.y0 = l.lo.y() - l.origin.y();
  const double nxd = std::floor((l.hi.x() - l.lo.x()) / params.cell) + 1;
  const double nyd = std::floor((l.hi.y() - l.lo.y()) / params.cell) + 1;
  if (nxd * nyd > kMaxCells) {
    throw DataError(name, "the tile spans " + fmt("%.0f", l.hi.x() - l.lo.x()) + " m x " +
                              fmt("%.0f", l.hi.y() - l.lo.y()) + " m: " + fmt("%.3g", nxd * nyd) +
                              " DTM cells of " + fmt("%g", params.cell) + " m (limit " +
                              fmt("%.0g", kMaxCells) + "); split the tile or raise --cell");
  }
  // The work on the raster (filling, refining, bucketing) is per cell: bound it by the points.
  const double n = double(l.x.size());
  const double allowed = kFreeCells + kCellsPerPoint * n;
  if (nxd * nyd > allowed) {
    throw DataError(name, "its " + fmt("%.0f", n) + " points spread over " +
                              fmt("%.0f", l.hi.x() - l.lo.x()) + " m x " + fmt("%.0f", l.hi.y() - l.lo.y()) +
                              " m: " + fmt("%.3g", nxd * nyd) + " DTM cells of " + fmt("%g", params.cell) +
                              " m, more than such a sparse tile " + "may have (" + fmt("%.0g", kFreeCells) +
                              " + " + fmt("%.0f", kCellsPerPoint) + " per point = " + fmt("%.3g", allowed) +
                              "); crop the tile to where its points are, or raise --cell");
  }
  dtm.nx = int(nxd);
  dtm.ny = int(nyd);
  return dtm;
}

constexpr std::uint32_t kNoPoint = std::numeric_limits<std::uint32_t>::max();

// The cells within kNearData cells (Chebyshev distance) of a cell holding a point: a
// separable dilation of the occupied cells, O(cells).
std::vector<char> cells_near_data(const Raster& r, const std::vector<std::uint32_t>& lowest) {
  const int nx = r.nx, ny = r.ny;
  std::vector<char> rows(lowest.size(), 0), out(lowest.size(), 0);
  for (int j = 0; j < ny; ++j) {
    int last = -1 - 2 * kNearData;  // the last occupied column up to i
    for (int i = 0; i < nx + kNearData; ++i) {
      if (i < nx && lowest[r.at(i, j)] != kNoPoint) last = i;
      // Column t = i - D is near when an occupied column lies in [t - D, t + D = i].
      const int t = i - kNearData;
      if (t >= 0 && t < nx && last >= t - kNearData) rows[r.at(t, j)] = 1;
    }
  }
  for (int i = 0; i < nx; ++i) {
    int last = -1 - 2 * kNearData;
    for (int j = 0; j < ny + kNearData; ++j) {
      if (j < ny && rows[r.at(i, j)]) last = j;
      const int t = j - kNearData;
      if (t >= 0 && t < ny && last >= t - kNearData) out[r.at(i, t)] = 1;
    }
  }
  return out;
}

// The lowest point of every cell (kNoPoint for an empty one); sets g.cell_of.
std::vector<std::uint32_t> lowest_points(const LocalFrame& l, Ground& g) {
  const std::size_t n = l.x.size();
  std::vector<std::uint32_t> lowest(g.cells(), kNoPoint);
  g.cell_of.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = g.dtm.at(g.dtm.ix(l.x[i]), g.dtm.iy(l.y[i]));
    g.cell_of[i] = std::uint32_t(c);
    if (lowest[c] == kNoPoint || l.z[i] < l.z[lowest[c]]) lowest[c] = std::uint32_t(i);
  }
  return lowest;
}

// PCL's progressive morphological filter on the cells' lowest points: the minima it calls ground.
pcl::Indices pmf_ground(const pcl::PointCloud<pcl::PointXYZ>::Ptr& minima, const Params& params) {
  pcl::Indices ground_minima;
  pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> pmf;
  pmf.setInputCloud(minima);
  pmf.setCellSize(float(params.cell));
  pmf.setMaxWindowSize(int(std::ceil(params.max_window / params.cell)) > 0 ? float(params.max_window) : 1.f);
  // PCL's threshold is slope * (window step in m) * cell + initial distance.
  pmf.setSlope(float(params.terrain_slope / params.cell));
  pmf.setInitialDistance(float(params.initial_distance));
  pmf.setMaxDistance(float(params.max_distance));
  pmf.setBase(2.0f);
  pmf.setExponential(true);
  pmf.extract(ground_minima);
  return ground_minima;
}

// The ground cells (PMF on the cells' lowest points): their lowest z in the DTM, NaN elsewhere.
// DataError when fewer than min_ground_share of the occupied cells are ground.
void ground_cells(const LocalFrame& l, const std::vector<std::uint32_t>& lowest, const Params& params,
                  const std::string& name, Ground& g, Stats& stats) {
  const std::size_t cells = g.cells();
  pcl::PointCloud<pcl::PointXYZ>::Ptr minima(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<std::size_t> minima_cell;
  for (std::size_t c = 0; c < cells; ++c) {
    if (lowest[c] == kNoPoint) continue;
    const std::uint32_t i = lowest[c];
    minima->push_back(pcl::PointXYZ(float(l.x[i]), float(l.y[i]), float(l.z[i])));
    minima_cell.push_back(c);
  }
  const pcl::Indices ground_minima = pmf_ground(minima, params);
  g.dtm.z.assign(cells, std::numeric_limits<double>::quiet_NaN());
  g.is_ground_cell.assign(cells, 0);
  for (const auto m : ground_minima) {
    const std::size_t c = minima_cell[std::size_t(m)];
    g.dtm.z[c] = l.z[lowest[c]];
    g.is_ground_cell[c] = 1;
  }
  stats.ground_cells = ground_minima.size();
  const double share = double(ground_minima.size()) / double(std::max<std::size_t>(1, minima->size()));
  if (share < params.min_ground_share) {
    throw DataError(name,
                    "found ground in only " + fmt("%.1f", 100 * share) + "% of the " +
                        std::to_string(minima->size()) + " occupied " + fmt("%g", params.cell) +
                        " m cells (--min-ground-share " + fmt("%g", params.min_ground_share) +
                        "): no terrain to measure heights from (a tile of only vegetation or objects?)");
  }
}

// Refine: mean z of the points near the first surface, in the ground cells; the others filled
// again from them.
void refine_dtm(const LocalFrame& l, const Params& params, Ground& g, Stats& stats) {
  const std::size_t cells = g.cells();
  // The residuals against the first surface are averaged, so a point's position inside its
  // cell (on a slope) does not bias the cell-centre value.
  std::vector<double> sum(cells, 0.0);
  std::vector<std::uint32_t> cnt(cells, 0);
  for (std::size_t i = 0; i < l.x.size(); ++i) {
    const std::size_t c = g.cell_of[i];
    if (!g.is_ground_cell[c]) continue;
    const double d = l.z[i] - g.dtm.height(l.x[i], l.y[i]);
    if (std::abs(d) <= params.ground_tolerance) {
      sum[c] += d;
      ++cnt[c];
    }
  }
  for (std::size_t c = 0; c < cells; ++c) {
    g.dtm.z[c] = g.is_ground_cell[c] ? g.dtm.z[c] + (cnt[c] > 0 ? sum[c] / cnt[c] : 0.0)
                                     : std::numeric_limits<double>::quiet_NaN();
  }
  stats.filled_cells = fill_holes(g.dtm, g.near_data);
}

// The DTM (step 2 of detect.h) and every point's height above it and class (ground or other).
Ground find_ground(const LocalFrame& l, const Params& params, const std::string& name, Result& r) {
  Ground g;
  g.dtm = dtm_raster(l, params, name);
  r.stats.cells = g.cells();
  const std::vector<std::uint32_t> lowest = lowest_points(l, g);
  ground_cells(l, lowest, params, name, g, r.stats);
  const double holes = double(g.cells() - r.stats.ground_cells);
  if (holes > kCellsPerPoint * double(l.x.size())) g.near_data = cells_near_data(g.dtm, lowest);
  fill_holes(g.dtm, g.near_data);
  refine_dtm(l, params, g, r.stats);
  const std::size_t n = l.x.size();
  r.height.resize(n);
  r.classes.assign(n, kClassOther);
  for (std::size_t i = 0; i < n; ++i) {
    r.height[i] = float(l.z[i] - g.dtm.height(l.x[i], l.y[i]));
    if (r.height[i] < params.min_object_height) {
      r.classes[i] = kClassGround;
      ++r.stats.ground_points;
    }
  }
  return g;
}

// Shape: vegetation (bush groups, crown pieces) is not made of planes; a vehicle is, even
// under a bush (then its planar area counts).
void drop_unplanar(Context& ctx, const Params& params, Stats& stats) {
  std::vector<Object> kept;
  for (Object& o : ctx.accepted) {
    o.shape = planar_shape(ctx, o.points, params.planar_radius, params.planar_ratio);
    if (params.min_planarity > 0 && o.shape.share < params.min_planarity &&
        o.shape.area < params.min_planar_area) {
      ++stats.rejected_shape;
    } else {
      kept.push_back(std::move(o));
    }
  }
  ctx.accepted.swap(kept);
}

// The objects (steps 3 and 4 of detect.h): the band's clusters that pass the vehicle tests
// (examine) and the shape test.
std::vector<Object> find_objects(const LocalFrame& l, const Params& params, const std::string& name, Result& r) {
  const std::size_t n = l.x.size();
  std::vector<std::uint32_t> band;
  for (std::size_t i = 0; i < n; ++i) {
    if (r.height[i] >= params.min_object_height && r.height[i] <= params.max_height)
      band.push_back(std::uint32_t(i));
  }
  r.stats.band_points = band.size();
  std::vector<double> hz(n);  // clustering in (x, y, height): the band is a flat slab
  for (std::size_t i = 0; i < n; ++i) hz[i] = r.height[i];
  Context ctx{params, l.x, l.y, hz, r.height, l.z, r.stats, {}, {}};
  for (std::size_t i = 0; i < n; ++i) {
    if (r.height[i] > params.max_height && r.height[i] <= params.max_height + 2 * params.voxel) {
      ctx.above.emplace(column_key(l.x[i], l.y[i], params.voxel), 1);
    }
  }
  try {
    auto clusters = cluster_points(band, l.x, l.y, hz, params.voxel, params.clustering);
    r.stats.clusters = clusters.size();
    for (auto& cl : clusters) examine(ctx, std::move(cl), 0);
  } catch (const VoxelOverflow& e) {
    throw DataError(name, "the points between --min-object-height and --max-height span " +
                              fmt("%.6g", e.extent) + " m, more than " + std::to_string(kVoxelMask - 1) +
                              " clustering voxels along an axis of --voxel " + fmt("%g", params.voxel) +
                              " m: raise --voxel (or crop the tile)");
  }
  drop_unplanar(ctx, params, r.stats);
  return std::move(ctx.accepted);
}

// The points bucketed by DTM cell (for cropping): cell c holds points[start[c] .. start[c + 1]).
struct CellPoints {
  std::vector<std::uint32_t> start, points;
};

CellPoints bucket_by_cell(const std::vector<std::uint32_t>& cell_of, std::size_t cells) {
  const std::size_t n = cell_of.size();
  CellPoints b;
  b.start.assign(cells + 1, 0);
  b.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) ++b.start[cell_of[i] + 1];
  for (std::size_t c = 0; c < cells; ++c) b.start[c + 1] += b.start[c];
  std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) b.points[fill[cell_of[i]]++] = std::uint32_t(i);
  return b;
}

// Ground truth of the tile: a point's vehicle instance (0 = none: no instance field, or a
// label field that says not a vehicle) and every vehicle's number of points.
struct TileTruth {
  const formats::PointCloud& tile;
  const Params& params;
  bool has_instance = false, has_label = false;
  std::map<std::uint32_t, std::size_t> instance_points;

  TileTruth(const formats::PointCloud& t, const Params& p)
      : tile(t), params(p), has_instance(t.has(p.instance_field)), has_label(t.has(p.label_field)) {
    if (!has_instance) return;
    for (std::size_t i = 0; i < tile.size(); ++i) {
      if (const std::uint32_t id = (*this)(i)) ++instance_points[id];
    }
  }
  std::uint32_t operator()(std::size_t i) const {
    if (!has_instance) return 0;
    if (has_label && std::uint32_t(tile.col(params.label_field)[i]) != formats::kLabelTarget) return 0;
    return std::uint32_t(tile.col(params.instance_field)[i]);
  }
};

// Least-squares ground plane z = a dx + b dy + c under the footprint (+2 m; ground cells
// only), (dx, dy) from the footprint centre; (0, 0, DTM height) when too few cells.
Vector3d ground_plane(const Ground& g, const Footprint& fp) {
  const Raster& dtm = g.dtm;
  const Vector2d u = fp.axis, v(-u.y(), u.x());
  const double hl = 0.5 * fp.length + 2.0, hw = 0.5 * fp.width + 2.0;
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  const double ext = hl + hw;
  const int i0 = dtm.ix(fp.centre.x() - ext), i1 = dtm.ix(fp.centre.x() + ext);
  const int j0 = dtm.iy(fp.centre.y() - ext), j1 = dtm.iy(fp.centre.y() + ext);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const Vector2d cc(dtm.x0 + (i + 0.5) * dtm.cell, dtm.y0 + (j + 0.5) * dtm.cell);
      const Vector2d d = cc - fp.centre;
      if (std::abs(d.dot(u)) > hl || std::abs(d.dot(v)) > hw || !g.is_ground_cell[dtm.at(i, j)]) continue;
      const Eigen::Vector3d row(d.x(), d.y(), 1.0);
      ata += row * row.transpose();
      atb += row * dtm.z[dtm.at(i, j)];
    }
  Vector3d plane(0, 0, dtm.height(fp.centre.x(), fp.centre.y()));
  if (ata(2, 2) >= 3 && std::abs(ata.determinant()) > 1e-9) plane = ata.ldlt().solve(atb);
  return plane;
}

// A candidate's rigid frame: rotation (columns = its axes in the local frame) and origin.
struct Frame {
  Eigen::Matrix3d R;
  Vector3d O;
  Vector3d to_frame(const LocalFrame& l, std::uint32_t q) const {
    return R.transpose() * (Vector3d(l.x[q], l.y[q], l.z[q]) - O);
  }
};

// z = the normal of the ground plane under the object, x = the long axis of its footprint
// refitted in that plane, origin on the plane under the footprint centre.
Frame object_frame(const LocalFrame& l, const Ground& g, const Object& o) {
  const Vector3d plane = ground_plane(g, o.fp);
  const Vector2d u = o.fp.axis;
  const Vector3d normal = Vector3d(-plane.x(), -plane.y(), 1.0).normalized();
  Vector3d ax(u.x(), u.y(), 0.0);
  ax = (ax - ax.dot(normal) * normal).normalized();
  const Vector3d ay = normal.cross(ax);
  Frame f;
  f.R.col(0) = ax;
  f.R.col(1) = ay;
  f.R.col(2) = normal;
  f.O = Vector3d(o.fp.centre.x(), o.fp.centre.y(), plane.z());
  // The footprint again, in the ground plane: on a slope the top view of a tall object is
  // sheared, and a small axis error is a large width error over a long vehicle.
  std::vector<Vector2d> in_plane(o.points.size());
  for (std::size_t m = 0; m < o.points.size(); ++m) in_plane[m] = f.to_frame(l, o.points[m]).head<2>();
  const Footprint fp = min_area_rectangle(in_plane);
  Vector3d ax2 = f.R * Vector3d(fp.axis.x(), fp.axis.y(), 0.0);
  if (ax2.x() < 0 || (ax2.x() == 0 && ax2.y() < 0)) ax2 = -ax2;
  f.R.col(0) = ax2;
  f.R.col(1) = normal.cross(ax2);
  return f;
}

// Recentres the frame on the object's extent in it; sets the candidate's size, heading,
// pose and the object's numbers.
void place_candidate(const LocalFrame& l, const Object& o, const Vector3d& origin, Frame& f, Candidate& c) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300, zmax = 0;
  for (std::uint32_t q : o.points) {
    const Vector3d p = f.to_frame(l, q);
    xmin = std::min(xmin, p.x());
    xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  f.O += f.R * Vector3d(0.5 * (xmin + xmax), 0.5 * (ymin + ymax), 0.0);
  for (std::uint32_t q : o.points) zmax = std::max(zmax, f.to_frame(l, q).z());
  c.length = xmax - xmin;
  c.width = ymax - ymin;
  c.height = zmax;
  c.heading = std::atan2(f.R(1, 0), f.R(0, 0));
  c.object_points = o.points.size();
  c.density = c.length * c.width > 0 ? double(c.object_points) / (c.length * c.width) : 0.0;
  c.planarity = o.shape.share;
  c.planar_area = o.shape.area;
  c.to_tile.topLeftCorner<3, 3>() = f.R;
  c.to_tile.topRightCorner<3, 1>() = f.O + origin;
}

// The rows of the points inside the candidate's box (footprint + margin, from -margin to
// height + margin in its frame), ascending, and their coordinates in the frame.
std::vector<std::size_t> crop_rows(const LocalFrame& l, const Ground& g, const CellPoints& cells,
                                   const Frame& f, const Candidate& c, const Params& params,
                                   std::vector<Vector3d>* coordinates) {
  const Raster& dtm = g.dtm;
  const double cx = 0.5 * c.length + params.margin, cy = 0.5 * c.width + params.margin;
  const double ctop = c.height + params.margin, cbot = -params.margin;
  const double reach = cx + cy + params.margin;
  std::vector<std::size_t> keep;
  std::vector<Vector3d> local;
  for (int j = dtm.iy(f.O.y() - reach); j <= dtm.iy(f.O.y() + reach); ++j)
    for (int i = dtm.ix(f.O.x() - reach); i <= dtm.ix(f.O.x() + reach); ++i) {
      const std::size_t cc = dtm.at(i, j);
      for (std::uint32_t k = cells.start[cc]; k < cells.start[cc + 1]; ++k) {
        const std::uint32_t q = cells.points[k];
        const Vector3d p = f.to_frame(l, q);
        if (std::abs(p.x()) <= cx && std::abs(p.y()) <= cy && p.z() >= cbot && p.z() <= ctop) {
          keep.push_back(q);
          local.push_back(p);
        }
      }
    }
  std::vector<std::size_t> order(keep.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return keep[a] < keep[b]; });
  std::vector<std::size_t> rows(keep.size());
  coordinates->resize(keep.size());
  for (std::size_t m = 0; m < order.size(); ++m) {
    rows[m] = keep[order[m]];
    (*coordinates)[m] = local[order[m]];
  }
  return rows;
}

// The crop: the tile's rows with every field, x y z replaced by the frame's coordinates
// (float32), sensor and normal directions rotated into the frame.
formats::PointCloud crop_cloud(const formats::PointCloud& tile, const std::vector<std::size_t>& rows,
                               const std::vector<Vector3d>& local, const Eigen::Matrix3d& R) {
  formats::PointCloud cloud = tile.select(rows);
  auto& lx = cloud.add("x", formats::kFloat32);
  auto& ly = cloud.add("y", formats::kFloat32);
  auto& lz = cloud.add("z", formats::kFloat32);
  for (std::size_t m = 0; m < rows.size(); ++m) {
    lx[m] = local[m].x();
    ly[m] = local[m].y();
    lz[m] = local[m].z();
  }
  for (const formats::Fields3& f : {formats::kSensorFields, formats::kNormalFields}) {
    if (!formats::has_fields(cloud, f)) continue;
    auto& dx = cloud.col(f[0]);
    auto& dy = cloud.col(f[1]);
    auto& dz = cloud.col(f[2]);
    for (std::size_t m = 0; m < cloud.size(); ++m) {
      const Vector3d d = R.transpose() * Vector3d(dx[m], dy[m], dz[m]);
      dx[m] = d.x();
      dy[m] = d.y();
      dz[m] = d.z();
    }
  }
  return cloud;
}

// The candidate's truth: the vehicle with the most points in the object (not merely in the
// crop around it), its points in the crop (`rows`), coverage and purity.
void candidate_truth(const TileTruth& truth, const Object& o, const std::vector<std::size_t>& rows,
                     Candidate& c) {
  c.has_truth = true;
  std::map<std::uint32_t, std::size_t> in_object;
  for (std::uint32_t q : o.points) {
    if (const std::uint32_t id = truth(q)) ++in_object[id];
  }
  std::size_t best = 0;
  for (const auto& [id, cnt] : in_object) {
    if (cnt > best) {
      best = cnt;
      c.truth.instance = id;
    }
  }
  if (c.truth.instance != 0) {
    for (std::size_t q : rows) c.truth.points += truth(q) == c.truth.instance;
    c.truth.coverage = double(c.truth.points) / double(truth.instance_points.at(c.truth.instance));
    c.truth.purity = double(best) / double(o.points.size());
  }
}

// Every labelled vehicle of the tile with the candidates whose truth it is.
std::vector<InstanceTruth> instances_of(const TileTruth& truth, const std::vector<Candidate>& candidates) {
  std::vector<InstanceTruth> out;
  for (const auto& [id, cnt] : truth.instance_points) {
    InstanceTruth it;
    it.instance = id;
    it.points = cnt;
    for (const auto& c : candidates) {
      if (c.truth.instance == id) it.candidates.push_back(c.id);
    }
    out.push_back(std::move(it));
  }
  return out;
}

// The candidates (step 5 of detect.h), sorted by their centre (x, then y) and numbered; the
// objects' points become kClassCandidate.
void extract_candidates(const formats::PointCloud& tile, const LocalFrame& l, const Ground& g,
                        const std::vector<Object>& objects, const Params& params, Result& r) {
  const CellPoints cells = bucket_by_cell(g.cell_of, g.cells());
  const TileTruth truth(tile, params);
  r.has_truth = truth.has_instance;
  struct Pending {
    Candidate c;
    Vector3d centre;
  };
  std::vector<Pending> pending;
  for (const Object& o : objects) {
    for (std::uint32_t q : o.points) r.classes[q] = kClassCandidate;
    Frame f = object_frame(l, g, o);
    Pending pd;
    Candidate& c = pd.c;
    place_candidate(l, o, r.origin, f, c);
    pd.centre = f.O + r.origin;
    std::vector<Vector3d> local;
    const std::vector<std::size_t> rows = crop_rows(l, g, cells, f, c, params, &local);
    c.cloud = crop_cloud(tile, rows, local, f.R);
    if (truth.has_instance) candidate_truth(truth, o, rows, c);
    pending.push_back(std::move(pd));
  }
  std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
    return a.centre.x() < b.centre.x() || (a.centre.x() == b.centre.x() && a.centre.y() < b.centre.y());
  });
  for (std::size_t k = 0; k < pending.size(); ++k) {
    char id[32];
    std::snprintf(id, sizeof id, "c%04zu", k + 1);
    pending[k].c.id = id;
    r.candidates.push_back(std::move(pending[k].c));
  }
  if (truth.has_instance) r.instances = instances_of(truth, r.candidates);
}

}  // namespace

void validate(const Params& p) {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw common::UsageError(what);
  };
  need(p.cell > 0 && std::isfinite(p.cell), "--cell must be > 0");
  need(p.max_window > p.cell, "--max-window must be larger than --cell");
  need(p.terrain_slope > 0, "--terrain-slope must be > 0");
  need(p.initial_distance >= 0 && p.max_distance >= p.initial_distance,
       "need 0 <= --initial-distance <= --max-distance");
  need(p.ground_tolerance > 0, "--ground-tolerance must be > 0");
  need(p.voxel >= 1e-3 && p.voxel <= 100, "--voxel must be in [1 mm, 100 m]");
  need(p.min_object_height >= 0, "--min-object-height must be >= 0");
  need(p.min_length >= 0 && p.max_length >= p.min_length, "need 0 <= --min-length <= --max-length");
  need(p.min_width >= 0 && p.max_width >= p.min_width, "need 0 <= --min-width <= --max-width");
  need(p.min_height >= 0 && p.max_height >= p.min_height, "need 0 <= --min-height <= --max-height");
  need(p.max_height > p.min_object_height, "--max-height must exceed --min-object-height");
  need(p.margin >= 0, "--margin must be >= 0");
  need(p.min_points >= 3, "--min-points must be >= 3");
  need(p.min_planarity >= 0 && p.min_planarity <= 1, "--min-planarity must be in [0, 1] (0 = off)");
  need(p.planar_radius >= 2 * 0.1 && std::isfinite(p.planar_radius), "--planar-radius must be >= 0.2 m");
  need(p.planar_ratio > 0 && p.planar_ratio < 1, "planar_ratio must be in (0, 1)");
  need(p.min_planar_area >= 0, "--min-planar-area must be >= 0");
  need(p.min_ground_share > 0 && p.min_ground_share <= 1, "--min-ground-share must be in (0, 1]");
}

double voxel_for_density(double d) {
  return d > 0 ? std::max(kDenseVoxel, kVoxelDensityScale / std::sqrt(d)) : kDenseVoxel;
}

double planarity_for_density(double d) { return d >= kPlanarityDensity ? kDensePlanarity : 0.0; }

double cell_for_density(double d) {
  return d > 0 ? std::clamp(std::sqrt(kCellReturns / d), kDenseCell, kSparseCell) : kDenseCell;
}

namespace {

// Points per occupied 1 m cell of the local frame (the same cells as measure_density's `all`).
// Before the ground, the extent is not yet bounded (find_ground refuses too many DTM cells), so
// the occupied cells are counted by sorting the points' cell coordinates: memory O(points).
double occupied_density(const LocalFrame& l) {
  const std::size_t n = l.x.size();
  if (n == 0) return 0.0;
  const double x0 = l.lo.x() - l.origin.x(), y0 = l.lo.y() - l.origin.y();
  std::vector<std::pair<double, double>> cell(n);
  for (std::size_t i = 0; i < n; ++i) {
    cell[i] = {std::floor(std::max(0.0, l.x[i] - x0)), std::floor(std::max(0.0, l.y[i] - y0))};
  }
  std::sort(cell.begin(), cell.end());
  const std::size_t cells = std::size_t(std::unique(cell.begin(), cell.end()) - cell.begin());
  return double(n) / double(cells);
}

// The tile's density on 1 m cells of the local frame (after the ground: a cell is open ground
// when every point in it lies below min_object_height).
Density measure_density(const formats::PointCloud& tile, const LocalFrame& l, const Result& r,
                        const Params& params) {
  Density d;
  const std::size_t n = l.x.size();
  const double x0 = l.lo.x() - l.origin.x(), y0 = l.lo.y() - l.origin.y();
  const std::size_t nx = std::size_t(std::floor(l.hi.x() - l.lo.x())) + 1;
  const std::size_t ny = std::size_t(std::floor(l.hi.y() - l.lo.y())) + 1;
  std::vector<std::uint32_t> count(nx * ny, 0), first(nx * ny, 0);
  std::vector<char> raised(nx * ny, 0);
  const std::vector<double>* ret = tile.has("return_number") ? &tile.col("return_number") : nullptr;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t cx = std::min(nx - 1, std::size_t(std::max(0.0, l.x[i] - x0)));
    const std::size_t cy = std::min(ny - 1, std::size_t(std::max(0.0, l.y[i] - y0)));
    const std::size_t c = cy * nx + cx;
    ++count[c];
    if (ret && (*ret)[i] <= 1) ++first[c];
    if (r.height[i] >= params.min_object_height) raised[c] = 1;
  }
  std::size_t open_points = 0, firsts = 0;
  for (std::size_t c = 0; c < count.size(); ++c) {
    if (!count[c]) continue;
    ++d.occupied_cells;
    firsts += first[c];
    if (!raised[c]) {
      ++d.open_cells;
      open_points += count[c];
    }
  }
  d.all = d.occupied_cells ? double(n) / double(d.occupied_cells) : 0.0;
  // Open ground needs a few cells to say anything (a tile of only objects has none).
  constexpr std::size_t kFewestOpenCells = 10;
  if (d.open_cells >= kFewestOpenCells) d.ground = double(open_points) / double(d.open_cells);
  if (ret && d.occupied_cells) d.first = double(firsts) / double(d.occupied_cells);
  return d;
}

}  // namespace

Result run(const formats::PointCloud& tile, const Params& given, const std::string& name) {
  validate(given);
  Params params = given;
  tile.require({"x", "y", "z"}, name, "is this a point cloud?");
  const std::size_t n = tile.size();
  if (n == 0) throw DataError(name, "the tile has no points");
  if (n > std::numeric_limits<std::uint32_t>::max() / 2) throw DataError(name, "more than 2^31 points");
  Result r;
  r.stats.points = n;
  const LocalFrame l = local_frame(tile, name);
  r.origin = l.origin;

  // The DTM cell from the density of all points (the ground is not known yet), detect.md §7.
  const double before_ground = occupied_density(l);
  if (params.cell_from_density) params.cell = cell_for_density(before_ground);
  validate(params);  // a ruled cell must still leave the ground filter's windows valid
  auto t0 = std::chrono::steady_clock::now();
  const Ground g = find_ground(l, params, name, r);
  r.stats.seconds_ground = seconds_since(t0);

  // The density rule (detect.h): the clustering voxel and the shape test from the tile's density.
  r.density = measure_density(tile, l, r, params);
  r.density.rule = r.density.ground ? *r.density.ground : r.density.all;
  if (params.voxel_from_density) params.voxel = voxel_for_density(r.density.rule);
  if (params.planarity_from_density) params.min_planarity = planarity_for_density(r.density.rule);
  r.density.voxel = params.voxel;
  r.density.min_planarity = params.min_planarity;
  r.density.voxel_by_rule = params.voxel_from_density;
  r.density.planarity_by_rule = params.planarity_from_density;
  r.density.cell = params.cell;
  r.density.cell_by_rule = params.cell_from_density;

  t0 = std::chrono::steady_clock::now();
  const std::vector<Object> objects = find_objects(l, params, name, r);
  r.stats.seconds_objects = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  extract_candidates(tile, l, g, objects, params, r);
  r.stats.seconds_candidates = seconds_since(t0);
  return r;
}

formats::PointCloud classification_cloud(const formats::PointCloud& tile, const Result& result) {
  formats::PointCloud out;
  const std::size_t n = tile.size();
  out.resize(n);
  auto& x = out.add("x", formats::kFloat32);
  auto& y = out.add("y", formats::kFloat32);
  auto& z = out.add("z", formats::kFloat32);
  auto& h = out.add("height", formats::kFloat32);
  auto& cls = out.add("class", formats::kUint8);
  auto& red = out.add("red", formats::kUint8);
  auto& green = out.add("green", formats::kUint8);
  auto& blue = out.add("blue", formats::kUint8);
  const auto& tx = tile.col("x");
  const auto& ty = tile.col("y");
  const auto& tz = tile.col("z");
  static const unsigned char kColour[4][3] = {{128, 128, 128}, {150, 110, 60}, {40, 160, 40}, {230, 30, 30}};
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = tx[i] - result.origin.x();
    y[i] = ty[i] - result.origin.y();
    z[i] = tz[i] - result.origin.z();
    h[i] = result.height[i];
    cls[i] = result.classes[i];
    const auto* col = kColour[std::min<int>(result.classes[i], 3)];
    red[i] = col[0];
    green[i] = col[1];
    blue[i] = col[2];
  }
  return out;
}

}  // namespace canopy::detect
