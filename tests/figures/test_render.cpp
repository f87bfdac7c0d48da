// The OpenGL subcommands through the binary (under xvfb-run -a when DISPLAY is unset):
// a hand-built box with a red top, green front (+x) and blue sides renders at the requested
// size with its colours, the front on the left (camera at the front-left), the same camera
// for any mesh with the fixed box framing, byte-identical reruns; plot writes a PNG of the
// requested size holding the line colours; bad input exits 1 and leaves no file.
#include <catch2/catch.hpp>

#include "helpers.h"

using namespace canopy;
using namespace canopy::figures;
using namespace canopy::figures::testing;

namespace {

formats::Mesh box_mesh() {
  formats::Mesh m;
  add_box(m, {-2, -1, 0}, {2, 1, 1.5}, {220, 30, 30}, {30, 180, 30}, {30, 30, 220});
  return m;
}

std::string render_cmd(const fs::path& ply, const fs::path& png, const std::string& extra = "") {
  return display_prefix() + kBin + " mesh -i " + ply.string() + " -o " + png.string() + " " + extra;
}

}  // namespace

TEST_CASE("xvfb-run is available when there is no X display") {
  if (display_prefix().empty()) return;  // a display is set: nothing to check
  INFO("DISPLAY is unset and xvfb-run is missing: install the Debian packages xvfb and xauth");
  REQUIRE(have_xvfb_run());
}

TEST_CASE("figures mesh: a two-colour box renders with both colours, front on the left") {
  const fs::path dir = fresh_dir("mesh");
  formats::write_ply(box_mesh(), (dir / "box.ply").string());
  std::string err;
  REQUIRE(sh(render_cmd(dir / "box.ply", dir / "box.png", "--width 320 --height 240"), dir / "err", &err) == 0);
  const Image im = read_png((dir / "box.png").string());
  REQUIRE(im.width == 320);
  REQUIRE(im.height == 240);
  int red = 0, green = 0, blue = 0;
  double green_x = 0, blue_x = 0;
  for (int y = 0; y < im.height; ++y) {
    for (int x = 0; x < im.width; ++x) {
      const auto* p = im.at(x, y);
      if (reddish(p)) ++red;
      if (greenish(p)) ++green, green_x += x;
      if (bluish(p)) ++blue, blue_x += x;
    }
  }
  CHECK(red > 500);
  CHECK(green > 100);
  CHECK(blue > 300);
  CHECK(green_x / green < blue_x / blue);  // the front (+x) face is seen on the left
  CHECK(white(im.at(0, 0)));
  CHECK(white(im.at(319, 239)));

  REQUIRE(sh(render_cmd(dir / "box.ply", dir / "again.png", "--width 320 --height 240"), dir / "err", &err) ==
          0);
  CHECK(slurp(dir / "box.png") == slurp(dir / "again.png"));
}

TEST_CASE("figures mesh: fixed box framing keeps the camera; bounds framing zooms in") {
  const fs::path dir = fresh_dir("camera");
  formats::Mesh one = box_mesh();
  formats::Mesh two = box_mesh();
  add_box(two, {-4.8, 1.2, 0}, {-4.3, 1.7, 0.5}, {30, 180, 30}, {30, 180, 30}, {30, 180, 30}, 1);
  formats::write_ply(one, (dir / "one.ply").string());
  formats::write_ply(two, (dir / "two.ply").string());
  std::string err;
  for (const char* name : {"one", "two"}) {
    REQUIRE(sh(render_cmd(dir / (std::string(name) + ".ply"), dir / (std::string(name) + ".png")),
               dir / "err", &err) == 0);
  }
  REQUIRE(sh(render_cmd(dir / "one.ply", dir / "bounds.png", "--framing bounds"), dir / "err", &err) == 0);
  const Image a = read_png((dir / "one.png").string());
  const Image b = read_png((dir / "two.png").string());
  const Image c = read_png((dir / "bounds.png").string());
  REQUIRE(a.width == 640);
  REQUIRE(b.width == 640);
  int covered = 0, same = 0, covered_bounds = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      if (!white(a.at(x, y))) {
        ++covered;
        same += std::equal(a.at(x, y), a.at(x, y) + 3, b.at(x, y));
      }
      covered_bounds += !white(c.at(x, y));
    }
  }
  REQUIRE(covered > 1000);
  CHECK(same > 0.97 * covered);         // the extra cube does not move the camera
  CHECK(covered_bounds > 3 * covered);  // its own bounds fill the frame
}

TEST_CASE("figures mesh: no faces, a missing file or no display exit 1 and leave no file") {
  const fs::path dir = fresh_dir("mesh_bad");
  formats::Mesh m = box_mesh();
  m.faces.clear();
  formats::write_ply(m, (dir / "nofaces.ply").string());
  std::string err;
  CHECK(sh(render_cmd(dir / "nofaces.ply", dir / "out.png"), dir / "err", &err) == 1);
  CHECK(err.find("no faces") != std::string::npos);
  CHECK(sh(render_cmd(dir / "absent.ply", dir / "out.png"), dir / "err", &err) == 1);
  CHECK(err.find("absent.ply") != std::string::npos);
  formats::write_ply(box_mesh(), (dir / "box.ply").string());
  CHECK(sh("env -u DISPLAY " + kBin + " mesh -i " + (dir / "box.ply").string() + " -o " +
               (dir / "out.png").string(),
           dir / "err", &err) == 1);
  CHECK(err.find("xvfb-run") != std::string::npos);
  CHECK(sh(render_cmd(dir / "box.ply", dir / "out.png", "--width 0"), dir / "err", &err) == 2);
  CHECK_FALSE(fs::exists(dir / "out.png"));
  CHECK(count_files(dir) == 3);  // nofaces.ply box.ply err
}

TEST_CASE("figures plot: PNG of the requested size with one colour per object") {
  const fs::path dir = fresh_dir("plot");
  {
    std::ofstream f(dir / "scores.csv");
    f << "object,scene,noise_mm,score,rank,entropy\n";
    const double noise[] = {0, 2, 4, 8, 16, 32};
    for (const char* scene : {"unoccluded", "circle"}) {
      for (int i = 0; i < 6; ++i) {
        f << "earthmover," << scene << "," << noise[i] << "," << 0.9 - 0.1 * i << ",1,0.3\n";
        f << "obj1," << scene << "," << noise[i] << "," << 0.5 + 0.05 * i << "," << (i % 2 ? 2 : 1) << ",1.1\n";
      }
    }
  }
  std::string err;
  const std::string cmd = display_prefix() + kBin + " plot -i " + (dir / "scores.csv").string();
  REQUIRE(sh(cmd + " -o " + (dir / "plot.png").string() + " --width 900 --height 300", dir / "err", &err) == 0);
  const Image im = read_png((dir / "plot.png").string());
  REQUIRE(im.width == 900);
  REQUIRE(im.height == 300);
  // The two objects' palette colours (Dark2 #1b9e77 and #d95f02), within antialiasing.
  auto near = [](const std::uint8_t* p, int r, int g, int b) {
    return std::abs(p[0] - r) < 12 && std::abs(p[1] - g) < 12 && std::abs(p[2] - b) < 12;
  };
  int first = 0, second = 0;
  for (int y = 0; y < im.height; ++y) {
    for (int x = 0; x < im.width; ++x) {
      first += near(im.at(x, y), 27, 158, 119);
      second += near(im.at(x, y), 217, 95, 2);
    }
  }
  CHECK(first > 200);
  CHECK(second > 200);
  REQUIRE(sh(cmd + " -o " + (dir / "again.png").string() + " --width 900 --height 300", dir / "err", &err) == 0);
  CHECK(slurp(dir / "plot.png") == slurp(dir / "again.png"));

  std::ofstream(dir / "bad.csv") << "object,scene,noise_mm,score\ntank,circle,4,high\n";
  CHECK(sh(display_prefix() + kBin + " plot -i " + (dir / "bad.csv").string() + " -o " +
               (dir / "bad.png").string(),
           dir / "err", &err) == 1);
  CHECK(err.find("bad.csv") != std::string::npos);
  std::ofstream(dir / "empty.csv") << "object,scene,noise_mm,score\ntank,circle,4,\n";
  CHECK(sh(display_prefix() + kBin + " plot -i " + (dir / "empty.csv").string() + " -o " +
               (dir / "bad.png").string(),
           dir / "err", &err) == 1);
  CHECK_FALSE(fs::exists(dir / "bad.png"));
}

TEST_CASE("figures plot --lo/--hi: a bar per point in the series' colour, from lo to hi") {
  const fs::path dir = fresh_dir("plot-bars");
  std::ofstream(dir / "ladder.csv")
      << "level,cover,value,lo,hi\n10,light,0.5,0.1,0.9\n25,light,0.6,0.2,0.95\n"
         "50,light,0.7,,\n";
  const std::string cmd = display_prefix() + kBin + " plot -i " + (dir / "ladder.csv").string() +
                          " --x level --y value --series cover --panel '' --width 600 --height 400";
  std::string err;
  REQUIRE(sh(cmd + " -o " + (dir / "plain.png").string(), dir / "err", &err) == 0);
  REQUIRE(sh(cmd + " --lo lo --hi hi -o " + (dir / "bars.png").string(), dir / "err", &err) == 0);
  // Pixels of the series' colour (Dark2 #1b9e77) in the upper and the lower fifth of the image:
  // the line runs between 0.5 and 0.7 of the axis, so only the bars reach there.
  auto count = [](const Image& im, int y0, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < im.width; ++x) {
        const std::uint8_t* p = im.at(x, y);
        n += std::abs(p[0] - 27) < 12 && std::abs(p[1] - 158) < 12 && std::abs(p[2] - 119) < 12;
      }
    return n;
  };
  const Image plain = read_png((dir / "plain.png").string()), bars = read_png((dir / "bars.png").string());
  CHECK(count(plain, 40, 120) == 0);
  CHECK(count(bars, 40, 120) > 20);
  CHECK(count(bars, 260, 330) > 20);
  // A bound column the file does not have is an error naming it.
  CHECK(sh(cmd + " --lo low --hi hi -o " + (dir / "x.png").string(), dir / "err", &err) == 1);
  CHECK(err.find("low") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.png"));
}
