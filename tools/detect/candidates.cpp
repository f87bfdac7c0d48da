#include "detect/candidates.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <utility>

#include "canopy/formats/cloud_eigen.h"

namespace canopy::detect {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

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

// The crop: the tile's rows with every field but the truth (kTruthFields), x y z replaced by the frame's
// coordinates (float32), sensor and normal directions rotated into the frame.
formats::PointCloud crop_cloud(const formats::PointCloud& tile, const std::vector<std::size_t>& rows,
                               const std::vector<Vector3d>& local, const Eigen::Matrix3d& R) {
  formats::PointCloud cloud = tile.select(rows);
  for (const char* f : kTruthFields) {
    if (cloud.has(f)) cloud.remove(f);
  }
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

}  // namespace

Placed place_candidates(const formats::PointCloud& tile, const LocalFrame& l, const Ground& g,
                        const std::vector<Object>& objects, const Params& params,
                        const std::vector<std::int32_t>& examined, const std::vector<TrimRest>& trims) {
  const CellPoints cells = bucket_by_cell(g.cell_of, g.cells());
  struct Pending {
    Candidate c;
    Vector3d centre;
  };
  std::vector<Pending> pending;
  for (const Object& o : objects) {
    Frame f = object_frame(l, g, o);
    Pending pd;
    Candidate& c = pd.c;
    place_candidate(l, o, l.origin, f, c);
    pd.centre = f.O + l.origin;
    std::vector<Vector3d> local;
    const std::vector<std::size_t> rows = crop_rows(l, g, cells, f, c, params, &local);
    c.cloud = crop_cloud(tile, rows, local, f.R);
    if (params.object_field) {
      // 1: a row of the object (o.points, rows of the tile, as the crop's rows); 2: a row last
      // examined outside the object's lineage (given to something else), 3 when that examination
      // is the leftover of a trim whose vehicle piece the object came out of; 0: the rest.
      std::vector<std::uint32_t> own = o.points;
      std::sort(own.begin(), own.end());
      auto in_lineage = [&](std::int32_t e) {
        return std::find(o.lineage.begin(), o.lineage.end(), e) != o.lineage.end();
      };
      std::vector<TrimRest> cut;  // the trims that cut this object
      for (const TrimRest& t : trims)
        if (in_lineage(t.piece)) cut.push_back(t);
      auto& mark = c.cloud.add(kObjectField, formats::kUint8);  // replaces a tile's own `object`
      for (std::size_t m = 0; m < rows.size(); ++m) {
        const auto q = static_cast<std::uint32_t>(rows[m]);
        if (std::binary_search(own.begin(), own.end(), q)) {
          mark[m] = kObjectOwn;
        } else if (q < examined.size() && examined[q] >= 0 && !in_lineage(examined[q])) {
          const std::int32_t e = examined[q];
          mark[m] = std::any_of(cut.begin(), cut.end(), [e](const TrimRest& t) { return t.holds(e); })
                        ? kObjectTrimmed
                        : kObjectOther;
        } else {
          mark[m] = kObjectContext;
        }
      }
    }
    pending.push_back(std::move(pd));
  }
  std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
    return a.centre.x() < b.centre.x() || (a.centre.x() == b.centre.x() && a.centre.y() < b.centre.y());
  });
  Placed out;
  for (std::size_t k = 0; k < pending.size(); ++k) {
    char id[32];
    std::snprintf(id, sizeof id, "c%04zu", k + 1);
    pending[k].c.id = id;
    out.candidates.push_back(std::move(pending[k].c));
  }
  return out;
}

}  // namespace canopy::detect
