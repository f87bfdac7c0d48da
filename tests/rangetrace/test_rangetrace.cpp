// rangetrace: frames, views, foliage, decoding and real POV-Ray renders of small synthetic
// scenes with known geometry (64-128 pixel images to stay fast).
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "rangetrace/tile.h"
#include "rangetrace/rangetrace.h"

using namespace canopy;
using namespace canopy::rangetrace;
using Eigen::Vector3d;

namespace {

const double kDeg = canopy::common::kDegree;

std::string tmp_dir() {
  const std::string d = std::string(CANOPY_TEST_TMP) + "/rangetrace";
  ::mkdir(CANOPY_TEST_TMP, 0755);
  ::mkdir(d.c_str(), 0755);
  return d;
}

Model inline_model(const std::string& code) {
  Model m;
  m.name = "synthetic";
  m.inline_code = code;
  return m;
}

// Distance from p to the surface of the axis-aligned box [lo, hi].
double box_surface_distance(const Vector3d& p, const Vector3d& lo, const Vector3d& hi) {
  const Vector3d c = (lo + hi) / 2, h = (hi - lo) / 2;
  const Vector3d d = (p - c).cwiseAbs() - h;
  if ((d.array() <= 0).all()) return -d.maxCoeff();
  return d.cwiseMax(0.0).norm();
}

struct Hits {
  std::vector<Vector3d> p;
  std::vector<std::uint32_t> label;
  std::vector<Vector3d> sensor;
  std::vector<int> view;
};

Hits hits(const formats::PointCloud& c) {
  Hits h;
  for (std::size_t i = 0; i < c.size(); ++i) {
    h.p.emplace_back(c.col("x")[i], c.col("y")[i], c.col("z")[i]);
    h.sensor.emplace_back(c.col("sensor_x")[i], c.col("sensor_y")[i], c.col("sensor_z")[i]);
    h.label.push_back(static_cast<std::uint32_t>(c.col("label")[i]));
    h.view.push_back(static_cast<int>(c.col("view_idx")[i]));
  }
  return h;
}

SceneRecipe two_views(int foliage) {
  SceneRecipe s;
  s.name = "test";
  s.views = {{20 * kDeg, 75 * kDeg}, {200 * kDeg, 60 * kDeg}};
  s.foliage_count = foliage;
  return s;
}

Params small(int size = 96, double spacing = 0.06) {
  Params p;
  p.size = size;
  p.spacing = spacing;
  p.threads = 2;
  return p;
}

}  // namespace

TEST_CASE("circle, flyby and dodecahedron views") {
  const auto c = circle_views(12, 75 * kDeg);
  REQUIRE(c.size() == 12);
  for (int k = 0; k < 12; ++k) {
    CHECK(c[k].azimuth == Approx(k * 30 * kDeg));
    CHECK(c[k].elevation == Approx(75 * kDeg));
  }
  const auto f = flyby_views(10, 75 * kDeg, 45 * kDeg);
  REQUIRE(f.size() == 20);
  CHECK(f[0].azimuth == Approx(45 * kDeg));
  CHECK(f[9].azimuth == Approx(-45 * kDeg));
  // Behind the tail: from 45 deg off the rear axis on the right to 45 deg on the left.
  CHECK(std::abs(std::remainder(f[10].azimuth + 135 * kDeg, 2 * canopy::common::kPi)) < 1e-9);
  CHECK(std::abs(std::remainder(f[19].azimuth - 135 * kDeg, 2 * canopy::common::kPi)) < 1e-9);
  // Straight ground tracks: tan(bearing) evenly spaced in the front pass.
  for (int k = 1; k < 10; ++k) {
    CHECK(std::tan(f[k - 1].azimuth) - std::tan(f[k].azimuth) == Approx(2.0 / 9));
  }
  const auto d = dodecahedron_views();
  REQUIRE(d.size() == 10);
  int upper = 0, lower = 0;
  for (const auto& v : d) {
    if (std::abs(v.elevation - 52.6226 * kDeg) < 1e-4) ++upper;
    if (std::abs(v.elevation - 10.8123 * kDeg) < 1e-4) ++lower;
  }
  CHECK(upper == 5);
  CHECK(lower == 5);
  CHECK(d[0].azimuth == Approx(0).margin(1e-12));
  // Neighbouring vertices of the upper pentagon are 72 degrees apart.
  CHECK(d[1].azimuth - d[0].azimuth == Approx(72 * kDeg));
}

TEST_CASE("built-in scene recipes") {
  const SceneRecipe circle = load_scene("circle");
  CHECK(circle.views.size() == 12);
  CHECK(circle.foliage_count == 500);
  CHECK(circle.foliage_radius == Approx(0.1));
  CHECK(circle.foliage_band == Approx(2.0));
  CHECK(circle.foliage_square == Approx(12.2));
  const SceneRecipe flyby = load_scene("flyby");
  CHECK(flyby.views.size() == 20);
  CHECK(flyby.foliage_count == 500);
  const SceneRecipe un = load_scene("unoccluded");
  CHECK(un.views.size() == 10);
  CHECK(un.foliage_count == 0);
}

TEST_CASE("every recipe of share/scenes is found by its short name") {
  // A tile recipe by name: the same recipe as by path, named by the short name, and its
  // directory (against which model paths resolve) is share/scenes/.
  const SceneRecipe forest = load_scene("forest");
  REQUIRE(forest.tile);
  CHECK(forest.name == "forest");
  CHECK(forest.tile->extent_x == Approx(40));
  CHECK(forest.tile->random_vehicles == 6);
  CHECK(forest.tile->spacing == Approx(0.08));
  CHECK(forest.tile->dir == common::share_dir() + "/scenes/");
  const SceneRecipe by_path = load_scene(std::string(CANOPY_SOURCE_DIR) + "/share/scenes/forest.scene");
  REQUIRE(by_path.tile);
  CHECK(by_path.tile->random_models == forest.tile->random_models);
  CHECK(by_path.tile->looks.size() == forest.tile->looks.size());
  // The thesis scenes keep their names; an unknown short name says where it looked.
  CHECK(load_scene("flyby").name == "flyby");
  try {
    load_scene("forst");
    FAIL("no error");
  } catch (const common::UsageError& e) {
    CHECK_THAT(std::string(e.what()), Catch::Contains("'forst'") && Catch::Contains("/scenes/forst.scene"));
  }
}

TEST_CASE("scene recipe errors name the file and line") {
  CHECK_THROWS_WITH(parse_scene("views = circle 12 75deg\nbogus = 1\n", "s.scene"),
                    Catch::Contains("s.scene") && Catch::Contains("line 2") && Catch::Contains("bogus"));
  CHECK_THROWS_AS(parse_scene("foliage_count = 3\n", "s.scene"), common::DataError);
  CHECK_THROWS_AS(parse_scene("view = 0deg 95deg\n", "s.scene"), common::DataError);
  const SceneRecipe s = parse_scene("view = 10deg 30deg  # one view\nview = 0.5rad 1.0rad\n", "x");
  REQUIRE(s.views.size() == 2);
  CHECK(s.views[1].azimuth == Approx(0.5));
}

TEST_CASE("foliage: count, band, square, orientation and seeding") {
  SceneRecipe s = load_scene("circle");
  Pose pose;
  pose.heading = 30 * kDeg;
  pose.position = {2.0, -1.0};
  const double top = 2.4;
  const auto a = make_foliage(s, pose, top, 7);
  REQUIRE(a.size() == 500);
  double zmin = 1e9, zmax = -1e9, umax = 0, vmax = 0;
  Vector3d mean_n = Vector3d::Zero();
  for (const auto& d : a) {
    CHECK(d.radius == 0.1);
    CHECK(d.normal.norm() == Approx(1.0));
    const double dx = d.centre.x() - 2.0, dy = d.centre.y() + 1.0;
    const double u = std::cos(pose.heading) * dx + std::sin(pose.heading) * dy;
    const double v = -std::sin(pose.heading) * dx + std::cos(pose.heading) * dy;
    umax = std::max(umax, std::abs(u));
    vmax = std::max(vmax, std::abs(v));
    zmin = std::min(zmin, d.centre.z());
    zmax = std::max(zmax, d.centre.z());
    mean_n += d.normal.cwiseAbs();
  }
  CHECK(zmin >= top);
  CHECK(zmax <= top + 2.0);
  CHECK(zmax - zmin > 1.9);  // the band is filled
  CHECK(umax <= 6.1);
  CHECK(vmax <= 6.1);
  CHECK(umax > 5.9);
  CHECK(vmax > 5.9);
  // Random orientation: mean |n_i| of uniform unit vectors is 1/2 per axis.
  mean_n /= 500.0;
  CHECK(mean_n.x() == Approx(0.5).margin(0.05));
  CHECK(mean_n.z() == Approx(0.5).margin(0.05));
  const auto b = make_foliage(s, pose, top, 7);
  const auto c = make_foliage(s, pose, top, 8);
  CHECK(a[499].centre == b[499].centre);
  CHECK(a[0].centre != c[0].centre);
}

TEST_CASE("crop box follows the vehicle heading and position") {
  Params p;
  p.pose.heading = 90 * kDeg;
  p.pose.position = {3, 1};
  const Placement pl = place(Vector3d(-2, -1, 0), Vector3d(2, 1, 2), p.pose);
  CHECK(pl.centre.isApprox(Vector3d(3, 1, 1)));
  CHECK(in_crop(Vector3d(3, 5.9, 1), pl, p));  // along the long axis (now +y)
  CHECK_FALSE(in_crop(Vector3d(3, 6.1, 1), pl, p));
  CHECK(in_crop(Vector3d(4.9, 1, 1), pl, p));
  CHECK_FALSE(in_crop(Vector3d(5.1, 1, 1), pl, p));
  CHECK(in_crop(Vector3d(3, 1, -0.99), pl, p));
  CHECK_FALSE(in_crop(Vector3d(3, 1, 3.01), pl, p));
}

TEST_CASE("decode_view inverts the colour coding") {
  Params p;
  p.size = 2;
  const Placement pl = place(Vector3d(-1, -1, 0), Vector3d(1, 1, 1), p.pose);
  const Encoding enc = encoding_for(pl, p);
  const Vector3d q(1.234, -0.567, 0.891);
  Image16 coords, labels;
  coords.width = labels.width = 2;
  coords.height = labels.height = 1;
  coords.rgb.assign(6, 0);
  labels.rgb = {65535, 0, 0, 0, 0, 0};  // pixel 1: no hit
  for (int a = 0; a < 3; ++a) {
    coords.rgb[a] = static_cast<std::uint16_t>(std::lround((q[a] - enc.lo[a]) / enc.span[a] * 65535));
  }
  ScanColumns out;
  decode_view(coords, labels, enc, pl, p, Vector3d(0, 0, 2), 4, &out);
  REQUIRE(out.points.size() == 1);
  CHECK((out.points[0].cast<double>() - q).norm() < 2e-4);
  CHECK(out.label[0] == formats::kLabelTarget);
  CHECK(out.view_idx[0] == 4);
  CHECK(out.sensor[0].cast<double>().isApprox(Vector3d(0, 0, 1)));
}

// A 2 x 1 x 0.8 m box (long along model x) with a 0.4 x 0.3 x 0.4 m bump on the model's left
// side (+y in the world frame = +z in POV-Ray's), placed off the origin.
const char* const kBoxWithBump =
    "#declare Vehicle = union { box { <-1, 0, -0.5>, <1, 0.8, 0.5> }\n"
    "  box { <-0.2, 0.8, 0.2>, <0.2, 1.2, 0.5> } }\n";

TEST_CASE("plane and box decode to within 0.5 mm at right-handed z-up coordinates") {
  Params p = small();
  p.pose.position = {1.5, -0.7};
  const auto cloud = render_scan(inline_model(kBoxWithBump), two_views(0), p);
  const Hits h = hits(cloud);
  REQUIRE(h.p.size() > 1000);
  const Vector3d lo(0.5, -1.2, 0), hi(2.5, -0.2, 0.8);
  const Vector3d blo(1.3, -0.5, 0.8), bhi(1.7, -0.2, 1.2);  // bump on the +y side
  int target = 0, ground = 0, bump = 0;
  double worst = 0;
  for (std::size_t i = 0; i < h.p.size(); ++i) {
    const Vector3d& q = h.p[i];
    if (h.label[i] == formats::kLabelGround) {
      ++ground;
      worst = std::max(worst, std::abs(q.z()));
    } else {
      REQUIRE(h.label[i] == formats::kLabelTarget);
      ++target;
      const double d = std::min(box_surface_distance(q, lo, hi), box_surface_distance(q, blo, bhi));
      worst = std::max(worst, d);
      if (q.z() > 0.85) {
        ++bump;
        CHECK(q.y() > -0.5 - 5e-4);  // the bump is on the vehicle's +y side
      }
    }
  }
  CHECK(worst < 5e-4);
  CHECK(target > 300);
  CHECK(ground > 1000);
  CHECK(bump > 20);
  // Sensor vectors: the unit direction of the view toward its sensor.
  const SceneRecipe scene = two_views(0);
  for (std::size_t i = 0; i < h.p.size(); i += 97) {
    const View& v = scene.views[h.view[i]];
    const Vector3d want(std::cos(v.elevation) * std::cos(v.azimuth),
                        std::cos(v.elevation) * std::sin(v.azimuth), std::sin(v.elevation));
    CHECK((h.sensor[i] - want).norm() < 1e-6);
  }
}

TEST_CASE("heading turns the vehicle counter-clockwise about +z") {
  Params p = small(80, 0.05);
  p.pose.heading = 90 * kDeg;
  const auto cloud = render_scan(inline_model(kBoxWithBump), two_views(0), p);
  const Hits h = hits(cloud);
  // Long axis now along y; the bump (model +y side) turns to the world -x side.
  const Vector3d lo(-0.5, -1, 0), hi(0.5, 1, 0.8), blo(-0.5, -0.2, 0.8), bhi(-0.2, 0.2, 1.2);
  int bump = 0;
  for (std::size_t i = 0; i < h.p.size(); ++i) {
    if (h.label[i] != formats::kLabelTarget) continue;
    const double d = std::min(box_surface_distance(h.p[i], lo, hi), box_surface_distance(h.p[i], blo, bhi));
    CHECK(d < 5e-4);
    if (h.p[i].z() > 0.85) ++bump;
  }
  CHECK(bump > 20);
}

TEST_CASE("labels on a synthetic scene with foliage") {
  Params p = small(128, 0.05);
  p.seed = 3;
  SceneRecipe s = two_views(60);
  s.foliage_radius = 0.3;
  s.foliage_square = 5.0;
  s.foliage_band = 1.0;
  const Model m = inline_model("#declare Vehicle = box { <-1, 0, -0.5>, <1, 0.8, 0.5> }\n");
  const auto cloud = render_scan(m, s, p);
  const Hits h = hits(cloud);
  const Placement pl = place(Vector3d(-1, -0.5, 0), Vector3d(1, 0.5, 0.8), p.pose);
  const auto discs = make_foliage(s, p.pose, pl.top, p.seed);
  int counts[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < h.p.size(); ++i) {
    const Vector3d& q = h.p[i];
    REQUIRE(h.label[i] >= 1);
    REQUIRE(h.label[i] <= 3);
    ++counts[h.label[i]];
    if (h.label[i] == formats::kLabelGround) {
      CHECK(std::abs(q.z()) < 5e-4);
    } else if (h.label[i] == formats::kLabelTarget) {
      CHECK(box_surface_distance(q, Vector3d(-1, -0.5, 0), Vector3d(1, 0.5, 0.8)) < 5e-4);
    } else {
      double best = 1e9;
      for (const auto& d : discs) {
        const Vector3d r = q - d.centre;
        const double off = std::abs(r.dot(d.normal));
        if ((r - r.dot(d.normal) * d.normal).norm() <= d.radius + 1e-3) best = std::min(best, off);
      }
      CHECK(best < 5e-4);
    }
  }
  CHECK(counts[1] > 100);
  CHECK(counts[2] > 100);
  CHECK(counts[3] > 100);
}

TEST_CASE("same seed gives a byte-identical scan, a different seed different foliage") {
  Params p = small(64, 0.08);
  const Model m = inline_model("#declare Vehicle = box { <-1, 0, -0.5>, <1, 0.8, 0.5> }\n");
  SceneRecipe s = two_views(300);
  p.seed = 11;
  const std::string a = formats::serialize_pcd(render_scan(m, s, p));
  p.threads = 1;
  const std::string b = formats::serialize_pcd(render_scan(m, s, p));
  p.seed = 12;
  const std::string c = formats::serialize_pcd(render_scan(m, s, p));
  CHECK(a == b);
  CHECK(a != c);
}

TEST_CASE("crop_window: the crop box projects to known pixel bounds") {
  // Default image (512 pixels of 30 mm: field 15.36 m), crop box 10 x 4 x 4 m centred on the
  // placed box's centre. Pixel i's ray passes at (i + 0.5) / 512 - 0.5 of the field, so a
  // point at offset r along the image's right lies at column r / 0.03 + 255.5.
  Params p;
  const double s = std::sqrt(0.5);
  // Heading 0, view from +x at 45 deg: right = world +y (the box's +-2 m across), up =
  // (-s, 0, s) (the box's +-5 m along and +-2 m up: at most 5 s + 2 s = 4.95 m).
  const double across = 2 / 0.03, up = (5 * s + 2 * s) / 0.03;
  const auto expect = [&](const PixelWindow& w) {
    CHECK(w.col0 == static_cast<int>(std::floor(255.5 - across)) - 2);  // 186
    CHECK(w.col1 == static_cast<int>(std::ceil(255.5 + across)) + 2);   // 325
    CHECK(w.row0 == static_cast<int>(std::floor(255.5 - up)) - 2);      // 88
    CHECK(w.row1 == static_cast<int>(std::ceil(255.5 + up)) + 2);       // 423
  };
  {
    const PixelWindow w = crop_window(p, View{0, 45 * kDeg});
    expect(w);
    CHECK(w.col0 == 186);
    CHECK(w.col1 == 325);
    CHECK(w.row0 == 88);
    CHECK(w.row1 == 423);
  }
  {
    // Turned by 90 deg and moved: the same view relative to the vehicle gives the same window
    // (camera from +y: right = world -x, the box's +-2 m across again).
    Params q = p;
    q.pose.heading = 90 * kDeg;
    q.pose.position = {3, -7};
    expect(crop_window(q, View{0, 45 * kDeg}));
    // From the side (azimuth 90 deg relative), the 10 m length runs across the image.
    const PixelWindow side = crop_window(q, View{90 * kDeg, 45 * kDeg});
    CHECK(side.col0 == static_cast<int>(std::floor(255.5 - 5 / 0.03)) - 2);  // 86
    CHECK(side.col1 == static_cast<int>(std::ceil(255.5 + 5 / 0.03)) + 2);   // 425
    CHECK(side.row0 == static_cast<int>(std::floor(255.5 - 4 * s / 0.03)) - 2);
    CHECK(side.row1 == static_cast<int>(std::ceil(255.5 + 4 * s / 0.03)) + 2);
  }
  {
    // A field smaller than the box: the whole image; straight down: the whole image too.
    Params q = p;
    q.size = 64;
    const PixelWindow w = crop_window(q, View{30 * kDeg, 60 * kDeg});
    CHECK((w.col0 == 0 && w.col1 == 63 && w.row0 == 0 && w.row1 == 63));
    const PixelWindow d = crop_window(p, View{0, 90 * kDeg});
    CHECK((d.col0 == 0 && d.col1 == 511 && d.row0 == 0 && d.row1 == 511));
  }
}

TEST_CASE("a render traced in windows is byte-identical to the full render") {
  // A 24 m field around a 10 x 4 x 4 m crop box: the windows trace well under half the pixels,
  // the rest (ground and foliage outside the box) never gave a kept point.
  Params p = small(120, 0.2);
  p.seed = 5;
  p.pose.heading = 30 * kDeg;
  p.pose.position = {2, -1};
  SceneRecipe s = two_views(150);
  s.views.push_back({100 * kDeg, 35 * kDeg});
  s.views.push_back({290 * kDeg, 15 * kDeg});
  const Model m = inline_model(kBoxWithBump);
  double traced = 0;
  for (const View& v : s.views) {
    const PixelWindow w = crop_window(p, v);
    traced += double(w.col1 - w.col0 + 1) * (w.row1 - w.row0 + 1);
  }
  CHECK(traced < 0.5 * s.views.size() * p.size * p.size);
  p.window = true;
  const auto windowed = render_scan(m, s, p);
  p.window = false;
  const auto full = render_scan(m, s, p);
  REQUIRE(full.size() > 2000);
  CHECK(formats::serialize_pcd(windowed) == formats::serialize_pcd(full));
}

TEST_CASE("a POV-Ray failure reports POV-Ray's own message") {
  Params p = small(16, 0.5);
  const Model bad = inline_model("#declare Vehicle = union { box { 0, 1 } spere { 0, 1 } }\n");
  CHECK_THROWS_WITH(render_scan(bad, two_views(0), p), Catch::Contains("POV-Ray failed") &&
                                                           Catch::Contains("Parse Error") &&
                                                           Catch::Contains("spere"));
  const Model none = inline_model("#declare NotAVehicle = box { 0, 1 }\n");
  CHECK_THROWS_WITH(render_scan(none, two_views(0), p), Catch::Contains("does not declare Vehicle"));
}

TEST_CASE("built-in models: real-world sizes that fit the crop box") {
  Params p;
  for (const char* name : kBuiltinModels) {
    INFO(name);
    const auto [lo, hi] = model_bounds(load_model(name, MeshImport{}), p);
    const Vector3d size = hi - lo;
    CHECK(std::abs(lo.z()) < 1e-6);           // standing on the ground
    CHECK(std::abs(lo.x() + hi.x()) < 2.6);   // roughly centred (a tank's gun)
    CHECK(std::abs(lo.y() + hi.y()) < 1e-6);  // symmetric across
    CHECK(size.x() <= 10.0);
    CHECK(size.y() <= 4.0);
    CHECK(size.z() <= 4.0);
    CHECK(size.x() > size.y());  // long axis along x
  }
  const auto [lo, hi] = model_bounds(load_model("obj1", MeshImport{}), p);
  CHECK((hi - lo).isApprox(Vector3d(8.1, 3.1, 2.0), 1e-6));
}

namespace {

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// Renders a mesh model with the unoccluded-style views and checks every target point lies on
// the box [-L/2, L/2] x [-W/2, W/2] x [0, H] in metres.
void check_box_mesh(const Model& m, double length, double width, double height) {
  Params p = small(96, 0.05);
  const auto cloud = render_scan(m, two_views(0), p);
  const Hits h = hits(cloud);
  const Vector3d lo(-length / 2, -width / 2, 0), hi(length / 2, width / 2, height);
  int target = 0;
  Vector3d seen_lo = Vector3d::Constant(1e9), seen_hi = Vector3d::Constant(-1e9);
  for (std::size_t i = 0; i < h.p.size(); ++i) {
    if (h.label[i] != formats::kLabelTarget) continue;
    ++target;
    CHECK(box_surface_distance(h.p[i], lo, hi) < 5e-4);
    seen_lo = seen_lo.cwiseMin(h.p[i]);
    seen_hi = seen_hi.cwiseMax(h.p[i]);
  }
  CHECK(target > 100);
  CHECK(seen_hi.z() == Approx(height).margin(5e-4));
  CHECK((seen_hi - seen_lo).x() == Approx(length).margin(0.1));
}

}  // namespace

TEST_CASE("mesh files round-trip through the POV-Ray conversion at the right scale") {
  const std::string dir = tmp_dir();
  // OBJ in millimetres, y up: 2000 x 800 (up) x 1000 mm box with quads, offset so centring
  // and grounding are exercised.
  std::string obj;
  const double X[2] = {3000, 5000}, Y[2] = {100, 900}, Z[2] = {-500, 500};
  for (int i = 0; i < 8; ++i) {
    obj += "v " + std::to_string(X[i & 1]) + " " + std::to_string(Y[(i >> 1) & 1]) + " " +
           std::to_string(Z[(i >> 2) & 1]) + "\n";
  }
  obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  write_text(dir + "/box.obj", obj);
  MeshImport mm;
  mm.scale = 1e-3;
  mm.z_up = false;
  check_box_mesh(load_model(dir + "/box.obj", mm), 2.0, 1.0, 0.8);

  // ASCII STL in centimetres, z up: 300 x 120 x 90 cm.
  const double a[2] = {-150, 150}, b[2] = {-60, 60}, c[2] = {10, 100};
  auto vtx = [&](int i) {
    return "vertex " + std::to_string(a[i & 1]) + " " + std::to_string(b[(i >> 1) & 1]) + " " +
           std::to_string(c[(i >> 2) & 1]) + "\n";
  };
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::string stl = "solid box\n";
  for (const auto& q : quads) {
    for (int t = 0; t < 2; ++t) {
      stl += "facet normal 0 0 0\nouter loop\n" + vtx(q[0]) + vtx(q[1 + t]) + vtx(q[2 + t]) +
             "endloop\nendfacet\n";
    }
  }
  stl += "endsolid box\n";
  write_text(dir + "/box.stl", stl);
  MeshImport cm;
  cm.scale = 1e-2;
  check_box_mesh(load_model(dir + "/box.stl", cm), 3.0, 1.2, 0.9);

  // PLY in metres through formats::write_ply.
  formats::Mesh ply;
  ply.vertices.resize(8);
  auto& x = ply.vertices.add("x");
  auto& y = ply.vertices.add("y");
  auto& z = ply.vertices.add("z");
  for (int i = 0; i < 8; ++i) {
    x[i] = i & 1 ? 1.25 : -1.25;
    y[i] = (i >> 1) & 1 ? 0.5 : -0.5;
    z[i] = (i >> 2) & 1 ? 1.0 : 0.0;
  }
  for (const auto& q : quads) {
    ply.faces.push_back({q[0], q[1], q[2]});
    ply.faces.push_back({q[0], q[2], q[3]});
  }
  formats::write_ply(ply, dir + "/box.ply");
  check_box_mesh(load_model(dir + "/box.ply", MeshImport{}), 2.5, 1.0, 1.0);
}

TEST_CASE("rangetrace CLI: failure exits 1 and leaves no output") {
  const std::string dir = tmp_dir();
  write_text(dir + "/bad.inc", "#declare Vehicle = union { box { 0, 1 } spere { 0, 1 } }\n");
  const std::string out = dir + "/bad_out.pcd";
  std::remove(out.c_str());
  const std::string cmd = std::string(CANOPY_BIN_DIR) + "/rangetrace --model " + dir +
                          "/bad.inc --scene unoccluded --size 16 -o " + out + " 2>" + dir + "/bad.err";
  const int rc = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(rc) == 1);
  struct stat st {};
  CHECK(::stat(out.c_str(), &st) != 0);
  std::ifstream err(dir + "/bad.err");
  const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  CHECK(text.find("Parse Error") != std::string::npos);
}

TEST_CASE("mesh importer: malformed OBJ/STL/PLY bytes are DataErrors naming the file") {
  // What `--model x.obj|.stl|.ply` parses before POV-Ray (and fuzz/fuzz_mesh.cpp drives). The
  // parsers' own errors are tested in tests/formats/test_mesh_import.cpp; here, what the
  // conversion adds, and that parser errors pass through naming the file.
  const MeshImport m;
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  struct Case {
    std::string bytes, ext, want;
  };
  const Case cases[] = {
      {tri + "f 1 2 0\n", "obj", "line 4: face index out of range"},
      {tri, "obj", "mesh has no faces"},
      {"solid x\nfacet normal 0 0 1\nendfacet\n", "stl", "mesh has no faces"},
  };
  for (const auto& c : cases) {
    INFO(c.bytes);
    try {
      mesh_file_to_pov(c.bytes, "bad." + c.ext, c.ext, m);
      FAIL("accepted");
    } catch (const common::DataError& e) {
      CHECK_THAT(std::string(e.what()), Catch::Contains("bad." + c.ext) && Catch::Contains(c.want));
    }
  }
  // Valid: a quad with v/vt/vn and a relative index -> two triangles; millimetres -> metres.
  MeshImport mm;
  mm.scale = 1e-3;
  const std::string pov = mesh_file_to_pov(
      "v 0 0 0\nv 1000 0 0\nv 1000 2000 0\nv 0 2000 0\nf 1/1/1 2//1 3 -1\n", "quad.obj", "obj", mm);
  CHECK_THAT(pov, Catch::Contains("vertex_vectors { 4") && Catch::Contains("face_indices { 2"));
  CHECK_THAT(pov, Catch::Contains("<0, 0, 0>,\n    <1, 0, 0>,\n    <1, 0, 2>,\n    <0, 0, 2>"));
  CHECK_THAT(pov, Catch::Contains("<0, 1, 2>,\n    <0, 2, 3>"));
}
