// tools/meshsize's measures (upright.h): the box of the faces' vertices, shared by the size line
// and the up check (stop 68), and the check on meshes built here.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "canopy/formats/mesh_import.h"
#include "meshsize/upright.h"

using canopy::formats::TriangleMesh;
namespace ms = canopy::meshsize;

namespace {

// A closed box [0, l] x [0, w] x [0, h] of 12 triangles, plus `extra` vertices no face uses.
TriangleMesh box_mesh(double l, double w, double h, const std::vector<Eigen::Vector3d>& extra = {}) {
  TriangleMesh m;
  for (double x : {0.0, l})
    for (double y : {0.0, w})
      for (double z : {0.0, h}) m.vertices.emplace_back(x, y, z);
  // Vertex index = 4 x + 2 y + z (each 0 or 1).
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& q : quads) {
    m.faces.push_back({q[0], q[1], q[2]});
    m.faces.push_back({q[0], q[2], q[3]});
  }
  for (const auto& v : extra) m.vertices.push_back(v);
  return m;
}

// A wedge: a 4 x 2 base at z = 0, its top edge at z = 1.5 over the base's middle line along x (a
// roof: the top is not the bottom's mirror image).
TriangleMesh wedge() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {4, 0, 0}, {4, 2, 0}, {0, 2, 0}, {0, 1, 1.5}, {4, 1, 1.5}};
  m.faces = {{0, 2, 1}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4}, {3, 4, 5}, {3, 5, 2}, {0, 4, 3}, {1, 2, 5}};
  return m;
}

}  // namespace

TEST_CASE("meshsize: bounds() is the box of the vertices the faces use") {
  const TriangleMesh m = box_mesh(4.5, 1.8, 1.5, {{100, -50, 7}});  // one vertex no face uses
  const ms::Box b = ms::bounds(m, m.vertices);
  CHECK(b.lo == Eigen::Vector3d(0, 0, 0));
  CHECK(b.hi == Eigen::Vector3d(4.5, 1.8, 1.5));
  CHECK(b.size() == Eigen::Vector3d(4.5, 1.8, 1.5));
  // In another frame (the vertices given, not the mesh's own): y up turned to z up.
  const std::vector<Eigen::Vector3d> turned = ms::render_frame(m, 1.0, "y", "box");
  const ms::Box t = ms::bounds(m, turned);
  CHECK(t.lo == Eigen::Vector3d(0, -1.5, 0));
  CHECK(t.hi == Eigen::Vector3d(4.5, 0, 1.8));
  // One triangle, negative coordinates, units scaled by render_frame.
  TriangleMesh one;
  one.vertices = {{-1000, 20, 5}, {-3000, 10, -5}, {-2000, 40, 0}};
  one.faces = {{0, 1, 2}};
  const ms::Box o = ms::bounds(one, ms::render_frame(one, 1e-3, "z", "one"));
  CHECK(o.lo.isApprox(Eigen::Vector3d(-3, 0.01, -0.005)));
  CHECK(o.hi.isApprox(Eigen::Vector3d(-1, 0.04, 0.005)));
}

TEST_CASE("meshsize: upright() measures in the box it is given") {
  const TriangleMesh w = wedge();
  const ms::Upright u = ms::upright(w, w.vertices, ms::bounds(w, w.vertices));
  CHECK(u.size == Eigen::Vector3d(4, 2, 1.5));
  CHECK_FALSE(u.on_end);
  CHECK(u.symmetry < 0.85);  // a roof: not its floor's mirror image
  CHECK(u.ok());
  // Lying on its side (read with the wrong up axis): mirror-symmetric about a horizontal plane.
  const std::vector<Eigen::Vector3d> side = ms::render_frame(w, 1.0, "y", "wedge");
  const ms::Upright s = ms::upright(w, side, ms::bounds(w, side));
  CHECK(s.size.isApprox(Eigen::Vector3d(4, 1.5, 2)));
  CHECK(s.on_side);
  CHECK_FALSE(s.ok());
  CHECK_THAT(ms::up_problem("y", s, u), Catch::Contains("with --up z (MESH_UP=z) it stands upright"));
  CHECK(ms::fixed(0.6789, 2) == "0.68");
  CHECK(ms::fixed(12.5, 0) == "12");  // printf's rounding: half to even
  // A plain box is as symmetric either way.
  const TriangleMesh b = box_mesh(4, 2, 1.8);
  CHECK(ms::upright(b, b.vertices, ms::bounds(b, b.vertices)).on_side);
}
