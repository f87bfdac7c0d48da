// meshsize: the axis-aligned extent of a vehicle mesh (.ply/.obj/.stl) in metres, in the frame
// rangetrace renders it in (--units scale, --up y turned to z up exactly as rangetrace --model
// does). Prints one line "length width height" (x, y and z extents); make's user-modelbase
// (mk/usermb.mk) chooses each entry's crop box from it.
//
// The up check (--up-check; docs/decisions/user-modelbase.md §8, stop 67): a y-up mesh read as
// z up (or a z-up one read with --up y) lies on its side, or stands on its nose, and its extent
// does not tell (4.37 x 1.96 x 2.02 m against 4.37 x 2.02 x 1.96). Vehicles are mirror-symmetric
// left to right, never top to bottom (wheels or tracks below, a roof above), so a mesh whose
// best mirror plane is horizontal lies on its side: the share of its surface voxels (a grid of
// 1/100 of its largest extent) whose mirror image about a horizontal plane near mid-height is
// occupied (within one voxel) is 0.21-0.68 for the 23 library vehicles upright and 0.95-1.00 on
// their side (0.15-0.57 and 0.94-1.00 for 5 Chrono bodies outside the library, 0.19-0.45 and
// 0.99-1.00 for the thesis's 5 models); >= 0.85 is "on its side". A vehicle whose height is its
// largest extent stands on its end (upright, the height is <= 0.65 of the larger horizontal
// extent). Neither changes the size line.
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <unordered_set>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/mesh_import.h"

namespace {

namespace cm = canopy::common;
namespace fm = canopy::formats;

constexpr double kSideSymmetry = 0.85;  // horizontal mirror symmetry at or above: on its side
constexpr double kMaxSamples = 2e7;     // surface samples of the up check, at most (about 2 s)

// The mesh's vertices in rangetrace's frame: scaled to metres, y up turned to z up.
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

struct Upright {
  Eigen::Vector3d size;
  double symmetry = 0;  // horizontal-plane mirror symmetry, 0..1
  bool on_side = false, on_end = false;
  bool ok() const { return !on_side && !on_end; }
};

// Samples the surface (16 points per voxel face area, a fixed xorshift stream: the same mesh
// gives the same answer) into voxels of 1/100 of the largest extent, and scores the best mirror
// plane z = c, c within 2.5% of the height of mid-height (quarter-voxel steps).
Upright upright(const fm::TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& v) {
  Upright u;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& f : mesh.faces) {
    for (int k : f) {
      lo = lo.cwiseMin(v[k]);
      hi = hi.cwiseMax(v[k]);
    }
  }
  u.size = hi - lo;
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

std::string fixed(double x, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, x);
  return b;
}

// What is wrong with the mesh read with --up `up` (u), and the remedy (other: read with the
// other up axis).
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

}  // namespace

int main(int argc, char** argv) {
  cm::Tool tool("meshsize",
                "Length, width and height (m) of a vehicle mesh as rangetrace --model places it.");
  tool.without_threads();
  std::string input, output = "-", units = "m", up = "z", up_check = "warn";
  tool.add_input(&input, "mesh: .ply, .obj or .stl");
  tool.add_output(&output, "text: one line 'length width height' in metres");
  tool.add("--units", &units, "mesh file units: mm, cm or m")->check(CLI::IsMember({"mm", "cm", "m"}));
  tool.add("--up", &up, "mesh file up axis: z or y")->check(CLI::IsMember({"y", "z"}));
  tool.add("--up-check", &up_check,
           "a mesh that looks on its side or on its end as read with --up: warn (stderr), refuse (exit "
           "1, no output) or off")
      ->check(CLI::IsMember({"warn", "refuse", "off"}));
  return tool.run(argc, argv, [&] {
    cm::log::Phase phase("read");
    std::string ext =
        input.substr(input.find_last_of('.') == std::string::npos ? input.size() : input.find_last_of('.') + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext != "ply" && ext != "obj" && ext != "stl") {
      throw cm::UsageError("-i '" + input + "': not a .ply, .obj or .stl mesh");
    }
    const fm::TriangleMesh mesh = fm::parse_triangle_mesh(cm::read_file(input), input, ext);
    if (mesh.faces.empty()) throw cm::DataError(input, "mesh has no faces");
    const double scale = units == "mm" ? 1e-3 : units == "cm" ? 1e-2 : 1.0;
    const std::vector<Eigen::Vector3d> vertices = render_frame(mesh, scale, up, input);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto& f : mesh.faces) {
      for (int k : f) {
        lo = lo.cwiseMin(vertices[k]);
        hi = hi.cwiseMax(vertices[k]);
      }
    }
    const Eigen::Vector3d size = hi - lo;
    // Nothing a vehicle in any unit (the user-modelbase check names MESH_UNITS for mm and cm);
    // also keeps the size line within its buffer.
    if (!size.allFinite() || size.maxCoeff() > 1e6) {
      char e[32];
      std::snprintf(e, sizeof e, "%.3g", size.maxCoeff());
      throw cm::DataError(input, std::string("its extent (") + e +
                                     " m as read) is beyond 1000 km: not a vehicle mesh in --units " + units);
    }
    char line[128];
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f\n", size.x(), size.y(), size.z());
    std::string upright_note;
    if (up_check != "off") {
      const Upright u = upright(mesh, vertices);
      upright_note = ", horizontal mirror symmetry " + fixed(u.symmetry, 3);
      if (!u.ok()) {
        const Upright other = upright(mesh, render_frame(mesh, scale, up == "z" ? "y" : "z", input));
        const std::string problem = up_problem(up, u, other);
        if (up_check == "refuse") {
          throw cm::DataError(input,
                              problem + ". If it is upright as it is: MESH_UP_CHECK=warn (--up-check warn)");
        }
        cm::log::warn(cm::display_name(input) + ": " + problem +
                      ". If it is upright as it is: --up-check off (make: MESH_UP_CHECK=off) silences this");
      }
    }
    cm::write_file_atomic(output, line);
    phase.done(std::string(line, std::strlen(line) - 1) + " m (length width height), " +
               std::to_string(mesh.faces.size()) + " triangles" + upright_note);
  });
}
