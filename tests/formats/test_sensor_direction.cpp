// formats/sensor_direction.h (issue 26): the direction toward the sensor from what a LAS file
// has. Analytic scenes: a point under a known trajectory position; a scanner flying a known
// line whose scan angle puts points to the right of the flight; the vertical fallback.
#include <catch2/catch.hpp>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/formats/sensor_direction.h"

using namespace canopy;
using Eigen::Vector3d;

namespace {

constexpr double kDeg = common::kPi / 180;

formats::PointCloud cloud_of(const std::vector<Vector3d>& p) {
  formats::PointCloud c;
  c.resize(p.size());
  const char* xyz[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    auto& col = c.add(xyz[a], formats::kFloat64);
    for (std::size_t i = 0; i < p.size(); ++i) col[i] = p[i][a];
  }
  return c;
}

void set(formats::PointCloud* c, const char* name, const std::vector<double>& v) {
  auto& col = c->add(name, formats::kFloat64);
  for (std::size_t i = 0; i < v.size(); ++i) col[i] = v[i];
}

// A scanner at `altitude` over flat ground z = 0 flying from `start` along the horizontal unit
// `heading` at 50 m/s, sweeping -30..30 deg across the line, 100 lines a second, 13 shots a line.
// LAS's convention: a positive scan angle is to the right of the flight. Point i's scan angle
// is angles[i], its time times[i].
struct Flight {
  std::vector<Vector3d> points;
  std::vector<double> times, angles;
};
Flight fly(const Vector3d& start, const Vector3d& heading, double altitude, double t0, int lines = 20) {
  Flight f;
  const Vector3d right(heading.y(), -heading.x(), 0);
  for (int l = 0; l < lines; ++l) {
    for (int k = 0; k < 13; ++k) {
      const double angle = -30 + 5 * k;
      const double t = t0 + l * 0.01 + k * 0.0005;
      const Vector3d sensor = start + heading * 50 * (t - t0) + Vector3d(0, 0, altitude);
      const Vector3d ground = sensor - Vector3d(0, 0, altitude) + right * altitude * std::tan(angle * kDeg);
      f.points.push_back(ground);
      f.times.push_back(t);
      f.angles.push_back(angle);
    }
  }
  return f;
}

}  // namespace

TEST_CASE("sensor directions: a point under a known trajectory position", "[sensor_direction]") {
  formats::Trajectory t;
  t.samples = {{0, 0, 0, 100, 0, 0, 0}, {10, 20, 40, 100, 0, 0, 0}};
  // At t = 5 the sensor is at (10, 20, 100).
  auto c = cloud_of({{10, 20, 0}, {10, -80, 0}, {10, 20, 50}});
  set(&c, "gps_time", {5, 5, 5});
  formats::SensorDirectionOptions o;
  o.trajectory = &t;
  o.trajectory_name = "traj.txt";
  const auto r = formats::sensor_directions(c, o, "pts.pcd");
  CHECK(r.used == formats::SensorSource::kTrajectory);
  CHECK(r.warnings.empty());
  REQUIRE(r.directions.size() == 3);
  CHECK(r.directions[0] == Vector3d(0, 0, 1));
  CHECK(r.directions[1].isApprox(Vector3d(0, 1, 1).normalized(), 1e-15));
  CHECK(r.directions[2] == Vector3d(0, 0, 1));

  // Points in a candidate frame: local -> world turns 90 deg about z and shifts; the direction
  // comes back in the local frame (world +y = local +x... here world (0,1,1) = local (1,0,1)).
  Eigen::Isometry3d to_world = Eigen::Isometry3d::Identity();
  to_world.linear() = Eigen::AngleAxisd(90 * kDeg, Vector3d::UnitZ()).toRotationMatrix();
  to_world.translation() = Vector3d(10, 20, 0);
  auto local = cloud_of({{0, 0, 0}, {-100, 0, 0}});  // world (10, 20, 0) and (10, -80, 0)
  set(&local, "gps_time", {5, 5});
  o.to_world = to_world;
  const auto l = formats::sensor_directions(local, o, "pts.pcd");
  CHECK(l.directions[0].isApprox(Vector3d(0, 0, 1), 1e-15));
  CHECK(l.directions[1].isApprox(Vector3d(1, 0, 1).normalized(), 1e-15));

  // A GPS time beyond the trajectory's end by more than the tolerance names the trajectory.
  set(&c, "gps_time", {5, 5, 11.5});
  o.to_world = Eigen::Isometry3d::Identity();
  try {
    formats::sensor_directions(c, o, "pts.pcd");
    FAIL("no error");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "traj.txt");
    CHECK_THAT(e.what(), Catch::Contains("GPS time 11.5 s is outside the trajectory's span [0, 10]"));
  }
  o.tolerance = 2;
  CHECK(formats::sensor_directions(c, o, "pts.pcd")
            .directions[2]
            .isApprox((Vector3d(20, 40, 100) - Vector3d(10, 20, 50)).normalized(), 1e-15));
  // Without gps_time: an error naming the points.
  try {
    formats::sensor_directions(cloud_of({{0, 0, 0}}), o, "pts.pcd");
    FAIL("no error");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "pts.pcd");
    CHECK_THAT(e.what(), Catch::Contains("field 'gps_time' missing"));
  }
}

TEST_CASE("sensor directions: scan angle 0 is vertical, +20 deg leans away from the right of the flight",
          "[sensor_direction]") {
  for (const Vector3d& heading : {Vector3d(0, 1, 0), Vector3d(0, -1, 0), Vector3d(1, 1, 0).normalized()}) {
    const Flight f = fly(Vector3d(500, 300, 0), heading, 200, 1000);
    auto c = cloud_of(f.points);
    set(&c, "gps_time", f.times);
    set(&c, "scan_angle", f.angles);
    formats::SensorDirectionOptions o;
    o.source = formats::SensorSource::kScanAngle;
    const auto r = formats::sensor_directions(c, o, "pts.pcd");
    CHECK(r.used == formats::SensorSource::kScanAngle);
    CHECK(r.warnings.empty());
    const Vector3d right(heading.y(), -heading.x(), 0);
    for (std::size_t i = 0; i < f.points.size(); ++i) {
      // The true direction toward the sensor, from the flight's geometry.
      const Vector3d truth = (Vector3d(0, 0, 200) - right * 200 * std::tan(f.angles[i] * kDeg)).normalized();
      CHECK(r.directions[i].isApprox(truth, 1e-9));
      if (f.angles[i] == 0) CHECK(r.directions[i].isApprox(Vector3d::UnitZ(), 1e-12));
      if (f.angles[i] == 20) {
        // Flying north (+y) the right is east (+x): the sensor lies west of the point.
        CHECK(r.directions[i].isApprox(Vector3d(0, 0, std::cos(20 * kDeg)) - right * std::sin(20 * kDeg), 1e-9));
        if (heading.y() == 1) CHECK(r.directions[i].x() == Approx(-std::sin(20 * kDeg)));
      }
    }
    Eigen::Vector2d d;
    double gain = 0;
    std::vector<std::size_t> rows(f.points.size());
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = i;
    REQUIRE(formats::flight_direction(f.points, f.times, f.angles, rows, &d, &gain));
    CHECK(d.isApprox(heading.head<2>(), 1e-9));
    CHECK(gain > 0);  // points move right as the angle grows
  }
}

TEST_CASE("sensor directions: flight lines by point_source_id, segments split at time gaps",
          "[sensor_direction]") {
  // Line 1 flies east, line 2 west over the same ground (times interleave in one file); line 2's
  // second pass, 30 s later, flies north with the same point_source_id.
  Flight a = fly(Vector3d(0, 0, 0), Vector3d(1, 0, 0), 300, 100);
  Flight b = fly(Vector3d(10, 5, 0), Vector3d(-1, 0, 0), 300, 100.003);
  Flight n = fly(Vector3d(5, -5, 0), Vector3d(0, 1, 0), 300, 130);
  std::vector<Vector3d> p;
  std::vector<double> t, ang, src;
  for (const Flight* f : {&a, &b, &n}) {
    p.insert(p.end(), f->points.begin(), f->points.end());
    t.insert(t.end(), f->times.begin(), f->times.end());
    ang.insert(ang.end(), f->angles.begin(), f->angles.end());
    src.insert(src.end(), f->points.size(), f == &a ? 1 : 2);
  }
  auto c = cloud_of(p);
  set(&c, "gps_time", t);
  set(&c, "scan_angle", ang);
  set(&c, "point_source_id", src);
  formats::SensorDirectionOptions o;  // auto: no columns, no trajectory, scan angle + time present
  const auto r = formats::sensor_directions(c, o, "pts.pcd");
  CHECK(r.used == formats::SensorSource::kScanAngle);
  CHECK(r.warnings.empty());
  CHECK_THAT(r.summary, Catch::Contains("3 flight segments"));
  std::size_t i = 0;
  for (const auto& [f, heading] :
       {std::pair<const Flight*, Vector3d>{&a, {1, 0, 0}}, {&b, {-1, 0, 0}}, {&n, {0, 1, 0}}}) {
    const Vector3d right(heading.y(), -heading.x(), 0);
    for (std::size_t k = 0; k < f->points.size(); ++k, ++i) {
      const double th = f->angles[k] * kDeg;
      CHECK(r.directions[i].isApprox(std::cos(th) * Vector3d::UnitZ() - std::sin(th) * right, 1e-9));
    }
  }
}

TEST_CASE("sensor directions: a fixed scan angle (orthographic look) takes the flight from time alone",
          "[sensor_direction]") {
  // A look at a constant 15 deg right of a flight toward -x: position along the line is time.
  std::vector<Vector3d> p;
  std::vector<double> t, ang;
  for (int i = 0; i < 50; ++i) {
    p.emplace_back(-2.0 * i, 3, 0);
    t.push_back(7 + 0.04 * i);
    ang.push_back(15);
  }
  auto c = cloud_of(p);
  set(&c, "gps_time", t);
  set(&c, "scan_angle", ang);
  formats::SensorDirectionOptions o;
  o.source = formats::SensorSource::kScanAngle;
  const auto r = formats::sensor_directions(c, o, "pts.pcd");
  const Vector3d right(0, 1, 0);  // flying -x, the right is +y
  CHECK(r.directions[0].isApprox(std::cos(15 * kDeg) * Vector3d::UnitZ() - std::sin(15 * kDeg) * right, 1e-12));
  // All at one GPS time: no flight direction; the vertical, with a warning.
  set(&c, "gps_time", std::vector<double>(p.size(), 7));
  const auto v = formats::sensor_directions(c, o, "pts.pcd");
  REQUIRE(v.warnings.size() == 1);
  CHECK_THAT(v.warnings[0], Catch::Contains("pts.pcd: 1 of 1 flight segments"));
  CHECK(v.directions[3] == Vector3d::UnitZ());
}

TEST_CASE("sensor directions: columns first, vertical last with a warning", "[sensor_direction]") {
  auto c = cloud_of({{1, 2, 3}, {4, 5, 6}});
  formats::SensorDirectionOptions o;
  // Nothing to derive from: the vertical (of the world frame, in the points' frame), warned.
  auto r = formats::sensor_directions(c, o, "pts.pcd");
  CHECK(r.used == formats::SensorSource::kVertical);
  REQUIRE(r.warnings.size() == 1);
  CHECK_THAT(r.warnings[0], Catch::StartsWith("pts.pcd: no sensor_x/y/z") && Catch::Contains("vertical"));
  CHECK(r.directions == std::vector<Vector3d>(2, Vector3d::UnitZ()));
  o.to_world.linear() = Eigen::AngleAxisd(90 * kDeg, Vector3d::UnitX()).toRotationMatrix();
  r = formats::sensor_directions(c, o, "pts.pcd");
  CHECK(r.directions[0].isApprox(Vector3d(0, 1, 0), 1e-15));  // world z = local +y
  // Asked for explicitly: no warning.
  o.source = formats::SensorSource::kVertical;
  CHECK(formats::sensor_directions(c, o, "pts.pcd").warnings.empty());
  // The simulator's columns win over everything: nothing computed.
  for (const char* f : {"sensor_x", "sensor_y", "sensor_z"}) c.add(f);
  set(&c, "gps_time", {1, 2});
  set(&c, "scan_angle", {0, 0});
  o.source = formats::SensorSource::kAuto;
  r = formats::sensor_directions(c, o, "pts.pcd");
  CHECK(r.used == formats::SensorSource::kColumns);
  CHECK(r.directions.empty());
  // Columns asked for but missing; a trajectory asked for but not given.
  o.source = formats::SensorSource::kColumns;
  CHECK_THROWS_WITH(formats::sensor_directions(cloud_of({{0, 0, 0}}), o, "pts.pcd"),
                    Catch::Contains("pts.pcd: field 'sensor_x' missing"));
  o.source = formats::SensorSource::kTrajectory;
  CHECK_THROWS_AS(formats::sensor_directions(c, o, "pts.pcd"), common::UsageError);
  CHECK(formats::parse_sensor_source("scan-angle", "--s") == formats::SensorSource::kScanAngle);
  CHECK_THROWS_AS(formats::parse_sensor_source("sky", "--s"), common::UsageError);
}
