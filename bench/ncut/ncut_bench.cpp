// ncut_bench [--quick] [mesh.ply ...]
// 1. Exponent comparison (squared vs linear) on synthetic box / vehicle-like meshes with
//    position and normal noise: segment count and agreement with the known faces.
// 2. Timing on a 10^5-vertex height field and on the given PLY meshes (single thread).
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "canopy/common/log.h"
#include "canopy/common/math.h"
#include "canopy/formats/ply.h"
#include "fixtures/ncut_meshes.h"
#include "ncut/ncut.h"

using namespace canopy;
using namespace canopy::ncut;
using namespace canopy::ncut::testing;
using Eigen::Vector3d;

namespace {

// Vehicle-like height field over a box body (sedan proportions): hood, windshield, roof,
// rear window, trunk and slanted side windows as planes meeting at creases, four vertical
// body sides; no bottom (the ground hides it). Parts = connected regions of equal normal.
TestMesh vehicle(double h) {
  const double len = 4.6, half = 0.9, z0 = 0.3, z1 = 0.9;
  auto profile = [](double x) {  // cabin height above the shoulder along x
    if (x < 1.4) return -1.0;
    if (x < 2.2) return 0.55 * (x - 1.4) / 0.8;
    if (x < 3.6) return 0.55;
    if (x < 4.1) return 0.55 - 0.55 * (x - 3.6) / 0.5;
    return -1.0;
  };
  auto height = [&](double x, double y) {
    const double side = 0.55 * (0.85 - std::abs(y)) / 0.2;
    return z1 + std::max(0.0, std::min(profile(x), side));
  };
  TestMesh m;
  const int nx = static_cast<int>(std::lround(len / h)), ny = static_cast<int>(std::lround(2 * half / h));
  const int nz = static_cast<int>(std::lround((z1 - z0) / h));
  std::vector<std::vector<int>> top(nx, std::vector<int>(ny));
  const double e = 1e-6;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const double x = (i + 0.5) * len / nx, y = -half + (j + 0.5) * 2 * half / ny;
      top[i][j] = static_cast<int>(m.in.points.size());
      m.in.points.push_back({x, y, height(x, y)});
      const double gx = (height(x + e, y) - height(x - e, y)) / (2 * e);
      const double gy = (height(x, y + e) - height(x, y - e)) / (2 * e);
      m.in.normals.push_back(Vector3d(-gx, -gy, 1).normalized());
      m.part.push_back(-1);
    }
  }
  for (int i = 0; i + 1 < nx; ++i) {
    for (int j = 0; j + 1 < ny; ++j) {
      m.in.faces.push_back({top[i][j], top[i + 1][j], top[i + 1][j + 1]});
      m.in.faces.push_back({top[i][j], top[i + 1][j + 1], top[i][j + 1]});
    }
  }
  const int base = 100;
  auto left = m.add_grid({0, -half, z0}, {len, 0, 0}, {0, 0, z1 - z0}, nx, nz, {0, -1, 0}, base);
  auto right = m.add_grid({0, half, z0}, {len, 0, 0}, {0, 0, z1 - z0}, nx, nz, {0, 1, 0}, base + 1);
  auto front = m.add_grid({0, -half, z0}, {0, 2 * half, 0}, {0, 0, z1 - z0}, ny, nz, {-1, 0, 0}, base + 2);
  auto back = m.add_grid({len, -half, z0}, {0, 2 * half, 0}, {0, 0, z1 - z0}, ny, nz, {1, 0, 0}, base + 3);
  m.zip(row_j(left, nz - 1), row_j(top, 0));
  m.zip(row_j(right, nz - 1), row_j(top, ny - 1));
  m.zip(row_j(front, nz - 1), row_i(top, 0));
  m.zip(row_j(back, nz - 1), row_i(top, nx - 1));
  m.zip(row_i(left, 0), row_i(front, 0));
  m.zip(row_i(left, nx - 1), row_i(back, 0));
  m.zip(row_i(right, 0), row_i(front, ny - 1));
  m.zip(row_i(right, nx - 1), row_i(back, ny - 1));
  // Top parts: flood fill over mesh edges joining equal normals.
  std::vector<std::vector<int>> adj(m.in.points.size());
  for (const auto& ed : mesh_edges(m.in.faces)) {
    adj[ed[0]].push_back(ed[1]);
    adj[ed[1]].push_back(ed[0]);
  }
  int next = 0;
  for (std::size_t s = 0; s < m.part.size(); ++s) {
    if (m.part[s] != -1) continue;
    std::vector<int> stack{static_cast<int>(s)};
    m.part[s] = next;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int u : adj[v]) {
        if (m.part[u] == -1 && (m.in.normals[u] - m.in.normals[v]).norm() < 1e-6) {
          m.part[u] = next;
          stack.push_back(u);
        }
      }
    }
    ++next;
  }
  return m;
}

// Two 1.5 m squares at 128 mm meeting along the y axis with a dihedral bend of phi.
TestMesh hinge(double phi) {
  TestMesh m;
  const double s = 1.536;
  const int n = 12;
  auto a = m.add_grid({-s, 0, 0}, {s, 0, 0}, {0, s, 0}, n, n, {0, 0, 1}, 0);
  const Vector3d u(std::cos(phi), 0, std::sin(phi));
  auto b = m.add_grid({0, 0, 0}, s * u, {0, s, 0}, n, n, {-std::sin(phi), 0, std::cos(phi)}, 1);
  m.zip(row_i(a, n - 1), row_i(b, 0));
  return m;
}

// 10^5-vertex height field: a triangular wave (period 4 m, amplitude 1 m) at 128 mm.
TestMesh big(int side) {
  TestMesh m;
  const double h = 0.128;
  std::vector<std::vector<int>> g(side, std::vector<int>(side));
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const double x = i * h, y = j * h;
      const double t = std::fmod(x, 4.0);
      const double z = t < 2 ? 0.5 * t : 0.5 * (4 - t);
      g[i][j] = static_cast<int>(m.in.points.size());
      m.in.points.push_back({x, y, z});
      m.in.normals.push_back(Vector3d(t < 2 ? -0.5 : 0.5, 0, 1).normalized());
      m.part.push_back(static_cast<int>(x / 2));
    }
  }
  for (int i = 0; i + 1 < side; ++i) {
    for (int j = 0; j + 1 < side; ++j) {
      m.in.faces.push_back({g[i][j], g[i + 1][j], g[i + 1][j + 1]});
      m.in.faces.push_back({g[i][j], g[i + 1][j + 1], g[i][j + 1]});
    }
  }
  return m;
}

struct Score {
  int segments = 0, segments10 = 0, parts = 0;
  double purity = 0;    // share of vertices in their segment's majority part (1 = no under-seg)
  double coverage = 0;  // share of vertices in their part's majority segment (1 = no over-seg)
};

Score score(const std::vector<int>& part, const std::vector<int>& seg) {
  std::map<int, std::map<int, int>> by_seg, by_part;
  for (std::size_t v = 0; v < part.size(); ++v) {
    ++by_seg[seg[v]][part[v]];
    ++by_part[part[v]][seg[v]];
  }
  Score s;
  s.segments = static_cast<int>(by_seg.size());
  s.parts = static_cast<int>(by_part.size());
  double pur = 0, cov = 0;
  for (const auto& [k, m] : by_seg) {
    int best = 0, total = 0;
    for (const auto& [p, c] : m) best = std::max(best, c), total += c;
    pur += best;
    s.segments10 += total >= 10;
  }
  for (const auto& [k, m] : by_part) {
    int best = 0;
    for (const auto& [p, c] : m) best = std::max(best, c);
    cov += best;
  }
  s.purity = pur / part.size();
  s.coverage = cov / part.size();
  return s;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Per segment: vertex count and its parts with counts.
void print_composition(const std::vector<int>& part, const std::vector<int>& seg) {
  std::map<int, std::map<int, int>> by_seg;
  for (std::size_t v = 0; v < part.size(); ++v) ++by_seg[seg[v]][part[v]];
  for (const auto& [k, m] : by_seg) {
    std::printf("    segment %2d:", k);
    for (const auto& [p, c] : m) std::printf(" part %d x%d", p, c);
    std::printf("\n");
  }
}

void print_run(const char* name, std::size_t n, const Result& r, double seconds) {
  const auto& c = r.stats.cut;
  std::printf(
      "%-28s %7zu vtx %8zu edges %4zu segs %6.3f s (graph %.3f, cut %.3f, attr %.3f) "
      "solves %d (dense %d, lanczos %d, s-i %d, fallback %d) matvecs %lld (max %lld) "
      "restarts %lld\n",
      name, n, r.stats.graph.edges, r.graph.segments.size(), seconds, r.stats.seconds_graph,
      r.stats.seconds_cut, r.stats.seconds_attributes, c.solves, c.dense_solves, c.lanczos_solves,
      c.shift_invert_solves, c.fallbacks, c.matvecs, c.max_matvecs, c.restarts);
}

// Dumps a synthetic mesh as PLY (for timing the ncut binary itself).
void write_mesh(const TestMesh& m, const std::string& path) {
  formats::Mesh out;
  out.vertices.resize(m.in.points.size());
  const char* names[6] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (const char* f : names) out.vertices.add(f, formats::kFloat32);
  for (std::size_t i = 0; i < m.in.points.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      out.vertices.col(names[c])[i] = m.in.points[i][c];
      out.vertices.col(names[3 + c])[i] = m.in.normals[i][c];
    }
  }
  for (const auto& f : m.in.faces) out.faces.push_back({f[0], f[1], f[2]});
  formats::write_ply(out, path);
}

struct Options {
  bool quick = false, detail = false, big_only = false, wrote = false;
  int dense_max = CutParams{}.dense_max;
  std::vector<std::string> files;
};

// Parses the arguments; --write-big / --write-vehicle write their mesh at once and set `wrote`.
Options parse_options(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if ((a == "--write-big" || a == "--write-vehicle") && k + 1 < argc) {
      write_mesh(a == "--write-big" ? big(317) : vehicle(0.128), argv[++k]);
      o.wrote = true;
      return o;
    }
    if (a == "--big-only")
      o.big_only = true;
    else if (a == "--dense-max" && k + 1 < argc)
      o.dense_max = std::atoi(argv[++k]);
    else if (a == "--quick")
      o.quick = true;
    else if (a == "--detail")
      o.detail = true;
    else
      o.files.push_back(a);
  }
  return o;
}

// Times one default run of the 10^5-vertex height field; returns it with its mesh's parts.
Result time_big(const TestMesh& b) {
  Params p;
  const double t0 = now();
  Result r = run(p, b.in);
  print_run("height field 10^5", b.in.points.size(), r, now() - t0);
  return r;
}

void exponent_comparison(bool quick, bool detail) {
  std::printf("== exponent comparison: segments (>= 10 vtx) / parts, purity, coverage ==\n");
  std::printf("%-10s %-8s %-8s | %-30s | %-30s\n", "shape", "pos mm", "nrm deg", "squared", "linear");
  const double deg = common::kDegree;
  const int seeds = quick ? 1 : 3;
  for (const char* shape : {"box", "vehicle"}) {
    for (const auto& [sp, sa] :
         std::vector<std::pair<double, double>>{{0, 0}, {0.002, 1}, {0.004, 2}, {0.008, 4}, {0.016, 8}}) {
      Score acc[2];
      double sum_seg[2] = {0, 0}, sum_pur[2] = {0, 0}, sum_cov[2] = {0, 0};
      for (int seed = 1; seed <= seeds; ++seed) {
        TestMesh m = std::string(shape) == "box" ? box({4.0, 1.8, 1.4}, 0.128, false) : vehicle(0.128);
        add_noise(&m, sp, sa * deg / std::sqrt(2.0), 100 + seed);
        for (int e = 0; e < 2; ++e) {
          Params p;
          p.affinity.exponent = e == 0 ? Exponent::kSquared : Exponent::kLinear;
          p.sparsify.seed = seed;
          const Result r = run(p, m.in);
          acc[e] = score(m.part, r.segment);
          if (detail && seed == 1) {
            std::printf("  %s %s noise %.0f mm %.0f deg:\n", shape, e == 0 ? "squared" : "linear", sp * 1000,
                        sa);
            print_composition(m.part, r.segment);
          }
          sum_seg[e] += acc[e].segments10;
          sum_pur[e] += acc[e].purity;
          sum_cov[e] += acc[e].coverage;
        }
      }
      char col[2][64];
      for (int e = 0; e < 2; ++e) {
        std::snprintf(col[e], sizeof col[e], "%5.1f / %2d  pur %.3f cov %.3f", sum_seg[e] / seeds,
                      acc[e].parts, sum_pur[e] / seeds, sum_cov[e] / seeds);
      }
      std::printf("%-10s %-8.0f %-8.0f | %-30s | %-30s\n", shape, sp * 1000, sa, col[0], col[1]);
    }
  }
}

void dihedral_sweep() {
  std::printf("\n== dihedral sweep: segments of two 1.5 m squares bent by phi (128 mm) ==\n");
  std::printf("%-8s %-8s %-8s\n", "phi deg", "squared", "linear");
  const double deg = common::kDegree;
  for (double phi : {5, 10, 15, 20, 25, 30, 40, 60, 90}) {
    int count[2];
    for (int e = 0; e < 2; ++e) {
      Params p;
      p.affinity.exponent = e == 0 ? Exponent::kSquared : Exponent::kLinear;
      count[e] = static_cast<int>(run(p, hinge(phi * deg).in).graph.segments.size());
    }
    std::printf("%-8.0f %-8d %-8d\n", phi, count[0], count[1]);
  }
}

void synthetic_timing(bool quick) {
  std::printf("\n== timing (single thread, default parameters) ==\n");
  for (double h : {0.128, 0.064}) {
    const TestMesh v = vehicle(h);
    const double t0 = now();
    const Result r = run(Params{}, v.in);
    print_run(h == 0.128 ? "vehicle-like 128mm" : "vehicle-like 64mm", v.in.points.size(), r, now() - t0);
  }
  if (!quick) {
    const TestMesh b = big(317);
    const Result r = time_big(b);
    const Score s = score(b.part, r.segment);
    std::printf("  %d parts, %d segments >= 10 vtx, purity %.3f, coverage %.3f\n", s.parts, s.segments10,
                s.purity, s.coverage);
  }
}

// Both exponents on a PLY mesh: timing, target segments and the largest segment areas.
void mesh_file_runs(const std::string& f, int dense_max) {
  const formats::Mesh mesh = formats::read_ply(f);
  const Inputs in = input_from_mesh(mesh, f);
  for (int e = 0; e < 2; ++e) {
    Params p;
    p.affinity.exponent = e == 0 ? Exponent::kSquared : Exponent::kLinear;
    p.cut.dense_max = dense_max;
    const double t0 = now();
    const Result r = run(p, in);
    std::string name = f.size() > 20 ? "..." + f.substr(f.size() - 17) : f;
    name += e == 0 ? " sq" : " lin";
    print_run(name.c_str(), in.points.size(), r, now() - t0);
    std::vector<double> areas;
    int target = 0;
    for (const auto& sg : r.graph.segments) {
      areas.push_back(sg.area);
      target += sg.label == 1 && sg.vertex_count >= 10;
    }
    std::sort(areas.rbegin(), areas.rend());
    std::printf("  %d target segments >= 10 vtx; largest areas m^2:", target);
    for (std::size_t k = 0; k < areas.size() && k < 10; ++k) std::printf(" %.2f", areas[k]);
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  common::log::set_tool("ncut_bench");
  common::log::set_level(common::log::Level::kQuiet);
  const Options o = parse_options(argc, argv);
  if (o.wrote) return 0;
  if (o.big_only) {
    time_big(big(317));
    return 0;
  }
  exponent_comparison(o.quick, o.detail);
  dihedral_sweep();
  synthetic_timing(o.quick);
  for (const std::string& f : o.files) mesh_file_runs(f, o.dense_max);
  return 0;
}
