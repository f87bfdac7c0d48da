// The baseline's serial k-d trees (tools/baseline/serial_kdtree.h) answer every search exactly
// as PCL's library trees do: the same neighbours, in the same order, with the same squared
// distances, bit for bit -- on a cloud with exact duplicates and equal distances (ties), for
// 1-NN (RANSAC's fitness, ICP), k-NN, radius searches (normals, FPFH) and 33-float FPFH
// signatures (RANSAC's feature matching). So the baseline's results do not change with them
// (docs/decisions/baseline.md §6).
#include <catch2/catch.hpp>

#include <cstdint>

#include "baseline/serial_kdtree.h"

namespace bl = canopy::baseline;

namespace {

// A small deterministic generator (no dependence on the library's rand()).
struct Lcg {
  std::uint64_t s;
  float next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<float>((s >> 33) % 100000) / 100000.0f;
  }
};

// Points on a 0.1 m lattice (many equal distances) plus random ones, every 7th point repeated.
pcl::PointCloud<bl::PointN>::Ptr cloud() {
  pcl::PointCloud<bl::PointN>::Ptr c(new pcl::PointCloud<bl::PointN>);
  Lcg g{42};
  for (int i = 0; i < 1500; ++i) {
    bl::PointN p;
    if (i % 2 == 0) {
      p.x = 0.1f * static_cast<float>(i % 10);
      p.y = 0.1f * static_cast<float>((i / 10) % 10);
      p.z = 0.1f * static_cast<float>(i / 100);
    } else {
      p.x = 3 * g.next(), p.y = 3 * g.next(), p.z = 2 * g.next();
    }
    p.normal_x = 0, p.normal_y = 0, p.normal_z = 1;
    c->push_back(p);
    if (i % 7 == 0) c->push_back(p);
  }
  return c;
}

}  // namespace

TEST_CASE("serial k-d tree: the library's neighbours, order and distances", "[baseline][kdtree]") {
  const auto c = cloud();
  pcl::search::KdTree<bl::PointN> library;
  library.setInputCloud(c);
  bl::SerialKdTree serial;
  serial.setInputCloud(c);
  bl::SerialFlann<bl::PointN> flann;
  flann.setInputCloud(c);
  pcl::KdTreeFLANN<bl::PointN> library_flann;
  library_flann.setInputCloud(c);

  Lcg g{7};
  int ties = 0;
  for (int q = 0; q < 400; ++q) {
    bl::PointN p;
    // queries on lattice points (exact ties), on cloud points and at random places
    if (q % 3 == 0) {
      p = (*c)[static_cast<std::size_t>(q) % c->size()];
    } else if (q % 3 == 1) {
      p.x = 0.05f + 0.1f * static_cast<float>(q % 9), p.y = 0.05f + 0.1f * static_cast<float>(q % 8),
      p.z = 0.1f;
    } else {
      p.x = 3 * g.next(), p.y = 3 * g.next(), p.z = 2 * g.next();
    }
    for (const int k : {1, 7}) {
      pcl::Indices a, b, e, f;
      std::vector<float> da, db, de, df;
      REQUIRE(library.nearestKSearch(p, k, a, da) == serial.nearestKSearch(p, k, b, db));
      REQUIRE(a == b);
      REQUIRE(da == db);
      REQUIRE(library_flann.nearestKSearch(p, k, e, de) == flann.nearestKSearch(p, k, f, df));
      REQUIRE(e == f);
      REQUIRE(de == df);
      REQUIRE(a == e);
      if (k == 7 && da[0] == da[1]) ++ties;
    }
    for (const double r : {0.15, 0.4}) {
      pcl::Indices a, b;
      std::vector<float> da, db;
      REQUIRE(library.radiusSearch(p, r, a, da) == serial.radiusSearch(p, r, b, db));
      REQUIRE(a == b);
      REQUIRE(da == db);
      // through the (cloud, index) overload, as PCL's features call it
      pcl::Indices x, y;
      std::vector<float> dx, dy;
      REQUIRE(library.radiusSearch(*c, q, r, x, dx) == serial.radiusSearch(*c, q, r, y, dy));
      REQUIRE(x == y);
      REQUIRE(dx == dy);
    }
  }
  REQUIRE(ties > 50);  // the comparison did meet equal distances
}

TEST_CASE("serial feature tree: the library's FPFH correspondences", "[baseline][kdtree]") {
  pcl::PointCloud<pcl::FPFHSignature33>::Ptr f(new pcl::PointCloud<pcl::FPFHSignature33>);
  Lcg g{11};
  for (int i = 0; i < 600; ++i) {
    pcl::FPFHSignature33 s;
    for (float& h : s.histogram) h = std::floor(10 * g.next());  // coarse values: ties
    f->push_back(s);
    if (i % 5 == 0) f->push_back(s);
  }
  pcl::KdTreeFLANN<pcl::FPFHSignature33> library;
  library.setInputCloud(f);
  bl::SerialFeatureTree serial;
  serial.setInputCloud(f);
  for (int q = 0; q < 200; ++q) {
    pcl::Indices a, b;
    std::vector<float> da, db;
    // (the (cloud, index) overload, as SampleConsensusPrerejective calls it)
    REQUIRE(library.nearestKSearch(*f, q * 3, 3, a, da) == serial.nearestKSearch(*f, q * 3, 3, b, db));
    REQUIRE(a == b);
    REQUIRE(da == db);
  }
}
