// Tile rendering: flight-line views, the POV-Ray scene (one frame per image: depth in red and
// green, class and instance in blue), parallel rendering, decoding, canopy cover, truth, picture.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "canopy/common/geometry.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/math.h"
#include "canopy/common/units.h"
#include "canopy/documents/scene_truth.h"
#include "canopy/formats/labels.h"
#include "canopy/sim/povray_run.h"
#include "rangetrace/tile.h"
#include "rangetrace/tile_sensor.h"

namespace canopy::rangetrace {

using common::Error;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

constexpr double kFine = 4096;  // green = frac(depth fraction * kFine)

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

std::string vec(const Vector3d& world) {
  const Vector3d p = pov_frame(world);
  return "<" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + ">";
}

// POV-Ray "matrix" of a world-frame affine map (p' = p M with row vectors).
std::string pov_matrix(const Eigen::Affine3d& world) {
  std::string out = "matrix <";
  for (int i = 0; i < 3; ++i) {
    const Vector3d image = pov_frame(world.linear() * pov_frame(Vector3d::Unit(i)));
    out += num(image.x()) + ", " + num(image.y()) + ", " + num(image.z()) + ", ";
  }
  const Vector3d t = pov_frame(world.translation());
  return out + num(t.x()) + ", " + num(t.y()) + ", " + num(t.z()) + ">";
}

std::uint32_t code_of(Class c, int instance) {
  return 1 + static_cast<std::uint32_t>(c) + 4 * static_cast<std::uint32_t>(instance);
}

std::uint32_t label_of(std::uint32_t cls) {
  switch (static_cast<Class>(cls)) {
    case Class::kGround: return formats::kLabelGround;
    case Class::kVegetation: return formats::kLabelFoliage;
    case Class::kClutter: return formats::kLabelClutter;
    default: return formats::kLabelTarget;
  }
}

Vector3d pixel_origin(const TileView& v, int i, int j) {
  const double x = (i + 0.5) / v.width - 0.5, y = 0.5 - (j + 0.5) / v.height;
  return v.origin + x * v.width * v.spacing * v.right + y * v.height * v.spacing * v.up;
}

// POV-Ray code of the whole tile. mode 0: depth/label coding, frames = views;
// mode 1: shaded picture from views[0] with footprint outlines.
// The models (Veh<m>), the ground, the tree templates in use (Tree<k>) and the clutter meshes
// (Obj<k>).
void pov_declarations(std::ostringstream& s, const Tile& tile, const Staged& st) {
  for (std::size_t m = 0; m < tile.models.size(); ++m) {
    s << "#ifdef (Vehicle) #undef Vehicle #end\n" << st.include_code[m];
    s << "#declare Veh" << m << " = Vehicle;\n";
  }
  s << TerrainModel(tile.recipe, tile.seed).pov();
  std::vector<bool> used_tree(tile.tree_meshes.size(), false);
  for (const auto& t : tile.trees) used_tree[t.template_index] = true;
  for (std::size_t k = 0; k < tile.tree_meshes.size(); ++k) {
    if (used_tree[k]) s << mesh_declare("Tree" + std::to_string(k), tile.tree_meshes[k]);
  }
  for (std::size_t k = 0; k < tile.object_meshes.size(); ++k) {
    s << mesh_declare("Obj" + std::to_string(k), tile.object_meshes[k]);
  }
}

// One orthographic camera per frame F, from arrays over the views.
void pov_cameras(std::ostringstream& s, const std::vector<TileView>& views, int mode) {
  const std::size_t n = views.size();
  auto array = [&](const std::string& name, auto value) {
    s << "#declare " << name << " = array[" << n << "] {";
    for (std::size_t k = 0; k < n; ++k) s << (k ? ", " : " ") << value(views[k]);
    s << " }\n";
  };
  array("CLoc", [](const TileView& v) { return vec(v.origin); });
  array("CDir", [](const TileView& v) { return vec(-v.toward); });
  array("CRight", [](const TileView& v) { return vec(v.right * v.width * v.spacing); });
  array("CUp", [](const TileView& v) { return vec(v.up * v.height * v.spacing); });
  array("CTow", [](const TileView& v) { return vec(v.toward); });
  array("CK0", [](const TileView& v) { return num(v.origin.dot(v.toward) - v.depth_lo); });
  array("CSpan", [](const TileView& v) { return num(v.depth_span); });
  s << "#declare F = " << (mode == 0 ? "frame_number" : "0") << ";\n";
  s << "camera { orthographic location CLoc[F] direction CDir[F] right CRight[F] up CUp[F] }\n";
  s << "background { rgb 0 }\n";
}

// The textures: mode 0 codes depth and class (emission only), mode 1 shades a picture.
// In mode 0 the canopy image (frame `canopy_frame`, if >= 0) is only read for its class
// (measure_cover: blue), so there red and green are 0: the same average with two plain black
// pigments in place of the two function pigments, i.e. the same blue by the same arithmetic,
// without evaluating the depth functions (≈ a quarter of that frame's trace, cost.md §13).
void pov_textures(std::ostringstream& s, const Tile& tile, int mode, int canopy_frame) {
  if (mode == 0) {
    // Depth d along the ray (from the image plane) as f = (d - lo) / span in [0, 1]:
    // red = f, green = frac(f * 4096); blue = 1 + class + 4 * instance.
    s << "#declare Tw = CTow[F];\n#declare TX = Tw.x;\n#declare TY = Tw.y;\n#declare TZ = Tw.z;\n";
    s << "#declare KK = CK0[F];\n#declare SP = CSpan[F];\n";
    s << "#declare FD = function { min(max((KK - (TX*x + TY*y + TZ*z)) / SP, 0), 1) }\n";
    s << "#declare FF = function { mod(FD(x, y, z) * " << num(kFine) << ", 1) }\n";
    s << "#declare Emit = finish { ambient 0 diffuse 0 specular 0 phong 0 emission 1 }\n";
    const char* depth_code =
        "#macro Code(C) texture { pigment { average pigment_map {\n"
        "  [1 function { FD(x, y, z) } color_map { [0 rgb 0] [1 rgb <3, 0, 0>] }]\n"
        "  [1 function { FF(x, y, z) } color_map { [0 rgb 0] [1 rgb <0, 3, 0>] }]\n"
        "  [1 rgb <0, 0, 3 * C / 65535>] } } finish { Emit } } #end\n";
    if (canopy_frame < 0) {
      s << depth_code;
    } else {
      s << "#if (F = " << canopy_frame << ")\n"
        << "#macro Code(C) texture { pigment { average pigment_map {\n"
           "  [1 rgb 0] [1 rgb 0] [1 rgb <0, 0, 3 * C / 65535>] } } finish { Emit } } #end\n"
           "#else\n"
        << depth_code << "#end\n";
    }
    s << "#declare TGround = Code(" << code_of(Class::kGround, 0) << ");\n";
    s << "#declare TVeg = Code(" << code_of(Class::kVegetation, 0) << ");\n";
    s << "#declare TClutter = Code(" << code_of(Class::kClutter, 0) << ");\n";
  } else {
    s << "#declare Shade = finish { ambient 0.2 diffuse 0.8 }\n";
    s << "#declare TVehicle = texture { pigment { rgb <0.75, 0.68, 0.5> } finish { Shade } }\n";
    s << "#declare TVeg = texture { pigment { rgb <0.2, 0.5, 0.15> } finish { Shade } }\n";
    s << "#declare TClutter = texture { pigment { rgb <0.55, 0.58, 0.65> } finish { Shade } }\n";
    s << "#declare TGround = texture { pigment { rgb <0.52, 0.45, 0.33> } finish { Shade } }\n";
    const Vector3d c(tile.recipe.extent_x / 2, tile.recipe.extent_y / 2, 0);
    s << "light_source { " << vec(c + Vector3d(-300, -400, 800)) << " color rgb 0.9 }\n";
    s << "light_source { " << vec(c + Vector3d(400, 300, 500)) << " color rgb 0.3 shadowless }\n";
  }
}

// Every object of the tile: the ground, the vehicles, the trees, the canopy discs, the clutter.
void pov_objects(std::ostringstream& s, const Tile& tile, int mode) {
  auto tvehicle = [&](int instance) {
    if (mode == 0) return "Code(" + std::to_string(code_of(Class::kVehicle, instance)) + ")";
    return std::string("texture { TVehicle }");
  };
  s << "object { Ground texture { TGround } }\n";
  for (const auto& v : tile.vehicles) {
    const auto& lo = tile.model_bounds[v.model_index].first;
    const auto& hi = tile.model_bounds[v.model_index].second;
    const Vector3d anchor((lo.x() + hi.x()) / 2, (lo.y() + hi.y()) / 2, lo.z());
    const Eigen::Affine3d t = v.pose.transform() * Eigen::Translation3d(-anchor);
    s << "object { Veh" << v.model_index << " " << pov_matrix(t) << " " << tvehicle(v.instance) << " }\n";
  }
  for (const auto& t : tile.trees) {
    const Eigen::Affine3d m = Eigen::Translation3d(t.base) *
                              Eigen::AngleAxisd(t.rotation, Vector3d::UnitZ()) * Eigen::Scaling(t.scale);
    s << "object { Tree" << t.template_index << " " << pov_matrix(m) << " texture { TVeg } }\n";
  }
  for (const auto& d : tile.recipe.discs) {
    s << "disc { " << vec(d.centre) << ", " << vec(Vector3d::UnitZ()) << ", " << num(d.radius)
      << " texture { TVeg } }\n";
  }
  // Sensor mode codes each clutter object's index (its ASPRS class depends on its kind).
  const bool clutter_ids = mode == 0 && tile.recipe.sensor.has_value();
  for (std::size_t k = 0; k < tile.objects.size(); ++k) {
    s << "object { Obj" << tile.objects[k].template_index << " "
      << pov_matrix(tile.objects[k].pose.transform())
      << (clutter_ids ? " Code(" + std::to_string(code_of(Class::kClutter, static_cast<int>(k) + 1)) + ") }\n"
                      : std::string(" texture { TClutter } }\n"));
  }
}

// The picture's outlines above everything: vehicle footprints red, clutter boxes yellow.
void pov_outlines(std::ostringstream& s, const Tile& tile, const std::vector<TileView>& views) {
  const double z = tile.top + 1;
  const double r = std::max(0.08, 1.2 * views[0].spacing);
  auto outline = [&](const std::array<Vector2d, 4>& q, const char* colour) {
    s << "union {\n";
    for (int e = 0; e < 4; ++e) {
      const Vector3d a(q[e].x(), q[e].y(), z), b(q[(e + 1) % 4].x(), q[(e + 1) % 4].y(), z);
      s << "  cylinder { " << vec(a) << ", " << vec(b) << ", " << num(r) << " }\n";
      s << "  sphere { " << vec(a) << ", " << num(r) << " }\n";
    }
    s << "  texture { pigment { rgb " << colour << " } finish { ambient 0 diffuse 0 emission 1 } }\n}\n";
  };
  for (const auto& v : tile.vehicles) outline(v.footprint, "<1, 0.1, 0.1>");
  for (const auto& o : tile.objects) {
    const Vector2d f(std::cos(o.pose.heading), std::sin(o.pose.heading)), l(-f.y(), f.x());
    const Vector2d c = o.pose.anchor.head<2>();
    const double a0 = o.lo.x(), a1 = o.lo.x() + o.size.x(), b0 = o.lo.y(), b1 = o.lo.y() + o.size.y();
    outline({c + a0 * f + b0 * l, c + a1 * f + b0 * l, c + a1 * f + b1 * l, c + a0 * f + b1 * l},
            "<1, 0.85, 0.1>");
  }
}

std::string tile_pov(const Tile& tile, const Staged& st, const std::vector<TileView>& views, int mode,
                     int canopy_frame = -1) {
  std::ostringstream s;
  s << "// generated by rangetrace (tile " << tile.name << ")\n#version 3.7;\n";
  s << "global_settings { assumed_gamma 1.0 ambient_light rgb " << (mode == 0 ? 0 : 1) << " }\n";
  pov_declarations(s, tile, st);
  pov_cameras(s, views, mode);
  pov_textures(s, tile, mode, canopy_frame);
  pov_objects(s, tile, mode);
  if (mode == 1) pov_outlines(s, tile, views);
  return s.str();
}

}  // namespace

Tile build_tile(const TileRecipe& recipe, const std::string& name, const Params& params) {
  return sim::build_tile(recipe, name, params.seed, params.povray);
}

// ---------------------------------------------------------------- decoding

bool decode_pixel(const Image16& img, const TileView& view, int i, int j, double* depth, std::uint32_t* cls,
                  std::int32_t* instance) {
  const std::uint16_t* c = &img.rgb[3 * (static_cast<std::size_t>(j) * img.width + i)];
  if (c[2] == 0) return false;                   // the ray hit nothing
  if (c[0] == 0 || c[0] == 65535) return false;  // outside the coded depth range
  const double coarse = c[0] / 65535.0, fine = c[1] / 65535.0;
  const double k = std::round(coarse * kFine - fine);
  const double f = (k + fine) / kFine;
  *depth = view.depth_lo + f * view.depth_span;
  *cls = (c[2] - 1u) & 3u;
  *instance = static_cast<std::int32_t>((c[2] - 1u) >> 2);
  return true;
}

void decode_tile_view(const Image16& img, const TileView& view, TileHits* out) {
  const std::size_t pixels = static_cast<std::size_t>(img.width) * img.height;
  out->p.reserve(out->p.size() + pixels);
  out->cls.reserve(out->cls.size() + pixels);
  out->instance.reserve(out->instance.size() + pixels);
  out->pixel.reserve(out->pixel.size() + pixels);
  for (int j = 0; j < img.height; ++j) {
    for (int i = 0; i < img.width; ++i) {
      double depth = 0;
      std::uint32_t cls = 0;
      std::int32_t instance = 0;
      if (!decode_pixel(img, view, i, j, &depth, &cls, &instance)) continue;
      out->p.push_back(pixel_origin(view, i, j) - depth * view.toward);
      out->cls.push_back(cls);
      out->instance.push_back(instance);
      out->pixel.push_back(static_cast<std::size_t>(j) * img.width + i);
    }
  }
}

double footprint_cover(const Image16& img, const TileView& view, const std::array<Vector2d, 4>& footprint) {
  std::size_t inside = 0, covered = 0;
  for (int j = 0; j < img.height; ++j) {
    for (int i = 0; i < img.width; ++i) {
      const Vector3d o = pixel_origin(view, i, j);
      if (!in_polygon(o.head<2>(), footprint)) continue;
      ++inside;
      const std::uint16_t b = img.rgb[3 * (static_cast<std::size_t>(j) * img.width + i) + 2];
      if (b != 0 && ((b - 1u) & 3u) == static_cast<std::uint32_t>(Class::kVegetation)) ++covered;
    }
  }
  return inside == 0 ? 0.0 : static_cast<double>(covered) / static_cast<double>(inside);
}

PixelWindow strip_window(const TileView& v, const TileRecipe& r, double zlo, double zhi, int margin) {
  // The tile's rectangle clipped to |(p - centre) . across| <= half (Sutherland-Hodgman).
  std::vector<Vector2d> poly = {{0, 0}, {r.extent_x, 0}, {r.extent_x, r.extent_y}, {0, r.extent_y}};
  for (const double sign : {1.0, -1.0}) {
    std::vector<Vector2d> out;
    auto inside = [&](const Vector2d& p) {
      return sign * (p - v.strip_centre).dot(v.strip_across) - v.strip_half;
    };
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Vector2d a = poly[k], b = poly[(k + 1) % poly.size()];
      const double da = inside(a), db = inside(b);
      if (da <= 0) out.push_back(a);
      if ((da < 0) != (db < 0) && da != db) out.push_back(a + (b - a) * (da / (da - db)));
    }
    poly = out;
  }
  const PixelWindow whole{0, v.width - 1, 0, v.height - 1};
  if (poly.empty()) return whole;
  double i0 = 1e300, i1 = -1e300, j0 = 1e300, j1 = -1e300;
  for (const Vector2d& q : poly) {
    for (const double z : {zlo, zhi}) {
      const Vector3d d = Vector3d(q.x(), q.y(), z) - v.origin;
      const double i = (d.dot(v.right) / (v.width * v.spacing) + 0.5) * v.width - 0.5;
      const double j = (0.5 - d.dot(v.up) / (v.height * v.spacing)) * v.height - 0.5;
      i0 = std::min(i0, i);
      i1 = std::max(i1, i);
      j0 = std::min(j0, j);
      j1 = std::max(j1, j);
    }
  }
  auto clip = [](double x, int n) { return static_cast<int>(std::clamp(x, 0.0, double(n - 1))); };
  const PixelWindow w{clip(std::floor(i0) - margin, v.width), clip(std::ceil(i1) + margin, v.width),
                      clip(std::floor(j0) - margin, v.height), clip(std::ceil(j1) + margin, v.height)};
  return w.col1 < w.col0 || w.row1 < w.row0 ? whole : w;
}

// ---------------------------------------------------------------- running

namespace {

// The INFO line of the tile phase.
std::string tile_summary(const Tile& tile, std::size_t images) {
  std::size_t triangles = 0;
  for (const auto& m : tile.tree_meshes) triangles += m.f.size();
  return std::to_string(tile.vehicles.size()) + " vehicles, " + std::to_string(tile.trees.size()) +
         " trees and bushes (" + std::to_string(triangles) + " template triangles), " +
         std::to_string(tile.objects.size()) + " clutter objects, " + std::to_string(images) + " images";
}

// Frames ordered by image size (POV-Ray renders one size per process), then view order:
// order[f] is the view of frame f.
std::vector<int> frame_order(const std::vector<TileView>& views) {
  std::vector<int> order(views.size());
  for (std::size_t k = 0; k < views.size(); ++k) order[k] = static_cast<int>(k);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return std::make_pair(views[a].width, views[a].height) < std::make_pair(views[b].width, views[b].height);
  });
  return order;
}

// The POV-Ray runs: each run of frames of one size split into chunks in proportion to its
// share of the frames (threads x count / frames, at least 1), largest work first.
std::vector<FrameRange> frame_ranges(const std::vector<TileView>& frames, int threads) {
  std::vector<FrameRange> tasks;
  const int nf = static_cast<int>(frames.size());
  for (int a = 0; a < nf;) {
    int b = a;
    while (b + 1 < nf && frames[b + 1].width == frames[a].width && frames[b + 1].height == frames[a].height)
      ++b;
    const int count = b - a + 1;
    const int chunks = std::clamp(static_cast<int>(std::lround(double(threads) * count / nf)), 1, count);
    for (int c = 0; c < chunks; ++c) {
      tasks.push_back(
          {a + count * c / chunks, a + count * (c + 1) / chunks - 1, frames[a].width, frames[a].height});
    }
    a = b + 1;
  }
  std::stable_sort(tasks.begin(), tasks.end(), [&](const FrameRange& x, const FrameRange& y) {
    return double(x.last - x.first + 1) * frames[x.first].width * frames[x.first].height >
           double(y.last - y.first + 1) * frames[y.first].width * frames[y.first].height;
  });
  return tasks;
}

// Each run's window: the union of its frames' strip_window (the canopy image, view 0, whole).
void add_windows(const Tile& tile, const std::vector<int>& order, const std::vector<TileView>& frames,
                 std::vector<FrameRange>* tasks) {
  const double zlo = TerrainModel(tile.recipe, tile.seed).lo() - 1, zhi = tile.top + 1;
  for (FrameRange& t : *tasks) {
    std::vector<PixelWindow> ws;
    for (int f = t.first; f <= t.last; ++f) {
      ws.push_back(order[f] == 0 ? PixelWindow{0, t.width - 1, 0, t.height - 1}
                                 : strip_window(frames[f], tile.recipe, zlo, zhi));
    }
    const PixelWindow u = window_union(ws);
    t.col0 = u.col0;
    t.col1 = u.col1;
    t.row0 = u.row0;
    t.row1 = u.row1;
  }
}

// The rendered frames of a tile's views (view 0: the canopy image).
class TileFrames {
 public:
  TileFrames(const std::vector<TileView>& views, const std::vector<int>& order, std::map<int, std::string> files)
      : views_(views), frame_of_(views.size()), files_(std::move(files)) {
    for (std::size_t f = 0; f < order.size(); ++f) frame_of_[order[f]] = static_cast<int>(f);
  }
  Image16 image(int view) const {
    const int f = frame_of_[view];
    if (!files_.count(f)) throw Error("POV-Ray wrote no image for frame " + std::to_string(f));
    const std::string& file = files_.at(f);
    Image16 img = parse_ppm(common::read_file(file), file);
    if (img.width != views_[view].width || img.height != views_[view].height) {
      throw Error("POV-Ray image of frame " + std::to_string(f) + " has the wrong size");
    }
    return img;
  }

 private:
  const std::vector<TileView>& views_;
  std::vector<int> frame_of_;
  std::map<int, std::string> files_;
};

// Canopy cover from the nadir image (view 0): per vehicle footprint and over the whole tile.
void measure_cover(const TileFrames& frames, const TileView& nadir, Tile* tile) {
  const Image16 img = frames.image(0);
  for (auto& v : tile->vehicles) v.canopy_cover = footprint_cover(img, nadir, v.footprint);
  const TileRecipe& r = tile->recipe;
  tile->canopy_cover = footprint_cover(
      img, nadir,
      {Vector2d(0, 0), Vector2d(r.extent_x, 0), Vector2d(r.extent_x, r.extent_y), Vector2d(0, r.extent_y)});
}

// The scan's columns: x y z (float64, shifted by the origin), sensor_x/y/z, view_idx, label, instance.
void add_tile_columns(formats::PointCloud* cloud) {
  const char* names[] = {"x", "y", "z", "sensor_x", "sensor_y", "sensor_z", "view_idx", "label", "instance"};
  const formats::FieldType types[] = {formats::kFloat64, formats::kFloat64, formats::kFloat64,
                                      formats::kFloat32, formats::kFloat32, formats::kFloat32,
                                      formats::kInt32,   formats::kUint32,  formats::kInt32};
  for (int c = 0; c < 9; ++c) cloud->add(names[c], types[c]);
}

// Appends the hits of image k (view_idx k - 1) inside the tile and the view's strip. The
// columns are written through their data pointers (one col() per column, not per value).
std::size_t append_view(const TileHits& hits, const TileView& v, std::size_t k, const TileRecipe& r,
                        formats::PointCloud* cloud, std::vector<std::size_t>* keep) {
  const Vector3d origin = r.has_origin ? r.origin : Vector3d::Zero();
  keep->clear();
  for (std::size_t i = 0; i < hits.p.size(); ++i) {
    const Vector3d& p = hits.p[i];
    if (p.x() < 0 || p.y() < 0 || p.x() > r.extent_x || p.y() > r.extent_y) continue;
    if (std::abs((p.head<2>() - v.strip_centre).dot(v.strip_across)) > v.strip_half) continue;
    keep->push_back(i);
  }
  const std::size_t base = cloud->size();
  cloud->resize(base + keep->size());
  double* col[9];
  for (int c = 0; c < 9; ++c) col[c] = cloud->col(static_cast<std::size_t>(c)).data() + base;
  const Eigen::Vector3f t = v.toward.cast<float>();
  for (std::size_t n = 0; n < keep->size(); ++n) {
    const std::size_t i = (*keep)[n];
    for (int a = 0; a < 3; ++a) {
      col[a][n] = hits.p[i][a] + origin[a];
      col[3 + a][n] = t[a];
    }
    col[6][n] = static_cast<double>(k - 1);
    col[7][n] = label_of(hits.cls[i]);
    col[8][n] = hits.cls[i] == static_cast<std::uint32_t>(Class::kVehicle) ? hits.instance[i] : 0;
  }
  return keep->size();
}

}  // namespace

// Every column is first reserved for one point per pixel of every image (address space only:
// pages are touched as points arrive), so the columns grow in place; grown image by image, every
// column was reallocated and copied several times (≈ a third of rangetrace's own CPU on a 40 mm
// tile, cost.md §13). The hits' buffers are reused from image to image for the same reason.
TileScan decode_tile(const std::function<Image16(int)>& image, const std::vector<TileView>& views,
                     const TileRecipe& r) {
  TileScan scan;
  add_tile_columns(&scan.cloud);
  std::size_t pixels = 0;
  for (std::size_t k = 1; k < views.size(); ++k)
    pixels += static_cast<std::size_t>(views[k].width) * views[k].height;
  for (std::size_t c = 0; c < scan.cloud.names().size(); ++c) scan.cloud.col(c).reserve(pixels);
  TileHits hits;
  std::vector<std::size_t> keep;
  for (std::size_t k = 1; k < views.size(); ++k) {
    const TileView& v = views[k];
    hits.p.clear();
    hits.cls.clear();
    hits.instance.clear();
    hits.pixel.clear();
    decode_tile_view(image(static_cast<int>(k)), v, &hits);
    scan.points_per_view.push_back(append_view(hits, v, k, r, &scan.cloud, &keep));
    scan.area_per_view.push_back(v.strip_area);
  }
  return scan;
}

TileScan run_tile(Tile* tile, const Params& params) {
  common::log::Phase prep("tile");
  std::optional<SensorPlan> plan;
  if (tile->recipe.sensor) {
    const TerrainModel terrain(tile->recipe, tile->seed);
    plan = plan_sensor(
        tile->recipe, [&](double x, double y) { return terrain.height(x, y); }, terrain.lo(), tile->top,
        tile->name);
  }
  std::vector<TileView> views = plan ? plan->views : tile_views(*tile);
  views.insert(views.begin(), canopy_view(*tile));     // frame of view 0: the canopy image
  check_tile_budget(views, tile->recipe, tile->name);  // with the tile's own terrain and trees
  prep.done(tile_summary(*tile, views.size() - 1) +
            (plan ? ", " + std::to_string(plan->pulses.size()) + " pulses on " +
                        std::to_string(plan->lines.size()) + " flight lines"
                  : std::string()));

  common::log::Phase render("render");
  TempDir tmp;
  const Staged st = stage_models(tile->models, tmp);
  const std::vector<int> order = frame_order(views);
  std::vector<TileView> frames;
  for (int k : order) frames.push_back(views[k]);
  const int canopy_frame = params.canopy_class_only
                               ? static_cast<int>(std::find(order.begin(), order.end(), 0) - order.begin())
                               : -1;
  common::write_file_atomic(tmp.path() + "/scene.pov", tile_pov(*tile, st, frames, 0, canopy_frame));
  const int nf = static_cast<int>(frames.size());
  // kRunsPerThread runs per thread, all in flight: POV-Ray's idle between frames overlaps.
  const int threads = kRunsPerThread * std::max(1, params.threads);
  std::vector<FrameRange> tasks = frame_ranges(frames, threads);
  if (params.window && !plan) add_windows(*tile, order, frames, &tasks);
  auto renames = st.renames;
  renames.emplace_back("scene.pov", "rangetrace's generated scene.pov (after the models' includes)");
  const TileFrames rendered(views, order,
                            render_frames(params.povray, tmp, st, "scene.pov", nf, tasks, threads, renames));
  double traced = 0, pixels = 0;
  for (const FrameRange& t : tasks) {
    const double n = t.last - t.first + 1;
    pixels += n * t.width * t.height;
    traced += t.col0 < 0 ? n * t.width * t.height : n * (t.col1 - t.col0 + 1) * double(t.row1 - t.row0 + 1);
  }
  char share[64];
  std::snprintf(share, sizeof share, " (%.0f%% of the pixels traced)", 100 * traced / pixels);
  render.done(std::to_string(nf) + " frames (" + std::to_string(nf - 1) + " images + canopy) in " +
              std::to_string(tasks.size()) + " POV-Ray runs" + (params.window && !plan ? share : ""));

  common::log::Phase decode("decode");
  measure_cover(rendered, views[0], tile);
  TileScan scan = plan ? sense_tile(
                             *plan, [&](int k) { return rendered.image(k + 1); }, tile, params.seed)
                       : decode_tile([&](int k) { return rendered.image(k); }, views, tile->recipe);
  double cover = 0;
  for (const auto& v : tile->vehicles) cover += v.canopy_cover;
  char summary[200];
  std::snprintf(summary, sizeof summary,
                "%zu points; canopy cover %.2f over the tile, %.2f on average over the vehicles",
                scan.cloud.size(), tile->canopy_cover,
                tile->vehicles.empty() ? 0.0 : cover / tile->vehicles.size());
  decode.done(summary);
  return scan;
}

// ---------------------------------------------------------------- truth and picture

namespace {

// Angles in degrees (+ 0.0: no "-0.0") and coordinates shifted by the tile's origin.
struct TruthUnits {
  Vector3d o;
  double angle(double rad) const { return rad * (180 / common::kPi) + 0.0; }
  documents::Point3 xyz(const Vector3d& p) const { return {p.x() + o.x(), p.y() + o.y(), p.z() + o.z()}; }
};

documents::Point3 plain(const Vector3d& p) { return {p.x(), p.y(), p.z()}; }

std::vector<documents::RenderedVehicle> truth_vehicles(const Tile& tile, const TruthUnits& u) {
  const Vector3d& o = u.o;
  std::vector<documents::RenderedVehicle> vehicles;
  for (const auto& v : tile.vehicles) {
    documents::RenderedVehicle e;
    e.instance = v.instance;
    e.model = v.model_name;
    // Procedural family instances carry their class (absent for other models: truth unchanged).
    e.cls = tile.models[v.model_index].vehicle_class;
    e.line = v.line;
    e.x = v.pose.anchor.x() + o.x();
    e.y = v.pose.anchor.y() + o.y();
    e.z = v.pose.anchor.z() + o.z();
    e.heading = u.angle(v.pose.heading);
    e.pitch = u.angle(v.pose.pitch);
    e.roll = u.angle(v.pose.roll);
    e.size = plain(v.size);
    for (const auto& p : v.footprint) e.footprint.push_back({p.x() + o.x(), p.y() + o.y()});
    e.canopy_cover = v.canopy_cover;
    vehicles.push_back(std::move(e));
  }
  return vehicles;
}

std::vector<documents::RenderedClutter> truth_clutter(const Tile& tile, const TruthUnits& u) {
  std::vector<documents::RenderedClutter> clutter;
  for (const auto& c : tile.objects) {
    documents::RenderedClutter e;
    e.kind = c.kind;
    e.centre = u.xyz(c.pose.anchor + c.pose.r * (c.lo + c.size / 2));
    e.size = plain(c.size);
    e.heading = u.angle(c.pose.heading);
    e.pitch = u.angle(c.pose.pitch);
    e.roll = u.angle(c.pose.roll);
    clutter.push_back(std::move(e));
  }
  return clutter;
}

// The images in view_idx order: which pass (heading, flight line) and look each is.
std::vector<documents::RenderedImage> truth_images(const Tile& tile, const TruthUnits& u) {
  const TileRecipe& r = tile.recipe;
  std::vector<documents::RenderedImage> images;
  const std::vector<TileView> views = tile_views(tile);
  for (std::size_t k = 0; k < views.size(); ++k) {
    const TileView& v = views[k];
    const Look& look = r.looks[v.look_idx];
    images.push_back({static_cast<std::int64_t>(k), u.angle(r.headings[v.heading_idx]), v.line,
                      u.angle(look.elevation), u.angle(look.azimuth), plain(v.toward), v.strip_area});
  }
  return images;
}

// Sensor mode: the sensor's keys, the flight lines and the measured density.
documents::RenderedSensor truth_sensor(const Tile& tile, const TruthUnits& u) {
  const Sensor& s = *tile.recipe.sensor;
  documents::RenderedSensor out;
  out.preset = s.name;
  out.keys = sensor_keys(s);
  for (const auto& l : tile.flight_lines)
    out.flight_lines.push_back({l.id, u.angle(l.heading), l.offset, u.xyz(l.start), u.xyz(l.end), l.t0, l.t1});
  out.returns_per_m2 = tile.returns_per_m2;
  out.first_returns_per_m2 = tile.pulses_per_m2;
  out.pulses_per_m2 = tile.fired_per_m2;
  for (std::size_t n : tile.pulses_by_returns) out.pulses_by_returns.push_back(static_cast<std::int64_t>(n));
  return out;
}

}  // namespace

std::string truth_json(const Tile& tile, const std::vector<std::pair<std::string, std::string>>& params) {
  const TileRecipe& r = tile.recipe;
  const TruthUnits u{r.has_origin ? r.origin : Vector3d::Zero()};
  documents::RenderedTruth t;
  t.scene = tile.name;
  t.extent_x = r.extent_x;
  t.extent_y = r.extent_y;
  if (r.has_origin) t.origin = u.xyz(Vector3d::Zero());
  t.terrain = r.terrain == Terrain::kFlat ? "flat" : r.terrain == Terrain::kSlope ? "slope" : "rolling";
  t.angles = "degrees; R = Rz(heading) Ry(pitch) Rx(roll), vehicle x forward, y left, z up";
  t.vehicles = truth_vehicles(tile, u);
  t.clutter = truth_clutter(tile, u);
  for (const auto& tree : tile.trees) (tree.bush ? t.bushes : tree.conifer ? t.conifer : t.broadleaf)++;
  t.discs = static_cast<std::int64_t>(r.discs.size());
  t.canopy_cover = tile.canopy_cover;
  t.canopy_spacing = r.canopy_spacing;
  if (r.sensor) {
    t.sensor = truth_sensor(tile, u);
  } else {
    t.images = truth_images(tile, u);
  }
  return documents::write_scene_truth(t, {"rangetrace", CANOPY_VERSION, params, {tile.name}});
}

std::string render_tile_picture(const Tile& tile, const Params& params) {
  const TileRecipe& r = tile.recipe;
  const double spacing = std::max(r.extent_x, r.extent_y) / std::max(8, params.size);
  TileRecipe coarse = r;
  coarse.canopy_spacing = spacing;
  Tile t = tile;
  t.recipe = coarse;
  const TileView v = canopy_view(t);
  TempDir tmp;
  const Staged st = stage_models(tile.models, tmp);
  common::write_file_atomic(tmp.path() + "/picture.pov", tile_pov(tile, st, {v}, 1));
  std::vector<std::string> args = {"-D", "-P", "-V"};
  args.insert(args.end(), st.args.begin(), st.args.end());
  args.insert(args.end(),
              {"+W" + std::to_string(v.width), "+H" + std::to_string(v.height), "+A0.05", "+R3", "+FN8",
               "+Ipicture.pov", "+Opicture.png", "+WT" + std::to_string(std::max(1, params.threads))});
  auto renames = st.renames;
  renames.emplace_back("picture.pov", "rangetrace's generated picture.pov");
  run_povray(params.povray, st, tmp.path(), args, "picture.log", renames);
  return common::read_file(tmp.path() + "/picture.png");
}

}  // namespace canopy::rangetrace
