// rangetrace: vehicle model + scene recipe -> scan PCD (POV-Ray range simulation, thesis ch. 2).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "canopy/common/cli.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/points_io.h"
#include "rangetrace/families.h"
#include "rangetrace/rangetrace.h"
#include "rangetrace/tile.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("rangetrace",
                    "Simulated airborne range scan of a vehicle under foliage, "
                    "ray traced with POV-Ray (thesis ch. 2).",
                    true);
  rangetrace::Params p;
  std::string out = "-", model = "", scene = "", units = "m", up = "z", picture = "", pos = "0,0";
  std::string truth = "";
  int view = 0;
  bool list_families = false;
  tool.app().get_option("--threads")->default_val(2);
  tool.app().add_option("--model", model,
                        "earthmover, obj1, sedan, semi, tank, family:<class>:<instance> (a procedural "
                        "vehicle; --list-families), a POV-Ray include "
                        "declaring Vehicle (.inc/.pov), or a mesh (.ply/.obj/.stl); not with a "
                        "tile scene (its recipe places the vehicles)");
  tool.add("--scene", &scene,
           "a recipe of share/scenes by name (circle, flyby, unoccluded, "
           "forest, ...) or a recipe file (share/scenes/README.md; required for scans; for --picture, omit "
           "it to show the model alone)");
  tool.add_output(&out, "scan: .pcd, .ply or .las (LAS 1.4) by the extension; '-' = PCD");
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
  tool.add("--truth", &truth, "tile scenes: write the ground truth (truth.json) here");
  tool.add_flag("--list-families", &list_families,
                "print the procedural vehicle classes "
                "(family:<class>:<instance>) with their length, width and height ranges, and exit")
      ->default_str("false");
  return tool.run(argc, argv, [&] {
    if (list_families) {
      for (const auto& c : rangetrace::family_classes()) {
        std::printf("%-13s length %5.2f-%5.2f m  width %4.2f-%4.2f m  height %4.2f-%4.2f m\n", c.name,
                    c.length.lo, c.length.hi, c.width.lo, c.width.hi, c.height.lo, c.height.hi);
      }
      return;
    }
    const auto comma = pos.find(',');
    if (comma == std::string::npos) throw common::UsageError("--position: expected X,Y");
    p.pose.position = {common::parse_length(pos.substr(0, comma)), common::parse_length(pos.substr(comma + 1))};
    if (p.size < 8 || p.size > 8192 || !(p.spacing > 0) || !(p.crop_length > 0) || !(p.crop_width > 0) ||
        !(p.crop_height > 0)) {
      throw common::UsageError("need 8 <= --size <= 8192, --spacing > 0 and crop sizes > 0");
    }
    formats::output_format(out);  // a mistyped extension fails before any rendering
    p.seed = tool.seed();
    p.threads = tool.threads();
    // Options added for tiles are recorded only in tile outputs, so that single-vehicle scans
    // stay byte-identical to those of earlier versions (the thesis experiment).
    auto parameters = [&](bool tile) {
      auto all = tool.parameters();
      all.erase(
          std::remove_if(all.begin(), all.end(), [](const auto& kv) { return kv.first == "list-families"; }),
          all.end());
      if (!tile) {
        all.erase(std::remove_if(all.begin(), all.end(), [](const auto& kv) { return kv.first == "truth"; }),
                  all.end());
      }
      return all;
    };
    if (!scene.empty()) {
      const rangetrace::SceneRecipe s = rangetrace::load_scene(scene);
      if (s.tile) {
        if (!model.empty()) {
          throw common::UsageError("--model: the tile scene '" + scene +
                                   "' places its own vehicles "
                                   "(vehicle = ... lines)");
        }
        // The scan and truth.json are committed together, or neither (checked before the work).
        common::OutputSet outputs;
        if (picture.empty()) {
          outputs.add(out, "-o");
          if (!truth.empty()) outputs.add(truth, "--truth");
        }
        const rangetrace::Tile tile = rangetrace::build_tile(*s.tile, scene, p);
        if (!picture.empty()) {
          common::write_file_atomic(picture, rangetrace::render_tile_picture(tile, p));
          common::log::info("wrote picture " + picture);
          return;
        }
        rangetrace::Tile rendered = tile;
        rangetrace::TileScan scan = rangetrace::run_tile(&rendered, p);
        if (scan.cloud.empty()) throw common::Error("no point in the tile");
        scan.cloud.comments.push_back("rangetrace (canopy) " CANOPY_VERSION);
        for (const auto& [name, value] : parameters(true)) {
          scan.cloud.comments.push_back("parameter " + name + " = " + value);
        }
        if (s.tile->has_origin) {
          char buf[160];
          std::snprintf(buf, sizeof buf, "origin %.3f %.3f %.3f (added to x y z)", s.tile->origin.x(),
                        s.tile->origin.y(), s.tile->origin.z());
          scan.cloud.comments.push_back(buf);
        }
        outputs.set(out, formats::serialize_points(scan.cloud, out));
        if (!truth.empty()) outputs.set(truth, rangetrace::truth_json(rendered, parameters(true)));
        outputs.commit();
        double area = 0;
        for (double a : scan.area_per_view) area += a;
        char dens[200];
        std::snprintf(dens, sizeof dens, "%.1f points per m^2 per image, %.1f per m^2 in all",
                      area > 0 ? scan.cloud.size() / area : 0.0,
                      scan.cloud.size() / (s.tile->extent_x * s.tile->extent_y));
        common::log::info("wrote " + std::to_string(scan.cloud.size()) + " points (" + scene + ", " +
                          std::to_string(rendered.vehicles.size()) + " vehicles, " +
                          std::to_string(scan.points_per_view.size()) + " images; " + dens + ") to " +
                          common::display_name(out, true));
        return;
      }
    }
    if (model.empty()) throw common::UsageError("--model is required (except for tile scenes)");
    if (!truth.empty()) throw common::UsageError("--truth: only tile scenes write a truth.json");
    rangetrace::MeshImport import;
    import.scale = units == "mm" ? 1e-3 : units == "cm" ? 1e-2 : 1.0;
    import.z_up = up == "z";
    const rangetrace::Model m = rangetrace::load_model(model, import);
    if (!picture.empty()) {
      rangetrace::SceneRecipe s;
      if (!scene.empty()) s = rangetrace::load_scene(scene);
      common::write_file_atomic(picture, rangetrace::render_picture(m, scene.empty() ? nullptr : &s, view, p));
      common::log::info("wrote picture " + picture);
      return;
    }
    if (scene.empty()) throw common::UsageError("--scene is required for a scan");
    const rangetrace::SceneRecipe s = rangetrace::load_scene(scene);
    formats::PointCloud cloud = rangetrace::run(m, s, p);
    if (cloud.empty()) throw common::Error("no point in the crop box (check --position, --crop-*)");
    cloud.comments.push_back("rangetrace (canopy) " CANOPY_VERSION);
    for (const auto& [name, value] : parameters(false)) {
      cloud.comments.push_back("parameter " + name + " = " + value);
    }
    if (!m.vehicle_class.empty()) cloud.comments.push_back("class " + m.vehicle_class);
    formats::write_points(cloud, out);
    common::log::info("wrote " + std::to_string(cloud.size()) + " points (" + m.name + ", " + s.name + ", " +
                      std::to_string(s.views.size()) + " views) to " + common::display_name(out, true));
  });
}
