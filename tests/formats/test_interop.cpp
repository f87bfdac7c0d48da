// Interoperability with PCL (PCD and PLY) and VTK (PLY), and the pcd2ply tool end to end.
#include <sys/stat.h>
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

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
  REQUIRE(run("printf 'VERSION 0.7\\nFIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nWIDTH 9\\nPOINTS 9\\nDATA binary\\nxyz' > " +
              dir + "/trunc.pcd") == 0);
  REQUIRE(run(": > " + dir + "/empty.pcd") == 0);
  for (const std::string& in : {dir + "/trunc.pcd", dir + "/empty.pcd", dir, dir + "/missing.pcd"}) {
    INFO(in);
    CHECK(run(bin + " -i " + in + " -o " + dir + "/out.ply 2> " + dir + "/err.txt") == 1);
    CHECK_FALSE(exists(dir + "/out.ply"));
    CHECK(run("grep -q 'pcd2ply: error: " + in + ": ' " + dir + "/err.txt") == 0);
  }
  CHECK(run("ls -A " + dir + " | grep -q tmp") != 0);  // no temporary left behind
}
