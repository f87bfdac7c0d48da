// Procedural vehicle families: twelve classes of POV-Ray CSG vehicles drawn from class ranges
// (docs/decisions/families.md lists the ranges and the real vehicles they come from).
//
// Every class builder works in the world frame (x forward, y left, z up, metres, ground z = 0,
// centred on x and y) with boxes cut by half-spaces, cylinders and half ellipsoids; the
// emitter converts to POV-Ray's frame with pov_frame() and prints fixed-precision numbers, so
// the text depends on the (class, instance) pair only.
#include "canopy/sim/families.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "canopy/common/error.h"
#include "canopy/common/rng.h"
#include "canopy/sim/model.h"

namespace canopy::sim {

using Eigen::Vector3d;

namespace {

// Class ranges (m): length, width, height of the whole vehicle. Sources in families.md.
const std::vector<FamilyClass> kClasses = {
    {"sedan", {4.40, 5.10}, {1.72, 1.90}, {1.38, 1.50}},
    {"hatchback", {3.55, 4.40}, {1.62, 1.80}, {1.42, 1.56}},
    {"suv", {4.40, 5.30}, {1.80, 2.05}, {1.65, 1.95}},
    {"pickup", {5.00, 5.90}, {1.80, 2.05}, {1.75, 2.00}},
    {"van", {4.90, 6.00}, {1.90, 2.06}, {1.95, 2.75}},
    {"box-truck", {7.00, 10.00}, {2.30, 2.55}, {3.00, 3.90}},
    {"semi-tractor", {5.80, 7.50}, {2.45, 2.55}, {3.00, 4.00}},
    {"bus", {10.50, 13.50}, {2.50, 2.55}, {2.90, 3.40}},
    {"wheeled-apc", {6.40, 8.00}, {2.50, 3.00}, {2.30, 2.90}},
    {"tracked-apc", {4.90, 7.00}, {2.70, 3.30}, {1.90, 2.70}},
    {"tank", {8.70, 11.40}, {3.40, 3.80}, {2.20, 3.00}},
    {"wheel-loader", {6.80, 9.00}, {2.50, 3.20}, {3.00, 3.70}},
};

// A half-space kept by a cut: n . x <= n . p (world frame; n need not be unit).
struct Cut {
  Vector3d n, p;
};

class Builder {
 public:
  void comment(const std::string& text) { out_ += "  // " + text + "\n"; }

  void box(const Vector3d& lo, const Vector3d& hi, const std::vector<Cut>& cuts = {}) {
    grow(lo);
    grow(hi);
    const std::string b = "box { " + vec(lo) + ", " + vec(hi) + " }";
    if (cuts.empty()) {
      out_ += "  " + b + "\n";
      return;
    }
    out_ += "  intersection {\n    " + b + "\n";
    for (const auto& c : cuts) {
      const Vector3d n = c.n.normalized();
      out_ += "    plane { " + vec(n) + ", " + num(n.dot(c.p)) + " }\n";
    }
    out_ += "  }\n";
  }

  // A cylinder between a and b; its bounds as POV-Ray computes them for an axis-aligned one
  // (the generator uses oblique cylinders only well inside the bounds).
  void cylinder(const Vector3d& a, const Vector3d& b, double r) {
    const Vector3d d = (b - a).normalized();
    for (int k = 0; k < 3; ++k) {
      const double e = r * std::sqrt(std::max(0.0, 1 - d[k] * d[k]));
      Vector3d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
      lo[k] -= e;
      hi[k] += e;
      grow_axis(k, lo[k], hi[k]);
    }
    out_ += "  cylinder { " + vec(a) + ", " + vec(b) + ", " + num(r) + " }\n";
  }

  // A wheel: a cylinder along y centred at (x, y, r).
  void wheel(double x, double y, double r, double width) {
    cylinder({x, y - width / 2, r}, {x, y + width / 2, r}, r);
  }

  // The upper half of an ellipsoid with semi-axes `radii` centred at `c`.
  void dome(const Vector3d& c, const Vector3d& radii) {
    grow(c - Vector3d(radii.x(), radii.y(), 0));
    grow(c + radii);
    const Vector3d s = pov_frame(radii);
    out_ += "  intersection {\n    sphere { 0, 1 scale " + vec_raw(s) + " translate " + vec(c) +
            " }\n    plane { <0, -1, 0>, " + num(-c.z()) + " }\n  }\n";
  }

  std::string text(const std::string& header) const {
    return header + "#declare Vehicle = union {\n" + out_ + "}\n";
  }
  Vector3d lo() const { return lo_; }
  Vector3d hi() const { return hi_; }

 private:
  static std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", v);
    if (std::string(buf) == "-0.0000") return "0.0000";
    return buf;
  }
  static std::string vec_raw(const Vector3d& p) {
    return "<" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + ">";
  }
  static std::string vec(const Vector3d& world) { return vec_raw(pov_frame(world)); }
  void grow(const Vector3d& p) {
    for (int k = 0; k < 3; ++k) grow_axis(k, p[k], p[k]);
  }
  void grow_axis(int k, double lo, double hi) {
    lo_[k] = empty_ ? lo : std::min(lo_[k], lo);
    hi_[k] = empty_ ? hi : std::max(hi_[k], hi);
    if (k == 2) empty_ = false;
  }

  std::string out_;
  Vector3d lo_ = Vector3d::Zero(), hi_ = Vector3d::Zero();
  bool empty_ = true;
};

struct Draw {
  common::Rng rng;
  double u(double lo, double hi) { return rng.uniform(lo, hi); }
  double in(const FamilyRange& r) { return rng.uniform(r.lo, r.hi); }
  bool chance(double p) { return rng.uniform() < p; }
};

using Sizes = Vector3d;  // L, W, H

// Two wheels of one axle at x, their outer faces at +-outer.
void axle(Builder* b, double x, double outer, double r, double width) {
  b->wheel(x, outer - width / 2, r, width);
  b->wheel(x, -(outer - width / 2), r, width);
}

// Passenger cars: three-box sedan, two-box hatchback and SUV (different proportions).
enum class Car { kSedan, kHatchback, kSuv };

void car(Builder* b, Draw* d, const Sizes& s, Car kind) {
  const double L = s.x(), W = s.y(), H = s.z();
  const bool suv = kind == Car::kSuv;
  const double r = suv ? d->u(0.35, 0.41) : kind == Car::kSedan ? d->u(0.30, 0.34) : d->u(0.28, 0.32);
  const double tyre = suv ? d->u(0.22, 0.27) : d->u(0.18, 0.22);
  const double zb = suv ? d->u(0.26, 0.34) : d->u(0.14, 0.20);  // body underside
  const double belt = H * (suv ? d->u(0.56, 0.62) : d->u(0.54, 0.60));
  const double hood = L * (kind == Car::kSedan ? d->u(0.24, 0.30)
                           : kind == Car::kSuv ? d->u(0.20, 0.25)
                                               : d->u(0.17, 0.23));
  const double x_ws = L / 2 - hood;  // windscreen base
  const double x_rw = kind == Car::kSedan ? -L / 2 + L * d->u(0.19, 0.24) : -L / 2 + d->u(0.06, 0.14);
  const double rake = d->u(0.55, 0.80);  // windscreen: run over rise
  const double rear = kind == Car::kSedan ? d->u(0.70, 1.00) : suv ? d->u(2.5, 5.0) : d->u(1.4, 2.6);
  const double wheelbase = L * (kind == Car::kHatchback ? d->u(0.61, 0.66) : d->u(0.56, 0.61));
  const double x_axle = L * d->u(0.00, 0.03);
  b->comment("lower body: floor to belt line, nose and tail rounded off, flanks tumbling home");
  b->box({-L / 2, -W / 2, zb}, {L / 2, W / 2, belt},
         {{{1, 0, -0.6}, {L / 2, 0, zb + 0.18}},
          {{1, 0, 0.5}, {L / 2, 0, belt - 0.20}},
          {{-1, 0, 0.5}, {-L / 2, 0, belt - 0.16}},
          {{-1, 0, -0.6}, {-L / 2, 0, zb + 0.18}},
          {{0, 1, 0.2}, {0, W / 2, belt}},
          {{0, -1, 0.2}, {0, -W / 2, belt}}});
  b->comment("bonnet");
  b->box({x_ws - 0.10, -W / 2 + 0.06, belt - 0.02}, {L / 2 - 0.10, W / 2 - 0.06, belt + 0.09},
         {{{0.09, 0, 1}, {L / 2 - 0.10, 0, belt + 0.02}}});
  if (kind == Car::kSedan) {
    b->comment("boot lid");
    b->box({-L / 2 + 0.05, -W / 2 + 0.06, belt - 0.02}, {x_rw + 0.25, W / 2 - 0.06, belt + 0.13});
  }
  const double roof_top = suv ? H - 0.05 : H;
  b->comment("greenhouse: windscreen, roof, rear window, side glass");
  b->box({x_rw, -W / 2 + 0.08, belt}, {x_ws + 0.10, W / 2 - 0.08, roof_top},
         {{{1, 0, rake}, {x_ws + 0.10, 0, belt}},
          {{-rear, 0, 1}, {x_rw, 0, belt + 0.08}},
          {{0, 1, 0.35}, {0, W / 2 - 0.08, belt}},
          {{0, -1, 0.35}, {0, -W / 2 + 0.08, belt}}});
  if (suv) {
    b->comment("roof rails");
    const double x0 = x_rw + 0.45, x1 = x_ws - 0.45;
    for (int side : {-1, 1})
      b->box({x0, side * (W / 2 - 0.30) - 0.03, roof_top - 0.01}, {x1, side * (W / 2 - 0.30) + 0.03, H});
  }
  b->comment("wheels");
  const double outer = W / 2 - d->u(0.02, 0.06);
  axle(b, x_axle + wheelbase / 2, outer, r, tyre);
  axle(b, x_axle - wheelbase / 2, outer, r, tyre);
}

void pickup(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.37, 0.42), tyre = d->u(0.24, 0.29);
  const double zb = d->u(0.36, 0.46);
  const double belt = H * d->u(0.56, 0.62);
  const double x_ws = L / 2 - L * d->u(0.20, 0.25);
  const double x_cb = x_ws - L * d->u(0.17, 0.27);  // back of the cab (single to crew cab)
  const double floor = zb + d->u(0.32, 0.42);       // bed floor
  const double side_top = belt + d->u(-0.04, 0.06);
  b->comment("front body to the back of the cab");
  b->box({x_cb, -W / 2, zb}, {L / 2, W / 2, belt},
         {{{1, 0, 0.4}, {L / 2, 0, belt - 0.15}}, {{1, 0, -0.7}, {L / 2, 0, zb + 0.2}}});
  b->comment("bonnet");
  b->box({x_ws - 0.10, -W / 2 + 0.05, belt - 0.02}, {L / 2 - 0.06, W / 2 - 0.05, belt + 0.08});
  b->comment("cab: windscreen, roof, upright back");
  b->box({x_cb, -W / 2 + 0.06, belt}, {x_ws + 0.10, W / 2 - 0.06, H},
         {{{1, 0, d->u(0.50, 0.70)}, {x_ws + 0.10, 0, belt}},
          {{0, 1, 0.25}, {0, W / 2 - 0.06, belt}},
          {{0, -1, 0.25}, {0, -W / 2 + 0.06, belt}}});
  const double x_bf = x_cb - d->u(0.06, 0.12);  // front wall of the bed
  b->comment("bed: chassis and floor, open box (two sides, front wall, tailgate)");
  b->box({-L / 2, -W / 2 + 0.04, zb}, {x_bf, W / 2 - 0.04, floor});
  for (int side : {-1, 1}) {
    b->box({-L / 2, side > 0 ? W / 2 - 0.07 : -W / 2, floor},
           {x_bf, side > 0 ? W / 2 : -W / 2 + 0.07, side_top});
  }
  b->box({x_bf - 0.07, -W / 2, floor}, {x_bf, W / 2, side_top});
  b->box({-L / 2, -W / 2, floor}, {-L / 2 + 0.07, W / 2, side_top});
  b->comment("wheels");
  const double outer = W / 2 - d->u(0.02, 0.06);
  axle(b, L / 2 - L * d->u(0.15, 0.19), outer, r, tyre);
  axle(b, -L / 2 + L * d->u(0.19, 0.25), outer, r, tyre);
}

void van(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.33, 0.38), tyre = d->u(0.20, 0.24);
  const double zb = d->u(0.30, 0.40);
  const double nose = L * d->u(0.08, 0.14);
  const double bonnet = d->u(0.95, 1.15);  // bonnet height
  b->comment("one box: cargo and cabin under one roof, steep windscreen");
  b->box({-L / 2, -W / 2, zb}, {L / 2 - nose, W / 2, H},
         {{{1, 0, d->u(0.35, 0.65)}, {L / 2 - nose, 0, bonnet}},
          {{-1, 0, 1}, {-L / 2, 0, H - 0.06}},
          {{0, 1, 0.08}, {0, W / 2, zb + 0.8}},
          {{0, -1, 0.08}, {0, -W / 2, zb + 0.8}}});
  b->comment("short bonnet");
  b->box({L / 2 - nose - 0.05, -W / 2 + 0.05, zb}, {L / 2, W / 2 - 0.05, bonnet},
         {{{1, 0, 0.6}, {L / 2, 0, bonnet - 0.25}}});
  b->comment("wheels");
  const double outer = W / 2 - d->u(0.03, 0.08);
  axle(b, L / 2 - L * d->u(0.14, 0.18), outer, r, tyre);
  axle(b, -L / 2 + L * d->u(0.17, 0.25), outer, r, tyre);
}

void box_truck(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.45, 0.52);
  const double cab = d->u(1.70, 2.30), cab_h = d->u(2.50, std::min(2.95, H - 0.15));
  const double cab_w = W * d->u(0.88, 0.95);
  const double gap = d->u(0.05, 0.20);
  const double box_floor = d->u(0.95, 1.25);
  b->comment("cab over the front axle");
  b->box({L / 2 - cab, -cab_w / 2, 0.55}, {L / 2, cab_w / 2, cab_h},
         {{{1, 0, d->u(0.10, 0.35)}, {L / 2, 0, cab_h - 0.9}}, {{1, 0, -0.3}, {L / 2, 0, 0.9}}});
  b->comment("cargo box");
  b->box({-L / 2, -W / 2, box_floor}, {L / 2 - cab - gap, W / 2, H});
  b->comment("chassis rails");
  b->box({-L / 2 + 0.3, -0.50, 0.60}, {L / 2 - cab + 0.2, 0.50, box_floor});
  b->comment("wheels: single front, dual rear");
  const double outer = cab_w / 2 - 0.02;
  axle(b, L / 2 - cab * d->u(0.40, 0.60), outer, r, 0.28);
  axle(b, -L / 2 + (L - cab) * d->u(0.22, 0.32), W / 2 - d->u(0.05, 0.12), r, 0.52);
}

void semi_tractor(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.50, 0.54);
  const bool conventional = d->chance(0.5);
  const double hood = conventional ? d->u(1.20, 1.80) : d->u(0.00, 0.10);
  const double cab = d->u(1.70, 2.30);
  const double x_cf = L / 2 - hood;  // cab front
  const double cab_top = std::min(H - 0.25, d->u(2.80, 3.40));
  const double cab_floor = d->u(0.95, 1.15);
  if (conventional) {
    b->comment("engine bonnet of a conventional tractor");
    b->box({x_cf - 0.05, -0.60, 0.70}, {L / 2, 0.60, d->u(1.60, 1.90)}, {{{1, 0, 0.7}, {L / 2, 0, 1.35}}});
  }
  b->comment("bumper");
  b->box({L / 2 - 0.30, -W / 2 + 0.05, 0.40}, {L / 2, W / 2 - 0.05, 0.80});
  b->comment("cab (day cab or sleeper) and roof fairing");
  b->box({x_cf - cab, -W / 2, cab_floor}, {x_cf, W / 2, cab_top},
         {{{1, 0, d->u(0.12, 0.35)}, {x_cf, 0, cab_floor + 0.9}}});
  b->box({x_cf - cab + 0.20, -W / 2 + 0.10, cab_top - 0.01}, {x_cf - 0.30, W / 2 - 0.10, H},
         {{{1, 0, d->u(0.8, 1.5)}, {x_cf - 0.30, 0, cab_top}}});
  const double x_back = x_cf - cab;
  b->comment("chassis rails, fifth-wheel plate, fuel tanks");
  b->box({-L / 2, -0.50, 0.80}, {x_back + 0.2, 0.50, 1.05});
  const double rear = x_back + L / 2;
  const bool tandem = rear >= 2.9;
  const double x_r1 = -L / 2 + d->u(0.65, 0.85);
  const double x_r2 = tandem ? x_r1 + d->u(1.30, 1.40) : x_r1;
  const double fifth = (x_r1 + x_r2) / 2;
  b->box({fifth - 0.60, -0.90, 1.05}, {fifth + 0.60, 0.90, 1.22});
  const double tank_r = d->u(0.28, 0.34);
  const double x_fa = conventional ? L / 2 - hood * 0.6 : x_cf - 0.55;  // steer axle
  const double tank_end = std::min(x_back + d->u(0.9, 1.4), x_fa - r - 0.05);
  for (int side : {-1, 1}) {
    b->cylinder({x_back + 0.15, side * (W / 2 - 0.40), 0.78},
                {std::max(tank_end, x_back + 0.45), side * (W / 2 - 0.40), 0.78}, tank_r);
  }
  b->comment("wheels: steer axle and drive axle(s)");
  const double outer = W / 2 - 0.02;
  axle(b, x_fa, outer - 0.05, r, 0.32);
  axle(b, x_r1, outer, r, 0.55);
  if (tandem) axle(b, x_r2, outer, r, 0.55);
}

void bus(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.48, 0.52);
  const double ac = d->u(0.20, 0.32);
  const double top = H - ac;
  const double zb = d->u(0.25, 0.35);
  b->comment("body: one long box, near-vertical windscreen");
  b->box({-L / 2, -W / 2, zb}, {L / 2, W / 2, top},
         {{{1, 0, d->u(0.05, 0.25)}, {L / 2, 0, 1.0}},
          {{-1, 0, 1}, {-L / 2, 0, top - 0.10}},
          {{1, 0, 1}, {L / 2, 0, top - 0.08}}});
  b->comment("roof air-conditioning pod");
  const double x0 = -L / 2 + L * d->u(0.10, 0.40), len = d->u(2.0, 3.5);
  b->box({x0, -0.85, top - 0.01}, {x0 + len, 0.85, H});
  b->comment("wheels");
  const double outer = W / 2 - 0.04;
  axle(b, L / 2 - d->u(2.40, 2.90), outer, r, 0.30);
  axle(b, -L / 2 + d->u(3.00, 3.70), outer, r, 0.55);
}

void wheeled_apc(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.52, 0.62), tyre = d->u(0.33, 0.40);
  const int axles = d->chance(0.75) ? 4 : 3;
  const double zb = d->u(0.40, 0.55);
  const bool turret = d->chance(0.6);
  const double hh = turret ? H - d->u(0.45, 0.65) : H - d->u(0.30, 0.45);  // hull roof
  const double hull_w = W - 2 * d->u(0.10, 0.18);
  b->comment("hull: long sloped glacis, bevelled sides, blunt rear");
  b->box({-L / 2, -hull_w / 2, zb}, {L / 2, hull_w / 2, hh},
         {{{1, 0, d->u(0.8, 1.6)}, {L / 2, 0, zb + 0.55}},
          {{1, 0, -1}, {L / 2, 0, zb + 0.25}},
          {{-1, 0, 0.25}, {-L / 2, 0, hh}},
          {{0, 1, d->u(0.5, 1.0)}, {0, hull_w / 2, hh - 0.45}},
          {{0, -1, d->u(0.5, 1.0)}, {0, -hull_w / 2, hh - 0.45}},
          {{0, 1, -1}, {0, hull_w / 2, zb + 0.30}},
          {{0, -1, -1}, {0, -hull_w / 2, zb + 0.30}}});
  const double xt = d->u(-0.6, 0.6);
  if (turret) {
    b->comment("small turret with autocannon");
    const double tr = d->u(0.60, 0.85);
    b->cylinder({xt, 0, hh - 0.02}, {xt, 0, H}, tr);
    b->cylinder({xt + tr - 0.1, 0, H - 0.22}, {std::min(L / 2 - 0.1, xt + tr + d->u(1.2, 2.0)), 0, H - 0.22},
                0.05);
  } else {
    b->comment("remote weapon station");
    b->box({xt - 0.40, -0.40, hh - 0.02}, {xt + 0.40, 0.40, H});
  }
  b->comment("wheels, evenly spaced");
  const double xf = L / 2 - d->u(1.10, 1.50), xr = -L / 2 + d->u(1.00, 1.40);
  for (int i = 0; i < axles; ++i) axle(b, xf + (xr - xf) * i / (axles - 1), W / 2, r, tyre);
}

// A track run: a box with half-cylinder ends, along x, standing on the ground.
void track(Builder* b, double x0, double x1, double y, double width, double rt) {
  b->box({x0, y - width / 2, 0}, {x1, y + width / 2, 2 * rt});
  b->cylinder({x0, y - width / 2, rt}, {x0, y + width / 2, rt}, rt);
  b->cylinder({x1, y - width / 2, rt}, {x1, y + width / 2, rt}, rt);
}

void tracked_apc(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double rt = d->u(0.34, 0.42), tw = d->u(0.38, 0.50);
  const bool turret = d->chance(0.4);
  const double cupola = d->u(0.22, 0.40);
  const double hh = turret ? H - d->u(0.45, 0.60) : H - cupola;  // hull roof
  b->comment("tracks");
  for (int side : {-1, 1})
    track(b, -L / 2 + rt + d->u(0.05, 0.2), L / 2 - rt - d->u(0.25, 0.45), side * (W / 2 - tw / 2), tw, rt);
  b->comment("hull: tall box over the tracks, large sloped front");
  const double zb = d->u(0.42, 0.52);
  b->box({-L / 2, -W / 2 + tw, zb}, {L / 2, W / 2 - tw, hh}, {{{1, 0, d->u(0.5, 1.3)}, {L / 2, 0, zb + 0.45}}});
  b->box({-L / 2 + 0.05, -W / 2, 2 * rt + 0.04}, {L / 2 - 0.30, W / 2, hh},
         {{{1, 0, d->u(0.5, 1.3)}, {L / 2 - 0.30, 0, 2 * rt + 0.20}}});
  const double xc = d->u(-0.2, 0.8);
  if (turret) {
    b->comment("one-man turret with a short cannon");
    const double tr = d->u(0.55, 0.80);
    b->cylinder({xc, 0, hh - 0.02}, {xc, 0, H}, tr);
    b->cylinder({xc + tr - 0.1, 0, H - 0.20}, {std::min(L / 2 - 0.05, xc + tr + d->u(1.2, 2.2)), 0, H - 0.20},
                0.05);
  } else {
    b->comment("commander's cupola");
    b->cylinder({xc, 0.5, hh - 0.02}, {xc, 0.5, H}, d->u(0.30, 0.40));
  }
}

void tank(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double overhang = d->u(std::max(2.2, L - 8.0), std::min(3.4, L - 6.5));  // gun beyond the hull
  const double hull = L - overhang;
  const double x_tail = -L / 2, x_nose = x_tail + hull;
  const double rt = d->u(0.40, 0.50), tw = d->u(0.55, 0.70);
  const double deck = d->u(1.55, 1.85);  // hull roof
  const double cup = d->u(0.15, 0.35);
  const double troof = H - cup;  // turret roof
  b->comment("tracks, fenders");
  for (int side : {-1, 1}) {
    track(b, x_tail + rt + 0.10, x_nose - rt - 0.15, side * (W / 2 - tw / 2), tw, rt);
    b->box({x_tail, side > 0 ? W / 2 - tw : -W / 2, 2 * rt + 0.05},
           {x_nose, side > 0 ? W / 2 : -W / 2 + tw, 2 * rt + 0.10});
  }
  b->comment("hull: long, low glacis");
  b->box({x_tail, -W / 2 + tw, 0.40}, {x_nose, W / 2 - tw, deck},
         {{{1, 0, d->u(1.2, 2.2)}, {x_nose, 0, 0.95}},
          {{1, 0, -1}, {x_nose, 0, 0.80}},
          {{-1, 0, 0.35}, {x_tail, 0, deck - 0.25}}});
  const double tx = x_tail + hull * d->u(0.50, 0.62);  // turret centre
  const double tl = d->u(2.8, 3.8), twd = std::min(W - 0.9, d->u(2.2, 3.0));
  if (d->chance(0.5)) {
    b->comment("turret: cast dome");
    b->cylinder({tx, 0, deck - 0.02}, {tx, 0, deck + 0.15}, twd / 2 - 0.15);
    b->dome({tx, 0, deck + 0.12}, {tl / 2, twd / 2, troof - deck - 0.12});
  } else {
    b->comment("turret: welded, flat faces, wedge front");
    b->box({tx - tl / 2, -twd / 2, deck - 0.02}, {tx + tl / 2, twd / 2, troof},
           {{{1, 0, d->u(0.3, 1.0)}, {tx + tl / 2, 0, troof - 0.35}},
            {{1, 1.2, 0}, {tx + tl / 2 - 0.5, twd / 2, 0}},
            {{1, -1.2, 0}, {tx + tl / 2 - 0.5, -twd / 2, 0}}});
  }
  const double gz = deck + (troof - deck) * d->u(0.40, 0.55);
  b->comment("gun, mantlet, cupola");
  b->cylinder({tx + tl / 2 - 0.3, 0, gz}, {L / 2, 0, gz}, d->u(0.07, 0.09));
  b->box({tx + tl / 2 - 0.45, -0.35, gz - 0.22}, {tx + tl / 2 + 0.05, 0.35, gz + 0.22});
  const double cy = d->u(0.3, 0.6);
  b->cylinder({tx - tl / 4, cy, troof - 0.02}, {tx - tl / 4, cy, H}, 0.30);
}

void wheel_loader(Builder* b, Draw* d, const Sizes& s) {
  const double L = s.x(), W = s.y(), H = s.z();
  const double r = d->u(0.62, 0.85), tyre = d->u(0.50, 0.65);
  const double outer = W / 2 - d->u(0.05, 0.25);
  const double bucket = L * d->u(0.13, 0.16);  // bucket depth (x)
  const double bucket_h = d->u(1.00, 1.30);
  const double x_bk = L / 2 - bucket;  // bucket back
  const double wheelbase = L * d->u(0.40, 0.45);
  const double x_fa = x_bk - L * d->u(0.17, 0.22);
  const double x_ra = x_fa - wheelbase;
  b->comment("tyres");
  axle(b, x_fa, outer, r, tyre);
  axle(b, x_ra, outer, r, tyre);
  b->comment("front frame, fenders");
  b->box({x_fa - 0.9, -0.60, 0.55}, {x_fa + 1.0, 0.60, 1.40});
  for (int side : {-1, 1}) {
    b->box({x_fa - 0.7, side > 0 ? outer - tyre - 0.05 : -outer - 0.05, 2 * r + 0.02},
           {x_fa + 0.7, side > 0 ? outer + 0.05 : -outer + tyre + 0.05, 2 * r + 0.10});
  }
  b->comment("lift arms and tilt link");
  for (int side : {-1, 1}) b->cylinder({x_fa - 1.2, side * 0.55, 2.05}, {x_bk + 0.1, side * 0.55, 1.0}, 0.16);
  b->cylinder({x_fa + 0.4, -0.55, 1.70}, {x_fa + 0.4, 0.55, 1.70}, 0.14);
  b->comment("bucket: floor, back, side plates (open top and front)");
  b->box({x_bk, -W / 2, 0}, {L / 2, W / 2, 0.07});
  b->box({x_bk, -W / 2, 0}, {x_bk + 0.12, W / 2, bucket_h});
  for (int side : {-1, 1})
    b->box({x_bk, side > 0 ? W / 2 - 0.05 : -W / 2, 0},
           {L / 2, side > 0 ? W / 2 : -W / 2 + 0.05, bucket_h * 0.85});
  b->comment("cab over the articulation, roof canopy");
  const double xc = (x_fa + x_ra) / 2 + d->u(0.0, 0.5);
  b->box({xc - 0.75, -0.75, 1.55}, {xc + 0.85, 0.75, H - 0.10}, {{{1, 0, 0.18}, {xc + 0.85, 0, 1.8}}});
  b->box({xc - 0.85, -0.85, H - 0.11}, {xc + 1.00, 0.85, H});
  b->comment("rear frame, engine hood, counterweight, exhaust stack");
  b->box({-L / 2 + 0.4, -0.65, 0.60}, {xc - 0.2, 0.65, 1.30});
  const double hood_top = d->u(2.2, 2.6);
  b->box({-L / 2 + 0.4, -0.85, 1.30}, {xc - 0.75, 0.85, hood_top},
         {{{-0.25, 0, 1}, {xc - 0.75, 0, hood_top}},
          {{0, 1, 0.45}, {0, 0.85, hood_top}},
          {{0, -1, 0.45}, {0, -0.85, hood_top}}});
  b->box({-L / 2, -1.10, 0.55}, {-L / 2 + 0.5, 1.10, 1.60}, {{{-1, 0, 0.6}, {-L / 2, 0, 1.30}}});
  b->cylinder({xc - 1.6, 0.45, 2.0}, {xc - 1.6, 0.45, std::min(H - 0.3, hood_top + 0.5)}, 0.08);
}

std::uint64_t instance_seed(const std::string& cls, int instance) {
  return common::derive_seed(static_cast<std::uint64_t>(instance), "family/" + cls);
}

}  // namespace

const std::vector<FamilyClass>& family_classes() { return kClasses; }

FamilyInstance make_family_instance(const std::string& vehicle_class, int instance) {
  const FamilyClass* c = nullptr;
  std::string names;
  for (const auto& k : kClasses) {
    if (vehicle_class == k.name) c = &k;
    names += std::string(names.empty() ? "" : ", ") + k.name;
  }
  if (!c) throw common::UsageError("unknown vehicle class '" + vehicle_class + "' (classes: " + names + ")");
  if (instance < 0 || instance > 999999999) {
    throw common::UsageError("family instance " + std::to_string(instance) + " outside 0..999999999");
  }
  Draw d{common::Rng(instance_seed(vehicle_class, instance))};
  const Sizes s(d.in(c->length), d.in(c->width), d.in(c->height));
  Builder b;
  const std::string cls = c->name;
  if (cls == "sedan")
    car(&b, &d, s, Car::kSedan);
  else if (cls == "hatchback")
    car(&b, &d, s, Car::kHatchback);
  else if (cls == "suv")
    car(&b, &d, s, Car::kSuv);
  else if (cls == "pickup")
    pickup(&b, &d, s);
  else if (cls == "van")
    van(&b, &d, s);
  else if (cls == "box-truck")
    box_truck(&b, &d, s);
  else if (cls == "semi-tractor")
    semi_tractor(&b, &d, s);
  else if (cls == "bus")
    bus(&b, &d, s);
  else if (cls == "wheeled-apc")
    wheeled_apc(&b, &d, s);
  else if (cls == "tracked-apc")
    tracked_apc(&b, &d, s);
  else if (cls == "tank")
    tank(&b, &d, s);
  else
    wheel_loader(&b, &d, s);
  FamilyInstance out;
  out.vehicle_class = cls;
  out.instance = instance;
  out.name = cls + "-" + std::to_string(instance);
  out.lo = b.lo();
  out.hi = b.hi();
  char header[512];
  std::snprintf(header, sizeof header,
                "// %s: instance %d of the procedural class %s (canopy families, "
                "docs/decisions/families.md).\n"
                "// Drawn dimensions: length %.3f m (x), width %.3f m, height %.3f m.\n"
                "// Frame: POV-Ray units metres, y up, ground at y = 0, centred at the origin, "
                "front toward +x.\n"
                "// Declares one object, Vehicle, without textures.\n",
                out.name.c_str(), instance, cls.c_str(), s.x(), s.y(), s.z());
  out.pov = b.text(header);
  return out;
}

bool is_family_spec(const std::string& spec) { return spec.rfind("family:", 0) == 0; }

FamilyInstance family_from_spec(const std::string& spec) {
  const auto colon = spec.find(':', 7);
  const std::string usage = "--model '" + spec + "': expected family:<class>:<instance>";
  if (!is_family_spec(spec) || colon == std::string::npos) throw common::UsageError(usage);
  const std::string cls = spec.substr(7, colon - 7), num = spec.substr(colon + 1);
  if (num.empty() || num.size() > 9 || num.find_first_not_of("0123456789") != std::string::npos) {
    throw common::UsageError(usage + " (instance: a number 0..999999999)");
  }
  return make_family_instance(cls, std::stoi(num));
}

}  // namespace canopy::sim
