// rangetrace: vehicle model + scene recipe -> scan PCD (POV-Ray range simulation, thesis ch. 2).
#include <string>

#include "canopy/common/cli.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/pcd.h"
#include "rangetrace/rangetrace.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("rangetrace", "Simulated airborne range scan of a vehicle under foliage, "
                                  "ray traced with POV-Ray (thesis ch. 2).", true);
  rangetrace::Params p;
  std::string out = "-", model = "", scene = "", units = "m", up = "z", picture = "", pos = "0,0";
  int view = 0;
  tool.app().get_option("--threads")->default_val(2);
  tool.app().add_option("--model", model, "earthmover, obj1, sedan, semi, tank, a POV-Ray include "
                        "declaring Vehicle (.inc/.pov), or a mesh (.ply/.obj/.stl)")->required();
  tool.add("--scene", &scene, "circle, flyby, unoccluded or a scene recipe file (required "
                              "for scans; for --picture, omit it to show the model alone)");
  tool.add_output(&out, "scan PCD");
  tool.add("--units", &units, "mesh file units: mm, cm or m")->check(CLI::IsMember({"mm", "cm", "m"}));
  tool.add("--up", &up, "mesh file up axis: z or y")->check(CLI::IsMember({"y", "z"}));
  tool.add_angle("--heading", &p.pose.heading, "vehicle heading, counter-clockwise from +x");
  tool.add("--position", &pos, "vehicle ground position X,Y (lengths, e.g. 1.5m,-200mm)");
  tool.add("--size", &p.size, "image width and height (pixels)");
  tool.add_length("--spacing", &p.spacing, "pixel spacing (field = size x spacing)");
  tool.add_length("--crop-length", &p.crop_length, "crop box length along the vehicle axis");
  tool.add_length("--crop-width", &p.crop_width, "crop box width");
  tool.add_length("--crop-height", &p.crop_height, "crop box height (centred on the vehicle)");
  tool.add("--povray", &p.povray, "POV-Ray executable");
  tool.add("--picture", &picture, "instead of a scan, write a shaded PNG picture here");
  tool.add("--view", &view, "view index shown by --picture with a scene");
  return tool.run(argc, argv, [&] {
    const auto comma = pos.find(',');
    if (comma == std::string::npos) throw common::UsageError("--position: expected X,Y");
    p.pose.position = {common::parse_length(pos.substr(0, comma)),
                       common::parse_length(pos.substr(comma + 1))};
    if (p.size < 8 || p.size > 8192 || !(p.spacing > 0) || !(p.crop_length > 0) ||
        !(p.crop_width > 0) || !(p.crop_height > 0)) {
      throw common::UsageError("need 8 <= --size <= 8192, --spacing > 0 and crop sizes > 0");
    }
    p.seed = tool.seed();
    p.threads = tool.threads();
    rangetrace::MeshImport import;
    import.scale = units == "mm" ? 1e-3 : units == "cm" ? 1e-2 : 1.0;
    import.z_up = up == "z";
    const rangetrace::Model m = rangetrace::load_model(model, import);
    if (!picture.empty()) {
      rangetrace::SceneRecipe s;
      if (!scene.empty()) s = rangetrace::load_scene(scene);
      common::write_file_atomic(picture, rangetrace::render_picture(m, scene.empty() ? nullptr : &s,
                                                                    view, p));
      common::log::info("wrote picture " + picture);
      return;
    }
    if (scene.empty()) throw common::UsageError("--scene is required for a scan");
    const rangetrace::SceneRecipe s = rangetrace::load_scene(scene);
    formats::PointCloud cloud = rangetrace::run(m, s, p);
    if (cloud.empty()) throw common::Error("no point in the crop box (check --position, --crop-*)");
    cloud.comments.push_back("rangetrace (canopy) " CANOPY_VERSION);
    for (const auto& [name, value] : tool.parameters()) {
      cloud.comments.push_back("parameter " + name + " = " + value);
    }
    formats::write_pcd(cloud, out);
    common::log::info("wrote " + std::to_string(cloud.size()) + " points (" + m.name + ", " +
                      s.name + ", " + std::to_string(s.views.size()) + " views) to " +
                      common::display_name(out, true));
  });
}
