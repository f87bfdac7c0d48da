// meshsize: the axis-aligned extent of a vehicle mesh (.ply/.obj/.stl) in metres, in the frame
// rangetrace renders it in (--units scale, --up y turned to z up exactly as rangetrace --model
// does). Prints one line "length width height" (x, y and z extents); make's user-modelbase
// (mk/usermb.mk) chooses each entry's crop box from it.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/mesh_import.h"

int main(int argc, char** argv) {
  namespace cm = canopy::common;
  namespace fm = canopy::formats;
  cm::Tool tool("meshsize",
                "Length, width and height (m) of a vehicle mesh as rangetrace --model places it.");
  tool.without_threads();
  std::string input, output = "-", units = "m", up = "z";
  tool.add_input(&input, "mesh: .ply, .obj or .stl");
  tool.add_output(&output, "text: one line 'length width height' in metres");
  tool.add("--units", &units, "mesh file units: mm, cm or m")->check(CLI::IsMember({"mm", "cm", "m"}));
  tool.add("--up", &up, "mesh file up axis: z or y")->check(CLI::IsMember({"y", "z"}));
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
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto& f : mesh.faces) {
      for (int k : f) {
        Eigen::Vector3d v = mesh.vertices[k] * scale;
        if (!v.allFinite()) throw cm::DataError(input, "non-finite vertex coordinate");
        if (up == "y") v = Eigen::Vector3d(v.x(), -v.z(), v.y());  // as sim/src/models.cpp
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
    }
    const Eigen::Vector3d size = hi - lo;
    char line[128];
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f\n", size.x(), size.y(), size.z());
    cm::write_file_atomic(output, line);
    phase.done(std::string(line, std::strlen(line) - 1) + " m (length width height), " +
               std::to_string(mesh.faces.size()) + " triangles");
  });
}
