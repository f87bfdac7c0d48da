// figures: the experiment's pictures as PNG (VTK, off-screen). Subcommands:
//   figures mesh -i segments.ply -o seg.png          a coloured segmentation, shaded
//   figures grid -o grid.png --cols 6 a.png b.png .. tiles in a labelled grid ('-' = failed)
//   figures plot -i scores.csv -o plot.png           score of the correct model vs noise
// mesh and plot need an X display: run under `xvfb-run -a` on a headless machine.
#include <sys/stat.h>

#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "figures/figures.h"

using namespace canopy;

namespace {

CLI::Option* length(CLI::App* app, const std::string& flags, double* metres, const std::string& help) {
  auto* opt = app->add_option_function<std::string>(
      flags, [metres](const std::string& t) { *metres = common::parse_length(t); },
      help + " (length: 10m, 400cm; bare = m)");
  return opt->default_str(common::format_length(*metres))->type_name("LENGTH");
}

bool exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

std::string size_text(const figures::Image& im) {
  return std::to_string(im.width) + "x" + std::to_string(im.height);
}

// Labels: comma-separated ("0 mm,2 mm"); a list without commas is split on whitespace
// ("earthmover obj1 sedan", as a Makefile variable expands).
std::vector<std::string> split_labels(const std::string& s) {
  std::vector<std::string> out;
  if (s.find(',') != std::string::npos) {
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = s.find(',', start);
      out.push_back(s.substr(start, comma == std::string::npos ? comma : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  } else {
    std::istringstream words(s);
    for (std::string w; words >> w;) out.push_back(w);
  }
  return out;
}

// figures mesh
struct MeshCommand {
  CLI::App* app = nullptr;
  figures::MeshView view;
  std::string in, out, framing = "box";
};

void bind(CLI::App& parent, MeshCommand& c) {
  CLI::App* mesh = c.app =
      parent.add_subcommand("mesh", "render a coloured segmentation PLY (ncut --colored)");
  figures::MeshView& mv = c.view;
  mesh->add_option("-i,--input", c.in, "mesh PLY (x y z, [red green blue], faces)")->required();
  mesh->add_option("-o,--output", c.out, "PNG to write")->required();
  mesh->add_option("--width", mv.width, "image width in pixels")
      ->check(common::number_check<int>())
      ->capture_default_str();
  mesh->add_option("--height", mv.height, "image height in pixels")
      ->check(common::number_check<int>())
      ->capture_default_str();
  mesh->add_option("--elevation", mv.elevation_deg, "camera elevation above the ground (deg)")
      ->check(common::number_check<double>())
      ->capture_default_str();
  mesh->add_option("--azimuth", mv.azimuth_deg, "camera azimuth from +x (front) toward +y (left), deg")
      ->check(common::number_check<double>())
      ->capture_default_str();
  mesh->add_option("--framing", c.framing,
                   "'box': fixed box (same camera for every mesh); "
                   "'bounds': the mesh's bounding box")
      ->capture_default_str();
  length(mesh, "--box-length", &mv.box[0], "fixed box along x, centred on the origin");
  length(mesh, "--box-width", &mv.box[1], "fixed box along y, centred on the origin");
  length(mesh, "--box-height", &mv.box[2], "fixed box along z, from the ground z = 0");
}

void run(MeshCommand& c) {
  if (c.framing != "box" && c.framing != "bounds") throw common::UsageError("--framing: 'box' or 'bounds'");
  c.view.framing = c.framing == "box" ? figures::Framing::kBox : figures::Framing::kBounds;
  figures::validate(c.view);
  common::check_output(c.out);
  common::log::Phase read("read");
  const formats::Mesh m = formats::read_ply(c.in);
  read.done(std::to_string(m.vertices.size()) + " vertices, " + std::to_string(m.faces.size()) + " faces");
  common::log::Phase render("render");
  const figures::Image image = figures::render_mesh(m, c.view, common::display_name(c.in));
  figures::write_png(image, c.out);
  render.done("wrote " + size_text(image) + " " + common::display_name(c.out, true));
}

// figures grid
struct GridCommand {
  CLI::App* app = nullptr;
  figures::GridParams params;
  std::string out, row_labels, col_labels;
  std::vector<std::string> cells;
};

void bind(CLI::App& parent, GridCommand& c) {
  CLI::App* grid = c.app = parent.add_subcommand("grid",
                                                 "tile PNGs row by row into a labelled grid; a cell "
                                                 "given as '-' or as a missing file is drawn 'failed'");
  figures::GridParams& gp = c.params;
  grid->add_option("-o,--output", c.out, "PNG to write")->required();
  grid->add_option("--cols", gp.cols, "cells per row")->check(common::number_check<int>())->required();
  grid->add_option("--labels-row", c.row_labels,
                   "row labels, one per row: comma-separated, or whitespace-separated when without commas");
  grid->add_option("--labels-col", c.col_labels, "column labels, one per column (same rule as --labels-row)");
  grid->add_option("--title", gp.title, "title line above the grid");
  grid->add_option("--font-size", gp.font_size, "label size in pixels")
      ->check(common::number_check<int>())
      ->capture_default_str();
  grid->add_option("--gap", gp.gap, "pixels between cells")
      ->check(common::number_check<int>())
      ->capture_default_str();
  grid->add_flag("--trim,!--no-trim", gp.trim,
                 "crop all tiles alike to the union of their non-background areas (default on)");
  grid->add_option("--margin", gp.margin, "pixels kept around the trimmed content")
      ->check(common::number_check<int>())
      ->capture_default_str();
  grid->add_option("cells", c.cells, "PNG files, row by row ('-' = failed cell)")->required();
}

void run(GridCommand& c) {
  figures::validate(c.params);
  common::check_output(c.out);
  c.params.row_labels = split_labels(c.row_labels);
  c.params.col_labels = split_labels(c.col_labels);
  common::log::Phase phase("grid");
  std::vector<std::optional<figures::Image>> images;
  int failed = 0;
  for (const auto& path : c.cells) {
    if (path == "-" || !exists(path)) {
      if (path != "-") common::log::warn(path + ": missing; drawn as a failed cell");
      images.emplace_back(std::nullopt);
      ++failed;
    } else {
      images.emplace_back(figures::read_png(path));
    }
  }
  const figures::Image image = figures::tile_grid(images, c.params);
  figures::write_png(image, c.out);
  phase.done("wrote " + size_text(image) + " " + common::display_name(c.out, true) + ": " +
             std::to_string(c.cells.size()) + " cells, " + std::to_string(failed) + " failed");
}

// figures plot
struct PlotCommand {
  CLI::App* app = nullptr;
  figures::PlotParams params;
  figures::PlotColumns columns;
  std::string in, out;
  std::vector<CLI::Option*> column_options;  // --x, --y, --series, --lo, --hi, --panel
};

void bind(CLI::App& parent, PlotCommand& c) {
  CLI::App* plot = c.app = parent.add_subcommand("plot",
                                                 "plot the correct model's score against noise, one "
                                                 "panel per scene, one line per object");
  figures::PlotParams& pp = c.params;
  figures::PlotColumns& pc = c.columns;
  plot->add_option("-i,--input", c.in, "scores CSV (object,scene,noise_mm,score,rank,entropy)")->required();
  plot->add_option("-o,--output", c.out, "PNG to write")->required();
  plot->add_option("--width", pp.width, "image width in pixels")
      ->check(common::number_check<int>())
      ->capture_default_str();
  plot->add_option("--height", pp.height, "image height in pixels")
      ->check(common::number_check<int>())
      ->capture_default_str();
  plot->add_option("--ylabel", pp.y_title, "title of the y axis")->capture_default_str();
  plot->add_option("--xlabel", pp.x_title, "title of the x axis")->capture_default_str();
  plot->add_option("--title", pp.title, "panel title (default: 'scene: ' and the panel's value)");
  c.column_options = {
      plot->add_option("--x", pc.x, "column of the x values (levels at equal spacing)")->capture_default_str(),
      plot->add_option("--y", pc.y, "column of the y values")->capture_default_str(),
      plot->add_option("--series", pc.series, "column naming the line (one colour each)")->capture_default_str(),
      plot->add_option("--lo", pc.lo, "column of the y value's lower 95% bound (with --hi: a bar per point)"),
      plot->add_option("--hi", pc.hi, "column of the y value's upper 95% bound"),
      plot->add_option("--panel", pc.panel,
                       "column naming the panel ('' = one panel); with any column "
                       "option, rows whose x is text (a summary row 'all') are left out")
          ->capture_default_str()};
}

void run(PlotCommand& c) {
  figures::validate(c.params);
  common::check_output(c.out);
  common::log::Phase phase("plot");
  std::size_t given = 0;
  for (const CLI::Option* o : c.column_options) given += o->count();
  c.columns.strict = given == 0;
  const auto rows = figures::parse_scores_csv(common::read_file(c.in), common::display_name(c.in), c.columns);
  const figures::Image image = figures::plot_scores(rows, c.params, common::display_name(c.in));
  figures::write_png(image, c.out);
  phase.done("wrote " + size_text(image) + " " + common::display_name(c.out, true) + " from " +
             std::to_string(rows.size()) + " rows");
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("figures",
                    "Renders the experiment's figures to PNG with VTK: a segmentation "
                    "mesh (mesh), a labelled grid of PNGs (grid), scores against noise "
                    "(plot). mesh and plot need an X display (use xvfb-run -a).");
  tool.without_threads();
  CLI::App& app = tool.app();
  app.require_subcommand(1);
  app.fallthrough();  // -q, -v, --config also after the subcommand
  MeshCommand mesh;
  GridCommand grid;
  PlotCommand plot;
  bind(app, mesh);
  bind(app, grid);
  bind(app, plot);
  return tool.run(argc, argv, [&] {
    if (mesh.app->parsed()) {
      run(mesh);
    } else if (grid.app->parsed()) {
      run(grid);
    } else if (plot.app->parsed()) {
      run(plot);
    }
  });
}
