// PCD reading speed and peak memory: canopy's read_pcd against PCL's loadPCDFile; LAZ reading
// against reading the same points as LAS.
//   formats_bench make <file.pcd> <points> [binary|binary_compressed|ascii]
//       writes a scan-like cloud (x y z sensor_x sensor_y sensor_z F4, view_idx I4, label U4)
//   formats_bench read <canopy|pcl-blob|pcl-xyzl> <file.pcd>
//       reads it once and prints "reader cpu_s wall_s peak_rss_MB points"
//   formats_bench unlaz <file.laz> <file.las>
//       writes the LAS a LAZ file decompresses to (canopy's laz_to_las)
//   formats_bench read <las|laz> <file>
//       reads a LAS or LAZ file once with read_points (as every tool does), same output
// Run each read in its own process (bench/formats/run.sh) so peak RSS is the reader's own.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "canopy/common/atomic_file.h"
#include "canopy/formats/laz.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/points_io.h"

namespace {

double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

double peak_rss_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // kB on Linux
}

int make(const std::string& path, std::size_t n, const std::string& enc) {
  using namespace canopy::formats;
  PointCloud c;
  c.resize(n);
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  auto& sx = c.add("sensor_x");
  auto& sy = c.add("sensor_y");
  auto& sz = c.add("sensor_z");
  auto& v = c.add("view_idx", kInt32);
  auto& l = c.add("label", kUint32);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    x[i] = static_cast<float>(std::fmod(t * 0.0137, 20.0) - 10.0);
    y[i] = static_cast<float>(std::fmod(t * 0.0071, 20.0) - 10.0);
    z[i] = static_cast<float>(std::sin(t * 1e-3));
    sx[i] = 0.0;
    sy[i] = static_cast<float>(std::sin(t * 1e-5));
    sz[i] = static_cast<float>(std::cos(t * 1e-5));
    v[i] = static_cast<double>(i / 500000);
    l[i] = static_cast<double>(i % 4);
  }
  PcdWriteOptions o;
  if (enc == "binary_compressed")
    o.encoding = PcdEncoding::binary_compressed;
  else if (enc == "ascii")
    o.encoding = PcdEncoding::ascii;
  write_pcd(c, path, o);
  return 0;
}

int read(const std::string& reader, const std::string& path) {
  const double c0 = cpu_seconds();
  const auto w0 = std::chrono::steady_clock::now();
  std::size_t n = 0;
  if (reader == "canopy") {
    n = canopy::formats::read_pcd(path).size();
  } else if (reader == "las" || reader == "laz") {
    n = canopy::formats::read_points(path).size();
  } else if (reader == "pcl-blob") {
    pcl::PCLPointCloud2 blob;
    if (pcl::io::loadPCDFile(path, blob) != 0) return 1;
    n = blob.width * blob.height;
  } else if (reader == "pcl-xyzl") {
    pcl::PointCloud<pcl::PointXYZL> cloud;
    if (pcl::io::loadPCDFile(path, cloud) != 0) return 1;
    n = cloud.size();
  } else {
    std::fprintf(stderr, "formats_bench: unknown reader %s\n", reader.c_str());
    return 2;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  std::printf("%-9s %6.3f %6.3f %8.1f %zu\n", reader.c_str(), cpu_seconds() - c0, wall, peak_rss_mb(), n);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string cmd = argc > 1 ? argv[1] : "";
  if (cmd == "make" && argc >= 4)
    return make(argv[2], std::strtoull(argv[3], nullptr, 10), argc > 4 ? argv[4] : "binary");
  if (cmd == "read" && argc == 4) return read(argv[2], argv[3]);
  if (cmd == "unlaz" && argc == 4) {
    canopy::common::write_file_atomic(
        argv[3], canopy::formats::laz_to_las(canopy::common::read_file(argv[2]), argv[2]));
    return 0;
  }
  std::fprintf(stderr,
               "usage: formats_bench make <file.pcd> <points> [binary|binary_compressed|ascii]\n"
               "       formats_bench read <canopy|pcl-blob|pcl-xyzl> <file.pcd>\n"
               "       formats_bench unlaz <file.laz> <file.las>\n"
               "       formats_bench read <las|laz> <file>\n");
  return 2;
}
