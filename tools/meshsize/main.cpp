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
#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/mesh_import.h"
#include "meshsize/upright.h"

namespace {

namespace cm = canopy::common;
namespace fm = canopy::formats;
namespace ms = canopy::meshsize;

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
    const std::vector<Eigen::Vector3d> vertices = ms::render_frame(mesh, scale, up, input);
    const ms::Box box = ms::bounds(mesh, vertices);  // the size line's and the up check's
    const Eigen::Vector3d size = box.size();
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
      const ms::Upright u = ms::upright(mesh, vertices, box);
      upright_note = ", horizontal mirror symmetry " + ms::fixed(u.symmetry, 3);
      if (!u.ok()) {
        // The other up axis: another frame, its own box.
        const std::vector<Eigen::Vector3d> turned = ms::render_frame(mesh, scale, up == "z" ? "y" : "z", input);
        const ms::Upright other = ms::upright(mesh, turned, ms::bounds(mesh, turned));
        const std::string problem = ms::up_problem(up, u, other);
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
