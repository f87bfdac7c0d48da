// The samples PCD contract, interoperability with PCL, and the fitvox binary end to end.
#include <catch2/catch.hpp>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/rng.h"
#include "canopy/formats/pcd.h"
#include "fitvox/fitvox.h"
#include "fixtures/fitvox_surfaces.h"

using namespace canopy;
using Eigen::Vector3d;
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kSampleFields = {"x",
                                                "y",
                                                "z",
                                                "normal_x",
                                                "normal_y",
                                                "normal_z",
                                                "curvature",
                                                "mean_curvature",
                                                "gauss_curvature",
                                                "u_x",
                                                "u_y",
                                                "u_z",
                                                "v_x",
                                                "v_y",
                                                "v_z",
                                                "w_x",
                                                "w_y",
                                                "w_z",
                                                "a0",
                                                "a1",
                                                "a2",
                                                "a3",
                                                "a4",
                                                "a5",
                                                "rms",
                                                "point_count",
                                                "label",
                                                "label_purity",
                                                "sensor_x",
                                                "sensor_y",
                                                "sensor_z"};

fs::path tmp_dir() {
  const fs::path d = fs::path(CANOPY_TEST_TMP) / "fitvox";
  fs::create_directories(d);
  return d;
}

// A tilted roof (label 1) over a floor (label 3), 20000 points per m², with sensor directions.
formats::PointCloud scene_cloud(double sigma) {
  common::Rng rng(41);
  formats::PointCloud c;
  for (const char* f : {"x", "y", "z", "sensor_x", "sensor_y", "sensor_z"}) c.add(f);
  c.add("view_idx", formats::kInt32);
  c.add("label", formats::kUint32);
  const int n = 40000;
  c.resize(n);
  const Vector3d s = Vector3d(0.3, 0.2, 1).normalized();
  for (int i = 0; i < n; ++i) {
    const double x = rng.uniform(-0.5, 0.5), y = rng.uniform(-0.5, 0.5);
    const bool roof = i % 2 == 0;
    Vector3d q(x, y, roof ? 1.0 + 0.2 * x : 0.0);
    q += sigma * Vector3d(rng.normal(), rng.normal(), rng.normal());
    c.col("x")[i] = q.x();
    c.col("y")[i] = q.y();
    c.col("z")[i] = q.z();
    c.col("sensor_x")[i] = s.x();
    c.col("sensor_y")[i] = s.y();
    c.col("sensor_z")[i] = s.z();
    c.col("label")[i] = roof ? 1 : 3;
  }
  return c;
}

int sh(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The PCD without its provenance comments (which name the input, "-" for stdin).
std::string body(const fs::path& p) {
  const std::string s = slurp(p);
  const auto at = s.find("\nVERSION");
  return at == std::string::npos ? s : s.substr(at);
}

}  // namespace

TEST_CASE("samples have exactly the contract's fields and load in PCL", "[io][pcl]") {
  const auto cloud = scene_cloud(0.002);
  bool has_sensor = false;
  const auto scan = fitvox::scan_from_cloud(cloud, "scene", &has_sensor);
  CHECK(has_sensor);
  const auto result = fitvox::run(fitvox::Params{}, scan);
  REQUIRE(result.samples.size() > 50);
  const auto samples = fitvox::samples_to_cloud(result);
  CHECK(samples.names() == kSampleFields);
  const fs::path path = tmp_dir() / "samples.pcd";
  formats::write_pcd(samples, path.string());

  pcl::PCLPointCloud2 blob;
  REQUIRE(pcl::io::loadPCDFile(path.string(), blob) == 0);
  std::vector<std::string> names;
  for (const auto& f : blob.fields) names.push_back(f.name);
  CHECK(names == kSampleFields);
  CHECK(blob.width * blob.height == result.samples.size());

  pcl::PointCloud<pcl::PointNormal> pn;
  REQUIRE(pcl::io::loadPCDFile(path.string(), pn) == 0);
  REQUIRE(pn.size() == result.samples.size());
  for (std::size_t i = 0; i < pn.size(); ++i) {
    const auto& f = result.samples[i].fit;
    CHECK(pn[i].x == static_cast<float>(f.p.x()));
    CHECK(pn[i].z == static_cast<float>(f.p.z()));
    CHECK(pn[i].normal_x == static_cast<float>(f.normal.x()));
    CHECK(pn[i].normal_z == static_cast<float>(f.normal.z()));
    CHECK(pn[i].curvature == static_cast<float>(f.variation));
  }
}

TEST_CASE("a plain PCL cloud without sensor fields works, normals toward +z", "[io][pcl]") {
  common::Rng rng(42);
  pcl::PointCloud<pcl::PointXYZ> plain;
  for (int i = 0; i < 20000; ++i) {
    plain.push_back(pcl::PointXYZ(static_cast<float>(rng.uniform(-0.5, 0.5)),
                                  static_cast<float>(rng.uniform(-0.5, 0.5)), 0.5f));
  }
  const fs::path path = tmp_dir() / "plain.pcd";
  REQUIRE(pcl::io::savePCDFileBinaryCompressed(path.string(), plain) == 0);
  bool has_sensor = true;
  const auto scan = fitvox::scan_from_cloud(formats::read_pcd(path.string()), path.string(), &has_sensor);
  CHECK_FALSE(has_sensor);
  const auto result = fitvox::run(fitvox::Params{}, scan);
  REQUIRE(result.samples.size() >= 49);
  for (const auto& s : result.samples) CHECK(s.fit.normal.z() == Approx(1).margin(1e-6));
}

TEST_CASE("scan_from_cloud rejects partial sensor fields and bad labels", "[io]") {
  auto c = scene_cloud(0);
  c.remove("sensor_y");
  CHECK_THROWS_AS(fitvox::scan_from_cloud(c, "f.pcd", nullptr), common::DataError);
  c = scene_cloud(0);
  c.col("label")[3] = 1.5;
  CHECK_THROWS_AS(fitvox::scan_from_cloud(c, "f.pcd", nullptr), common::DataError);
  c = scene_cloud(0);
  c.remove("x");
  CHECK_THROWS_WITH(fitvox::scan_from_cloud(c, "f.pcd", nullptr), Catch::Contains("f.pcd"));
}

TEST_CASE("fitvox binary: files, pipes, determinism, errors", "[cli]") {
  const fs::path d = tmp_dir();
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/fitvox";
  const fs::path scan = d / "scan.pcd";
  formats::write_pcd(scene_cloud(0.004), scan.string());

  const fs::path out1 = d / "out1.pcd", out2 = d / "out2.pcd", out3 = d / "out3.pcd";
  fs::remove(out1);
  REQUIRE(sh(bin + " -q -i " + scan.string() + " -o " + out1.string()) == 0);
  REQUIRE(sh(bin + " -q --threads 2 < " + scan.string() + " > " + out2.string()) == 0);
  CHECK(body(out1) == body(out2));  // stdin/stdout and 2 threads: byte-identical data
  const auto samples = formats::read_pcd(out1.string());
  CHECK(samples.names() == kSampleFields);
  CHECK(samples.size() > 50);

  // noise 4 mm: the fixed thesis bound still keeps most; --config with the shipped defaults
  const std::string ini = std::string(CANOPY_SOURCE_DIR) + "/share/params/fitvox.ini";
  REQUIRE(sh(bin + " -q --config " + ini + " -i " + scan.string() + " -o " + out3.string()) == 0);
  CHECK(body(out1) == body(out3));

  // malformed input: exit 1, message names the file, no output file
  const fs::path bad = d / "bad.pcd", none = d / "none.pcd", err = d / "err.txt";
  std::ofstream(bad) << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                        "WIDTH 10\nHEIGHT 1\nPOINTS 10\nDATA binary\nabc";
  fs::remove(none);
  CHECK(sh(bin + " -i " + bad.string() + " -o " + none.string() + " 2> " + err.string()) == 1);
  CHECK_FALSE(fs::exists(none));
  CHECK(slurp(err).find("bad.pcd") != std::string::npos);

  // nothing survives (voxels far too small): an error, not an empty file
  CHECK(sh(bin + " --voxel 5mm -i " + scan.string() + " -o " + none.string() + " 2> " + err.string()) == 1);
  CHECK_FALSE(fs::exists(none));

  // invalid parameter: usage error
  CHECK(sh(bin + " --min-points 3 -i " + scan.string() + " -o " + none.string() + " 2> " + err.string()) == 2);
  CHECK(sh(bin + " --noise=-2mm -i " + scan.string() + " -o " + none.string() + " 2> " + err.string()) == 2);

  // no sensor fields: a warning, normals toward +z
  auto plain = scene_cloud(0);
  for (const char* f : {"sensor_x", "sensor_y", "sensor_z"}) plain.remove(f);
  const fs::path plain_path = d / "plain_scan.pcd";
  formats::write_pcd(plain, plain_path.string());
  CHECK(sh(bin + " -i " + plain_path.string() + " -o " + out3.string() + " 2> " + err.string()) == 0);
  CHECK(slurp(err).find("warning") != std::string::npos);
}

TEST_CASE("LAS sensor columns (gps_time, scan_angle, point_source_id) are carried from the sample's point",
          "[cli]") {
  // Issue 26: verify derives the direction toward the sensor from these on real tiles. Each
  // input point gets values computed from its own coordinates, so a sample's values must be
  // those of its own point (the voxel's point nearest the centre, before resampling moves it).
  const fs::path d = tmp_dir();
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/fitvox";
  auto las = scene_cloud(0);
  for (const char* f : {"sensor_x", "sensor_y", "sensor_z"}) las.remove(f);
  auto& t = las.add("gps_time", formats::kFloat64);
  auto& a = las.add("scan_angle", formats::kFloat32);
  auto& s = las.add("point_source_id", formats::FieldType{'U', 2});
  for (std::size_t i = 0; i < las.size(); ++i) {
    t[i] = 307843211.0 + 1000 * las.col("x")[i] + 1e-3 * static_cast<double>(i);
    a[i] = static_cast<float>(20 * las.col("y")[i]);
    s[i] = las.col("z")[i] > 0.5 ? 7 : 3;
  }
  const fs::path in = d / "las_scan.pcd", out = d / "las_samples.pcd";
  formats::write_pcd(las, in.string());
  REQUIRE(sh(bin + " -q --resample false -i " + in.string() + " -o " + out.string()) == 0);
  const auto samples = formats::read_pcd(out.string());
  REQUIRE(samples.size() > 50);
  CHECK(samples.type("gps_time") == formats::kFloat64);
  CHECK(samples.type("scan_angle") == formats::kFloat32);
  CHECK(samples.type("point_source_id") == (formats::FieldType{'U', 2}));
  // Without resampling a sample is its point: find it by coordinates and compare.
  std::size_t matched = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    for (std::size_t i = 0; i < las.size(); ++i) {
      if (static_cast<float>(las.col("x")[i]) != static_cast<float>(samples.col("x")[k]) ||
          static_cast<float>(las.col("y")[i]) != static_cast<float>(samples.col("y")[k]) ||
          static_cast<float>(las.col("z")[i]) != static_cast<float>(samples.col("z")[k])) {
        continue;
      }
      CHECK(samples.col("gps_time")[k] == t[i]);
      CHECK(samples.col("scan_angle")[k] == static_cast<float>(a[i]));
      CHECK(samples.col("point_source_id")[k] == s[i]);
      ++matched;
      break;
    }
  }
  CHECK(matched == samples.size());
}

TEST_CASE("the INFO line gives the RMS bound's range least first; at 6 points it is --max-rms", "[cli]") {
  // Until stop 67 the line gave the bound at the most and at the fewest points: with
  // --min-points 6 (fitvox-tile.ini) "RMS bound 43.54-8.00 mm", a range that read reversed.
  const fs::path d = tmp_dir();
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/fitvox";
  const fs::path scan = d / "bound_scan.pcd", out = d / "bound.pcd", err = d / "bound.err";
  formats::write_pcd(scene_cloud(0.004), scan.string());
  auto bound = [&](const std::string& options) {
    REQUIRE(sh(bin + " " + options + " -i " + scan.string() + " -o " + out.string() + " 2> " + err.string()) ==
            0);
    const std::string log = slurp(err);
    const auto at = log.find("RMS bound ");
    REQUIRE(at != std::string::npos);
    return log.substr(at, log.find('\n', at) - at);
  };
  double lo = 0, hi = 0;
  int k_min = 0, k_max = 0;
  const std::string six = bound("--min-points 6");
  INFO(six);
  REQUIRE(std::sscanf(six.c_str(), "RMS bound %lf-%lf mm over voxels of %d-%d points", &lo, &hi, &k_min,
                      &k_max) == 4);
  CHECK(lo == 8.00);  // --max-rms: a biquadratic fits 6 points exactly
  CHECK(hi > lo);
  CHECK(k_min == 6);
  CHECK(k_max > 100);  // 20000 points per m² in 128 mm voxels
  CHECK(six.find("6 points exactly") != std::string::npos);
  const std::string thesis = bound("--min-points 32");
  INFO(thesis);
  REQUIRE(std::sscanf(thesis.c_str(), "RMS bound %lf-%lf mm over voxels of %d-", &lo, &hi, &k_min) == 3);
  CHECK(lo < hi);
  CHECK(k_min == 32);
  CHECK(thesis.find("exactly") == std::string::npos);
  // no noise term (--noise 0): one value, --max-rms
  CHECK(bound("--noise 0 --max-rms 5mm").rfind("RMS bound 5.00 mm,", 0) == 0);
}
