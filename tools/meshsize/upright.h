// meshsize's measures of a vehicle mesh in rangetrace's frame: its box and the up check
// (docs/decisions/user-modelbase.md §8, stop 67; main.cpp's comment says how the check works).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "canopy/formats/mesh_import.h"

namespace canopy::meshsize {

// The mesh's vertices in rangetrace's frame: scaled to metres, y up turned to z up (as
// sim/src/models.cpp). A non-finite vertex is a DataError naming `input`.
std::vector<Eigen::Vector3d> render_frame(const formats::TriangleMesh& mesh, double scale,
                                          const std::string& up, const std::string& input);

// An axis-aligned box.
struct Box {
  Eigen::Vector3d lo, hi;
  Eigen::Vector3d size() const { return hi - lo; }
};

// The box of the vertices `v` (the mesh's, in one frame) that the mesh's faces use: a vertex no
// face uses is not part of the vehicle. The size line's extent and the up check's grid.
Box bounds(const formats::TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& v);

// The up check's answer for the mesh in one frame.
struct Upright {
  Eigen::Vector3d size;
  double symmetry = 0;  // horizontal-plane mirror symmetry, 0..1
  bool on_side = false, on_end = false;
  bool ok() const { return !on_side && !on_end; }
};

// Samples the surface of the mesh with vertices `v` and box `box` (bounds(mesh, v)) and scores
// its best horizontal mirror plane (main.cpp's comment).
Upright upright(const formats::TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& v, const Box& box);

// `x` with `digits` decimals ("%.*f"), as the messages give numbers.
std::string fixed(double x, int digits);

// What is wrong with the mesh read with --up `up` (u), and the remedy (other: read with the
// other up axis).
std::string up_problem(const std::string& up, const Upright& u, const Upright& other);

}  // namespace canopy::meshsize
