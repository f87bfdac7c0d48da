// rangetrace: vehicle model + scene recipe -> scan PCD (POV-Ray range simulation, thesis ch. 2).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/provenance.h"
#include "canopy/sim/families.h"
#include "rangetrace/stage.h"
#include "rangetrace/tile_sensor.h"

using namespace canopy;

namespace {

// The options given as text and the files.
struct Options {
  std::string out = "-", units = "m", up = "z", picture = "", pos = "0,0", truth = "";
  bool list_families = false;
};

// What is rendered: the model, the scene, the mesh import, the outputs.
void bind_request(common::Tool& tool, rangetrace::Request& r, Options& o) {
  tool.app().add_option("--model", r.model,
                        "earthmover, obj1, sedan, semi, tank, family:<class>:<instance> (a procedural "
                        "vehicle; --list-families), a POV-Ray include "
                        "declaring Vehicle (.inc/.pov; checked, then rendered in a sandbox: "
                        "CANOPY_POVRAY_SANDBOX=auto|bwrap|off, docs/decisions/sandbox.md), or a mesh "
                        "(.ply/.obj/.stl); not with a tile scene (its recipe places the vehicles)");
  tool.add("--scene", &r.scene,
           "a recipe of share/scenes by name (circle, flyby, unoccluded, "
           "forest, ...) or a recipe file (share/scenes/README.md; required for scans; for --picture, omit "
           "it to show the model alone)");
  tool.add_output(&o.out, "scan: .pcd, .ply or .las (LAS 1.4) by the extension; '-' = PCD");
  tool.add("--units", &o.units, "mesh file units: mm, cm or m")->check(CLI::IsMember({"mm", "cm", "m"}));
  tool.add("--up", &o.up, "mesh file up axis: z or y")->check(CLI::IsMember({"y", "z"}));
}

// The pose, the images and the crop box.
void bind_params(common::Tool& tool, rangetrace::Params& p, Options& o) {
  tool.add_angle("--heading", &p.pose.heading, "vehicle heading, counter-clockwise from +x");
  tool.add("--position", &o.pos, "vehicle ground position X,Y (lengths, e.g. 1.5m,-200mm)");
  tool.add("--size", &p.size, "image width and height (pixels)");
  tool.add_length("--spacing", &p.spacing, "pixel spacing (field = size x spacing)");
  tool.add_length("--crop-length", &p.crop_length, "crop box length along the vehicle axis");
  tool.add_length("--crop-width", &p.crop_width, "crop box width");
  tool.add_length("--crop-height", &p.crop_height, "crop box height (centred on the vehicle)");
  tool.add("--povray", &p.povray, "POV-Ray executable");
}

// The other outputs: a picture, the truth, the list of families.
void bind_extras(common::Tool& tool, rangetrace::Request& r, Options& o) {
  tool.add("--picture", &o.picture, "instead of a scan, write a shaded PNG picture here");
  tool.add("--view", &r.view, "view index shown by --picture with a scene");
  tool.add("--truth", &o.truth, "tile scenes: write the ground truth (truth.json) here");
  tool.add_flag("--list-families", &o.list_families,
                "print the procedural vehicle classes "
                "(family:<class>:<instance>) with their length, width and height ranges, and exit")
      ->default_str("false");
}

void print_families() {
  for (const auto& c : rangetrace::family_classes()) {
    std::printf("%-13s length %5.2f-%5.2f m  width %4.2f-%4.2f m  height %4.2f-%4.2f m\n", c.name,
                c.length.lo, c.length.hi, c.width.lo, c.width.hi, c.height.lo, c.height.hi);
  }
}

Eigen::Vector2d parse_position(const std::string& pos) {
  const auto comma = pos.find(',');
  if (comma == std::string::npos) throw common::UsageError("--position: expected X,Y");
  return {common::parse_length(pos.substr(0, comma)), common::parse_length(pos.substr(comma + 1))};
}

// The recorded parameters. Options added for tiles are recorded only in tile outputs, so that
// single-vehicle scans stay byte-identical to those of earlier versions (the thesis experiment).
std::vector<std::pair<std::string, std::string>> recorded(const common::Tool& tool, bool tile) {
  auto all = tool.parameters();
  all.erase(std::remove_if(all.begin(), all.end(), [](const auto& kv) { return kv.first == "list-families"; }),
            all.end());
  if (!tile) {
    all.erase(std::remove_if(all.begin(), all.end(), [](const auto& kv) { return kv.first == "truth"; }),
              all.end());
  }
  return all;
}

// Writes the scan (a tile's with its truth.json, committed together or neither).
void write_scan(const common::Tool& tool, const Options& o, rangetrace::Outputs* r, common::OutputSet* outputs) {
  r->cloud.comments =
      formats::provenance_comments({"rangetrace", CANOPY_VERSION, recorded(tool, r->tile.has_value()), {}});
  r->cloud.comments.insert(r->cloud.comments.end(), r->notes.begin(), r->notes.end());
  if (!r->tile) {
    formats::write_points(r->cloud, o.out);
    return;
  }
  outputs->set(o.out, formats::serialize_points(r->cloud, o.out));
  if (!o.truth.empty()) outputs->set(o.truth, rangetrace::truth_json(*r->tile, recorded(tool, true)));
  if (r->tile->recipe.sensor && o.out != "-") {
    outputs->set(rangetrace::trajectory_path(o.out),
                 formats::serialize_trajectory(rangetrace::tile_trajectory(*r->tile)));
  }
  outputs->commit();
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("rangetrace",
                    "Simulated airborne range scan of a vehicle under foliage, "
                    "ray traced with POV-Ray (thesis ch. 2).",
                    true);
  rangetrace::Params p;
  rangetrace::Request request;
  Options o;
  tool.app().get_option("--threads")->default_val(2);
  bind_request(tool, request, o);
  bind_params(tool, p, o);
  bind_extras(tool, request, o);
  return tool.run(argc, argv, [&] {
    if (o.list_families) return print_families();
    p.pose.position = parse_position(o.pos);
    rangetrace::validate(p);
    formats::output_format(o.out);  // a mistyped extension fails before any rendering
    p.seed = tool.seed();
    p.threads = tool.threads();
    // Render windows (cost.md §11) are on; CANOPY_RENDER_WINDOW=off traces every pixel, and
    // CANOPY_CANOPY_CLASS_ONLY=off codes depth in a tile's canopy image (§13), for comparisons
    // and measurements. Environment variables: the scan's provenance is unchanged.
    const char* window = std::getenv("CANOPY_RENDER_WINDOW");
    p.window = window == nullptr || std::string(window) != "off";
    const char* class_only = std::getenv("CANOPY_CANOPY_CLASS_ONLY");
    p.canopy_class_only = class_only == nullptr || std::string(class_only) != "off";
    request.import.scale = o.units == "mm" ? 1e-3 : o.units == "cm" ? 1e-2 : 1.0;
    request.import.z_up = o.up == "z";
    request.picture = !o.picture.empty();
    request.truth = !o.truth.empty();
    const rangetrace::Inputs inputs = rangetrace::load_inputs(request);
    // A tile's scan and truth.json are committed together, or neither (checked before the work).
    common::OutputSet outputs;
    if (inputs.tile() && !request.picture) {
      outputs.add(o.out, "-o");
      if (request.truth) outputs.add(o.truth, "--truth");
      // A sensor tile's trajectory file beside the scan (issue 28), committed with it.
      if (inputs.scene->tile->sensor && o.out != "-") {
        outputs.add(rangetrace::trajectory_path(o.out), "the trajectory beside -o");
      }
    }
    rangetrace::Outputs r = rangetrace::run(p, inputs);
    if (request.picture) {
      common::write_file_atomic(o.picture, r.picture);
      common::log::info("wrote picture " + o.picture);
      return;
    }
    write_scan(tool, o, &r, &outputs);
    common::log::info("wrote " + r.summary + " to " + common::display_name(o.out, true));
  });
}
