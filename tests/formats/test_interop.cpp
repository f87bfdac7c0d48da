// Interoperability with PCL (PCD and PLY) and VTK (PLY), and the pcd2ply tool end to end.
#include <sys/stat.h>
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include "canopy/common/atomic_file.h"
#include "canopy/formats/pcd.h"
#include "support/cli.h"
#include "canopy/formats/ply.h"

using namespace canopy::formats;

namespace {

std::string tmp_dir(const std::string& name) { return canopy::test::fresh_dir("formats", name).string(); }

using canopy::test::run;

using canopy::test::exists;

pcl::PointCloud<pcl::PointXYZINormal> pcl_cloud() {
  pcl::PointCloud<pcl::PointXYZINormal> c;
  for (int i = 0; i < 100; ++i) {
    pcl::PointXYZINormal p;
    p.x = 0.01f * static_cast<float>(i);
    p.y = -0.5f + 0.003f * static_cast<float>(i * i % 17);
    p.z = 2.0f;
    p.intensity = static_cast<float>(i % 7);
    p.normal_x = 0;
    p.normal_y = 0;
    p.normal_z = 1;
    p.curvature = 0.125f;
    c.push_back(p);
  }
  return c;
}

}  // namespace

TEST_CASE("PCD files PCL writes (ascii, binary, binary_compressed) load with ours") {
  const std::string dir = tmp_dir("pcl_pcd");
  const auto src = pcl_cloud();
  pcl::io::savePCDFileASCII(dir + "/a.pcd", src);
  pcl::io::savePCDFileBinary(dir + "/b.pcd", src);
  pcl::io::savePCDFileBinaryCompressed(dir + "/c.pcd", src);
  for (const char* f : {"a.pcd", "b.pcd", "c.pcd"}) {
    INFO(f);
    const PointCloud c = read_pcd(dir + "/" + f);
    REQUIRE(c.size() == src.size());
    for (const char* name : {"x", "y", "z", "intensity", "normal_x", "normal_y", "normal_z", "curvature"}) {
      CHECK(c.has(name));
    }
    for (std::size_t i = 0; i < src.size(); ++i) {
      CHECK(static_cast<float>(c.col("y")[i]) == Approx(src[i].y).epsilon(1e-6));
      CHECK(c.col("intensity")[i] == src[i].intensity);
      CHECK(c.col("curvature")[i] == 0.125);
    }
  }
}

TEST_CASE("PCD files PCL's PCLPointCloud2 binary writer pads with zeros load with ours") {
  // pcl::io::savePCDFile(PCLPointCloud2, binary = true) (pcl_convert_pcd_ascii_binary, pcl_ply2pcd,
  // pcl_converter) stretches the file by a page of zero bytes after the data.
  const std::string dir = tmp_dir("pcl_blob");
  // PointNormal: fields in offset order (PointXYZINormal's are not, and PCL then writes a
  // padding field with COUNT -20, which neither reader accepts).
  pcl::PointCloud<pcl::PointNormal> src;
  for (int i = 0; i < 100; ++i) {
    pcl::PointNormal p;
    p.x = 0.01f * static_cast<float>(i);
    p.y = -0.5f + 0.003f * static_cast<float>(i * i % 17);
    p.z = 2.0f;
    p.normal_x = p.normal_y = 0;
    p.normal_z = 1;
    p.curvature = 0.125f * static_cast<float>(i % 3);
    src.push_back(p);
  }
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(src, blob);
  REQUIRE(pcl::io::savePCDFile(dir + "/blob.pcd", blob, Eigen::Vector4f::Zero(),
                               Eigen::Quaternionf::Identity(), true) == 0);
  struct stat st {};
  REQUIRE(stat((dir + "/blob.pcd").c_str(), &st) == 0);
  const PointCloud c = read_pcd(dir + "/blob.pcd");
  REQUIRE(c.size() == src.size());
  INFO("file " << st.st_size << " bytes, data " << src.size() * blob.point_step);
  CHECK(static_cast<std::size_t>(st.st_size) > src.size() * blob.point_step + 3000);  // the padding is there
  CHECK(parse_pcd(canopy::common::read_file(dir + "/blob.pcd"), "blob.pcd").size() == src.size());
  for (std::size_t i = 0; i < src.size(); ++i) {
    CHECK(c.col("x")[i] == src[i].x);
    CHECK(c.col("y")[i] == src[i].y);
    CHECK(c.col("curvature")[i] == src[i].curvature);
    CHECK(c.col("normal_z")[i] == 1.0);
  }
  // The same through pcd2ply, the tool path.
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/pcd2ply";
  REQUIRE(run(bin + " -q -i " + dir + "/blob.pcd -o " + dir + "/blob.ply") == 0);
  CHECK(read_ply(dir + "/blob.ply").vertices.size() == src.size());
}

TEST_CASE("PCD files we write as binary_compressed and ascii load in PCL") {
  const std::string dir = tmp_dir("our_pcd_enc");
  PointCloud c;
  c.resize(1000);
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  auto& l = c.add("label", kUint32);
  for (std::size_t i = 0; i < c.size(); ++i) {
    x[i] = static_cast<float>(0.01 * static_cast<double>(i));
    y[i] = static_cast<float>(std::sin(0.1 * static_cast<double>(i)));
    z[i] = 2.0;
    l[i] = static_cast<double>(i % 4);
  }
  for (auto enc : {PcdEncoding::binary_compressed, PcdEncoding::ascii}) {
    PcdWriteOptions o;
    o.encoding = enc;
    write_pcd(c, dir + "/ours.pcd", o);
    pcl::PointCloud<pcl::PointXYZL> typed;
    REQUIRE(pcl::io::loadPCDFile(dir + "/ours.pcd", typed) == 0);
    REQUIRE(typed.size() == c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      CHECK(typed[i].x == static_cast<float>(x[i]));
      CHECK(typed[i].y == static_cast<float>(y[i]));
      CHECK(typed[i].label == static_cast<std::uint32_t>(l[i]));
    }
  }
}

TEST_CASE("PLY with scalar_ names and int labels loads in PCL and VTK") {
  const std::string dir = tmp_dir("ply_cc");
  Mesh m;
  m.vertices.resize(3);
  m.vertices.add("x") = {0, 1, 0};
  m.vertices.add("y") = {0, 0, 1};
  m.vertices.add("z") = {0, 0, 0};
  m.vertices.add("label", kUint32) = {1, 2, 3};
  m.vertices.add("curvature") = {0.5, 0.25, 0.125};
  m.faces = {{0, 1, 2}};
  PlyWriteOptions o;
  o.scalar_prefix = true;
  write_ply(m, dir + "/cc.ply", o);
  pcl::PCLPointCloud2 blob;
  REQUIRE(pcl::io::loadPLYFile(dir + "/cc.ply", blob) == 0);
  std::vector<std::string> names;
  for (const auto& f : blob.fields) names.push_back(f.name);
  CHECK(std::find(names.begin(), names.end(), "scalar_label") != names.end());
  CHECK(std::find(names.begin(), names.end(), "scalar_curvature") != names.end());
  vtkNew<vtkPLYReader> reader;
  reader->SetFileName((dir + "/cc.ply").c_str());
  reader->Update();
  CHECK(reader->GetOutput()->GetNumberOfPoints() == 3);
  CHECK(reader->GetOutput()->GetNumberOfPolys() == 1);
}

TEST_CASE("PCD files we write load in PCL with every field") {
  const std::string dir = tmp_dir("our_pcd");
  PointCloud c;
  c.resize(3);
  c.add("x") = {1, 2, 3};
  c.add("y") = {4, 5, 6};
  c.add("z") = {7, 8, 9};
  c.add("label", kUint32) = {1, 2, 3};
  c.add("sensor_z") = {0.5, 0.5, 1};
  write_pcd(c, dir + "/ours.pcd");
  pcl::PCLPointCloud2 blob;
  REQUIRE(pcl::io::loadPCDFile(dir + "/ours.pcd", blob) == 0);
  CHECK(blob.width * blob.height == 3);
  REQUIRE(blob.fields.size() == 5);
  CHECK(blob.fields[3].name == "label");
  pcl::PointCloud<pcl::PointXYZL> typed;
  REQUIRE(pcl::io::loadPCDFile(dir + "/ours.pcd", typed) == 0);
  CHECK(typed[2].z == 9.0f);
  CHECK(typed[1].label == 2u);
}

TEST_CASE("pcd2ply turns a PCL-written cloud into a PLY that PCL and VTK read with all fields") {
  const std::string dir = tmp_dir("pcd2ply");
  pcl::io::savePCDFileBinaryCompressed(dir + "/in.pcd", pcl_cloud());
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/pcd2ply";
  REQUIRE(run(bin + " -q -i " + dir + "/in.pcd -o " + dir + "/out.ply") == 0);
  // Pipe form.
  REQUIRE(run("cat " + dir + "/in.pcd | " + bin + " -q > " + dir + "/piped.ply") == 0);
  CHECK(read_ply(dir + "/piped.ply").vertices.size() == 100);

  pcl::PCLPointCloud2 blob;
  REQUIRE(pcl::io::loadPLYFile(dir + "/out.ply", blob) == 0);
  CHECK(blob.width * blob.height == 100);
  std::vector<std::string> names;
  for (const auto& f : blob.fields) names.push_back(f.name);
  for (const char* want : {"x", "y", "z", "intensity", "normal_x", "curvature"}) {
    CHECK(std::find(names.begin(), names.end(), want) != names.end());
  }

  vtkNew<vtkPLYReader> reader;
  reader->SetFileName((dir + "/out.ply").c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  CHECK(poly->GetNumberOfPoints() == 100);
  REQUIRE(poly->GetPointData()->GetNormals() != nullptr);
  CHECK(poly->GetPointData()->GetNormals()->GetComponent(5, 2) == 1.0);
}

TEST_CASE("pcd2ply on malformed input exits 1 with a message and writes nothing") {
  const std::string dir = tmp_dir("pcd2ply_bad");
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/pcd2ply";
  REQUIRE(run("printf 'VERSION 0.7\\nFIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nWIDTH 9\\nPOINTS 9\\nDATA "
              "binary\\nxyz' > " +
              dir + "/trunc.pcd") == 0);
  REQUIRE(run(": > " + dir + "/empty.pcd") == 0);
  // Cases that crashed, hung or allocated gigabytes before (issue 12).
  REQUIRE(run("printf 'VERSION 0.7\\nFIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nCOUNT 1 1 200000\\nWIDTH 0\\n"
              "POINTS 0\\nDATA binary\\n' > " +
              dir + "/count.pcd") == 0);
  REQUIRE(run("printf 'FIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nWIDTH 100000000\\nPOINTS 100000000\\n"
              "DATA binary\\n0123456789ab' > " +
              dir + "/points.pcd") == 0);
  REQUIRE(run("printf 'ply\\nformat ascii 1.0\\nelement vertex 0\\nend_header\\n' > " + dir + "/mesh.pcd") == 0);
  for (const std::string& in : {dir + "/trunc.pcd", dir + "/empty.pcd", dir, dir + "/missing.pcd",
                                dir + "/count.pcd", dir + "/points.pcd", dir + "/mesh.pcd"}) {
    INFO(in);
    CHECK(run(bin + " -i " + in + " -o " + dir + "/out.ply 2> " + dir + "/err.txt") == 1);
    CHECK_FALSE(exists(dir + "/out.ply"));
    CHECK(run("grep -q 'pcd2ply: error: " + in + ": ' " + dir + "/err.txt") == 0);
  }
  CHECK(run("ls -A " + dir + " | grep -q tmp") != 0);  // no temporary left behind
}
