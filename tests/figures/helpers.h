// Shared helpers of the figures tests: temp dirs, running the binary (under xvfb-run when no
// X display is set), hand-built coloured box meshes, pixel classification.
#pragma once

#include "support/cli.h"

#include <sys/wait.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "canopy/formats/ply.h"
#include "figures/figures.h"

namespace canopy::figures::testing {

namespace fs = std::filesystem;

inline const std::string kBin = std::string(CANOPY_BIN_DIR) + "/figures";

inline fs::path fresh_dir(const std::string& name) { return canopy::test::fresh_dir("figures", name); }

using canopy::test::sh;

// Prefix for commands that render with OpenGL: none with a display, else xvfb-run -a.
inline std::string display_prefix() {
  const char* d = std::getenv("DISPLAY");
  if (d != nullptr && *d != '\0') return "";
  return "xvfb-run -a ";
}

inline bool have_xvfb_run() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

// Axis-aligned box [x0,x1] x [y0,y1] x [z0,z1] with n x n triangles pairs per face, every face
// its own vertices (sharp creases); colour per face: top (+z), front (+x), other sides.
inline void add_box(formats::Mesh& m, std::array<double, 3> lo, std::array<double, 3> hi,
                    std::array<int, 3> top, std::array<int, 3> front, std::array<int, 3> side, int n = 4) {
  auto& v = m.vertices;
  for (const char* f : {"x", "y", "z"}) v.add(f, formats::kFloat32);
  for (const char* f : {"red", "green", "blue"}) v.add(f, formats::kUint8);
  auto face = [&](std::array<double, 3> o, std::array<double, 3> u, std::array<double, 3> w,
                  std::array<int, 3> c) {
    const auto base = static_cast<std::int32_t>(v.size());
    v.resize(v.size() + static_cast<std::size_t>((n + 1) * (n + 1)));
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const std::size_t k = static_cast<std::size_t>(base + j * (n + 1) + i);
        for (int d = 0; d < 3; ++d) {
          v.col(std::string(1, "xyz"[d]))[k] = o[d] + u[d] * i / n + w[d] * j / n;
        }
        v.col("red")[k] = c[0], v.col("green")[k] = c[1], v.col("blue")[k] = c[2];
      }
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const std::int32_t a = base + j * (n + 1) + i, b = a + 1, cc = a + n + 1, d = cc + 1;
        m.faces.push_back({a, b, d});
        m.faces.push_back({a, d, cc});
      }
    }
  };
  const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
  face({lo[0], lo[1], hi[2]}, {dx, 0, 0}, {0, dy, 0}, top);    // +z
  face({hi[0], lo[1], lo[2]}, {0, dy, 0}, {0, 0, dz}, front);  // +x
  face({lo[0], lo[1], lo[2]}, {0, 0, dz}, {0, dy, 0}, side);   // -x
  face({lo[0], lo[1], lo[2]}, {dx, 0, 0}, {0, 0, dz}, side);   // -y
  face({lo[0], hi[1], lo[2]}, {0, 0, dz}, {dx, 0, 0}, side);   // +y
}

// Hue classes of a shaded pixel: which channel clearly dominates.
inline bool reddish(const std::uint8_t* p) { return p[0] > 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2]; }
inline bool greenish(const std::uint8_t* p) { return p[1] > 60 && p[1] > 2 * p[0] && p[1] > 2 * p[2]; }
inline bool bluish(const std::uint8_t* p) { return p[2] > 60 && p[2] > 2 * p[0] && p[2] > 2 * p[1]; }
inline bool white(const std::uint8_t* p) { return p[0] == 255 && p[1] == 255 && p[2] == 255; }

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// No file in dir besides the listed ones (no temporaries left behind).
inline int count_files(const fs::path& dir) {
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

}  // namespace canopy::figures::testing
