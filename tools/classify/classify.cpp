// classify's decision (classify.h step 5) and the class table.
#include "classify/classify.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "canopy/common/error.h"
#include "canopy/common/vehicle_classes.h"
#include "classify/features.h"

namespace canopy::classify {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

// Logistic of how far a value lies past its threshold: 0.5 at the threshold, -> 1 beyond it
// (ratio value / threshold; steepness 8: 0.98 at 1.5 x, 0.02 at 0.5 x).
double past(double value, double threshold) {
  if (!(threshold > 0)) return value > 0 ? 1 : 0;
  return 1 / (1 + std::exp(-8 * (value / threshold - 1)));
}

// How far (in its uncertainty) a measured value lies outside [lo, hi].
double miss(double value, const std::array<double, 2>& range, double sigma) {
  return std::max({0.0, range[0] - value, value - range[1]}) / sigma;
}

struct Fit {
  const TableRange* cls = nullptr;
  double distance = kInf;    // sqrt of the summed squared misses (0 = inside every range)
  double centrality = kInf;  // squared distance from the ranges' middles, relative to their halves
};

Fit fit(const TableRange& k, const Features& f, double sigma, const Params& p) {
  Fit r;
  r.cls = &k;
  double dl = miss(f.length, k.length, sigma);
  // A tank's gun is thin: at low density its points may be too few to join the object.
  if (k.hull_length[1] > 0) dl = std::min(dl, miss(f.length, k.hull_length, sigma));
  const double dw = miss(f.width, k.width, sigma), dh = miss(f.height, k.height, sigma);
  r.distance = std::sqrt(dl * dl + dw * dw + dh * dh);
  // The profile: a contradiction costs profile_penalty (in the size's sigmas).
  const int plateau = f.plateau_share >= p.plateau_split ? +1 : -1;
  const int tail = f.end_high >= p.tail_split ? +1 : -1;
  if ((k.plateau != 0 && k.plateau != plateau) || (k.tail != 0 && k.tail != tail))
    r.distance += p.profile_penalty;
  auto rel = [&](double v, const std::array<double, 2>& g) {
    const double mid = 0.5 * (g[0] + g[1]), half = 0.5 * (g[1] - g[0]) + sigma;
    return (v - mid) * (v - mid) / (half * half);
  };
  r.centrality = rel(f.length, k.length) + rel(f.width, k.width) + rel(f.height, k.height);
  return r;
}

// A class range's name in a sentence: the class, and the modelbase entry it came from.
std::string label(const TableRange& k) {
  if (k.envelope > 0)
    return k.name + " (the envelope of " + std::to_string(k.envelope) + " modelbase entries)";
  return k.entry.empty() ? k.name : k.name + " (modelbase entry " + k.entry + ")";
}

// The envelope of every class's range along one dimension.
std::array<double, 2> envelope(const std::vector<TableRange>& table, std::array<double, 2> ClassRange::*dim) {
  std::array<double, 2> e{kInf, -kInf};
  for (const TableRange& k : table) {
    e[0] = std::min(e[0], (k.*dim)[0]);
    e[1] = std::max(e[1], (k.*dim)[1]);
  }
  return e;
}

// What kind of evidence a reason is (Answer::refused_on) unless the caller says: too_sparse the
// density, vegetation_like the surface, too_large / too_small / too_flat the size,
// not_vehicle_shape the shape.
const char* evidence_of(const std::string& reason) {
  if (reason == "too_sparse") return "density";
  if (reason == "vegetation_like") return "surface";
  if (reason == "not_vehicle_shape") return "shape";
  return "size";
}

// none with a reason; `strength` = how clearly (0.5 at the threshold, -> 1 beyond it); `on` the
// kind of evidence (evidence_of the reason unless given).
void refuse(Answer& a, const char* reason, std::string detail, double strength, const char* on = nullptr) {
  a.reason = reason;
  a.refused_on = on ? on : evidence_of(a.reason);
  a.detail = std::move(detail);
  a.confidence = std::clamp(strength, 0.0, 1.0);
}

bool sparse(Answer& a, const Params& p) {
  const Features& f = a.features;
  if (f.object_points < p.min_points) {
    refuse(a, "too_sparse",
           fmt("%.0f object points; a class answer needs at least %.0f (and %.0f points/m^2; "
               "a model answer about %.0f points/m^2)",
               static_cast<double>(f.object_points), static_cast<double>(p.min_points), p.min_density,
               p.model_density),
           0);
    return true;
  }
  if (f.density < p.min_density) {
    refuse(a, "too_sparse",
           fmt("%.1f points/m^2 on the object's top; a class answer needs %.1f, a model answer about %.0f",
               f.density, p.min_density, p.model_density),
           0);
    return true;
  }
  return false;
}

// Echo widths known and the cue on (classify.md §25): whether the object's echoes are a hard
// surface's.
bool hard_echoes(const Features& f, const Params& p) {
  return p.max_echo_widening > 0 && f.echo_widening && *f.echo_widening <= p.max_echo_widening;
}

// With echo_late (classify.md §25, §44): whether the object's echoes waive late_returns (hard, and
// at most echo_late_widening when it is set).
bool late_waivable(const Features& f, const Params& p) {
  return p.echo_late && hard_echoes(f, p) &&
         (p.echo_late_widening <= 0 || *f.echo_widening <= p.echo_late_widening);
}

// Whether late_returns would refuse the object and its echoes waived the cue.
bool late_waived(const Features& f, const Params& p) {
  return late_waivable(f, p) && f.late_returns && *f.late_returns > p.max_late_returns;
}

bool vegetation(Answer& a, const Params& p) {
  const Features& f = a.features;
  if (p.max_echo_widening > 0 && f.echo_widening && *f.echo_widening > p.max_echo_widening) {
    refuse(a, "vegetation_like",
           fmt("wide echoes: its median echo is %.0f%% of the open ground's (a hard surface <= %.0f%%)",
               100 * *f.echo_widening, 100 * p.max_echo_widening),
           past(*f.echo_widening, p.max_echo_widening));
    return true;
  }
  const bool hard = hard_echoes(f, p);
  struct Cue {
    const char* what;
    double value, threshold;
  };
  std::vector<Cue> cues = {
      {"%.0f%% of its interior points lie 0.5 m or more under another of its points "
       "(vehicle <= %.0f%%)",
       f.below_share, p.max_below_share}};
  if (!hard) {
    cues.push_back({"ground returns under it: %.0f%% of its interior returns (vehicle <= %.0f%%)",
                    f.ground_through, p.max_ground_through});
  }
  if (f.late_returns && !late_waivable(f, p)) {
    cues.push_back({p.late_shadow ? "%.0f%% later returns, those shadowed from above weighed by the shade "
                                    "around it (vehicle <= %.0f%%)"
                    : p.late_returns_inside
                        ? "%.0f%% later returns split inside it (return_number > 1 under earlier "
                          "returns at or below its top; vehicle <= %.0f%%)"
                        : "%.0f%% later returns (return_number > 1; vehicle <= %.0f%%)",
                    *f.late_returns, p.max_late_returns});
  }
  // Fill is good when high: its cue is the inverse ratio (threshold / value > 1 when below).
  if (f.fill && *f.fill < p.min_fill) {
    // With bridge_fill the rectangle less the shadows --bridge crossed (classify.md §27).
    const bool off_shadows = (p.bridge_fill || p.fill_empty_cells) && f.shadow_area > 0;
    const std::string shadows = off_shadows ? fmt(" less %.2f m^2 of shadow", f.shadow_area) : std::string();
    refuse(a, "vegetation_like",
           fmt(f.fill_from_first ? "porous or patchy: %.0f%% of the tile's first returns per m^2 on its "
                                   "rectangle (no open ground around it or in the tile)"
               : f.fill_from_tile
                   ? "porous or patchy: %.0f%% of the tile's open ground's points per m^2 on its "
                     "rectangle (no open ground around it)"
                   : "porous or patchy: %.0f%% of the open ground's points per m^2 on its rectangle",
               100 * *f.fill) +
               shadows +
               fmt(" (%.1f of %.1f; a solid top >= %.0f%%)",
                   off_shadows ? *f.fill * *f.ground_density : f.density, *f.ground_density, 100 * p.min_fill),
           past(p.min_fill, std::max(*f.fill, 1e-6)));
    return true;
  }
  const Cue* worst = nullptr;
  for (const Cue& c : cues) {
    if (c.value > c.threshold && (!worst || c.value / c.threshold > worst->value / worst->threshold))
      worst = &c;
  }
  if (worst) {
    refuse(a, "vegetation_like", fmt(worst->what, 100 * worst->value, 100 * worst->threshold),
           past(worst->value, worst->threshold));
    return true;
  }
  // The cells' size grows with the spacing and so does a sampled panel's apparent roughness
  // (its cell tops come from fewer points): the threshold scales with it, over a floor (§5, §28).
  const double rough = std::max(p.roughness_floor, p.max_roughness * f.spacing);
  const bool line = p.roughness == Params::Roughness::kLine;
  const double value = line ? f.top_roughness_line : f.top_roughness;
  const std::size_t cells = line ? f.top_cells_line : f.top_cells;
  if (cells >= 3 && value > rough) {
    // A top rough against the plane but smooth along lines (equipment on a roof, §43) is kept.
    const bool lines_too = !line && p.max_roughness_line > 0 && f.top_cells_line >= 3;
    // Its threshold follows the cells (max(0.3 m, 1.5 spacings)): it stops falling where they stop
    // at 0.3 m, at max_roughness_line x 0.2 m.
    const double rough_line = p.max_roughness_line * std::max(f.spacing, 0.2);
    if (lines_too && f.top_roughness_line <= rough_line) return false;
    refuse(a, "vegetation_like",
           fmt(line ? "the top is rough: %.0f mm from the line through its neighbours along the smoothest "
                      "direction (median; vehicle <= %.0f mm)"
                    : "the top is rough: %.0f mm from the local plane of its neighbours (median; vehicle <= "
                      "%.0f mm)",
               1e3 * value, 1e3 * rough) +
               (lines_too ? fmt(", and %.0f mm from the line through its neighbours along the smoothest "
                                "direction (vehicle <= %.0f mm)",
                                1e3 * f.top_roughness_line, 1e3 * rough_line)
                          : std::string()),
           past(value, rough));
    return true;
  }
  return false;
}

// The size gates against the envelope of every class (too_large, too_small, too_flat).
bool size_gates(Answer& a, const Params& p, double sigma, const std::vector<TableRange>& table) {
  const Features& f = a.features;
  const auto L = envelope(table, &ClassRange::length), W = envelope(table, &ClassRange::width),
             H = envelope(table, &ClassRange::height);
  const double g = p.size_gate * sigma;
  const std::string size = fmt("%.2f x %.2f x %.2f m", f.length, f.width, f.height);
  if (f.length > L[1] + g || f.width > W[1] + g || f.height > H[1] + g) {
    const double over =
        std::max({(f.length - L[1]) / sigma, (f.width - W[1]) / sigma, (f.height - H[1]) / sigma});
    refuse(
        a, "too_large",
        size + fmt(" exceeds the largest family (%.1f x %.2f x %.1f m) by %.1f sigma", L[1], W[1], H[1], over),
        past(over, p.size_gate));
    return true;
  }
  if (f.length < L[0] - g || f.width < W[0] - g) {
    const double under = std::max((L[0] - f.length) / sigma, (W[0] - f.width) / sigma);
    refuse(a, "too_small",
           size + fmt(" is under the smallest family (%.2f x %.2f m) by %.1f sigma", L[0], W[0], under),
           past(under, p.size_gate));
    return true;
  }
  if (f.height < H[0] - g) {
    const double under = (H[0] - f.height) / sigma;
    refuse(a, "too_flat", size + fmt(" is lower than the lowest family (%.2f m) by %.1f sigma", H[0], under),
           past(under, p.size_gate));
    return true;
  }
  return false;
}

// A vehicle has a roof: a share of its length within the plateau (docs/decisions/classify.md §5:
// fitted on real tiles, where the solid-top cues leave crowns of young trees).
bool roofless(Answer& a, const Params& p) {
  const Features& f = a.features;
  if (p.min_plateau <= 0 || f.plateau_share >= p.min_plateau) return false;
  refuse(a, "not_vehicle_shape",
         fmt("no roof: %.0f%% of its length within %.0f mm (+ 10%% of H) of its top (a vehicle >= %.0f%%)",
             100 * f.plateau_share, 1e3 * p.plateau_drop, 100 * p.min_plateau),
         past(p.min_plateau, std::max(f.plateau_share, 1e-6)));
  return true;
}

// Takes back the class answered (its shape contradicts it): not_vehicle_shape, `why`, and the
// class its size fitted.
void unanswer(Answer& a, const std::string& why, double strength) {
  const std::string cls = a.cls;
  a.cls.clear();
  a.group.clear();
  a.entry.clear();
  a.class_score = a.class_margin = 0;
  refuse(a, "not_vehicle_shape", why + "; its size fits " + cls, strength);
}

// A vehicle's ends fill its width (classify.md §15; off unless --min-end-fill): an answered
// class is refused, unless it is the tank (a hull length: its gun overhangs an end) or a modelbase
// entry whose own surface has an open end (or, unmeasured, a tank), when the emptier end fifth's top view is
// filled less than min_end_fill x the middle's.
void open_end(Answer& a, const Params& p, const std::vector<TableRange>& table) {
  const Features& f = a.features;
  if (p.min_end_fill <= 0 || a.cls.empty() || f.end_fill >= p.min_end_fill) return;
  for (const TableRange& k : table) {
    if (k.name == a.cls && k.entry == a.entry && (k.hull_length[1] > 0 || k.open_end)) return;
  }
  unanswer(
      a,
      fmt("an open or tapering end: its end fifth's top view is %.0f%% as full as its middle (a vehicle's "
          "ends fill its width: >= %.0f%%)",
          100 * f.end_fill, 100 * p.min_end_fill),
      past(p.min_end_fill, std::max(f.end_fill, 1e-6)));
}

// The outline gates (classify.md §16; each 0: off), after the class is chosen: the answer is
// refused when its outline contradicts its group (a car without a bonnet or boot under its cabin:
// a rock, a box; a tracked vehicle, van or bus with a step deeper than max_notch: a caravan or
// trailer behind its drawbar) or when an end is a drawbar (narrow and low: a trailer or caravan
// without its tractor).
void outline(Answer& a, const Params& p) {
  const Features& f = a.features;
  if (a.cls.empty()) return;
  std::string why;
  double strength = 0;
  const double step = p.rectangularity_sampled ? f.notch_sampled : f.notch;  // the oval gate's (§37)
  // A hard object under a crown whose late returns were waived: the wider drawbar (§44).
  const bool waived = late_waived(f, p) && p.echo_late_drawbar > p.drawbar_width;
  const double drawbar_width = waived ? p.echo_late_drawbar : p.drawbar_width;
  if (drawbar_width > 0 && p.drawbar_level > 0 && f.tip_width < drawbar_width && f.tip_level < p.drawbar_level) {
    why = fmt("a drawbar: its narrower end is %.0f%% of its width and %.0f%% of its height (a trailer or "
              "caravan without its tractor; a vehicle's end >= %.0f%% wide or >= %.0f%% high",
              100 * f.tip_width, 100 * f.tip_level, 100 * drawbar_width, 100 * p.drawbar_level) +
          (waived ? "; its late returns waived on hard echoes)" : ")");
    strength = std::min(past(drawbar_width, std::max(f.tip_width, 1e-6)),
                        past(p.drawbar_level, std::max(f.tip_level, 1e-6)));
  } else if (p.min_notch > 0 && a.group == "car" && f.notch < p.min_notch) {
    why =
        fmt("no bonnet or boot under a cabin: its top's profile lies within %.0f%% of its height of its "
            "upper hull (a car's step >= %.0f%%)",
            100 * f.notch, 100 * p.min_notch);
    strength = past(p.min_notch, std::max(f.notch, 1e-6));
  } else if (p.min_rectangularity > 0 && a.group == "car" && f.rectangularity < p.min_rectangularity &&
             step < p.rectangularity_notch) {
    why =
        fmt("an oval outline: its top view's convex hull fills %.0f%% of its minimum-area rectangle (an "
            "ellipse 79%%; a car's rounded rectangle >= %.0f%%) and no step under its profile's hull (%.0f%% "
            "of its height",
            100 * f.rectangularity, 100 * p.min_rectangularity, 100 * step) +
        (p.rectangularity_sampled ? " over its bins sampled across the width" : "") +
        fmt("; a car's bonnet or boot >= %.0f%%)", 100 * p.rectangularity_notch);
    strength = past(p.min_rectangularity, std::max(f.rectangularity, 1e-6));
  } else if (p.min_shoulder > 0 && (a.group == "car" || a.group == "van") && f.shoulder &&
             *f.shoulder < p.min_shoulder) {
    why = fmt("a body narrowing upward: the outer %.0f%% of its width reaches %.0f%% of its height in the "
              "middle of its length (a stack of logs or pipes, a tent; a ",
              100 * (1 - kShoulderBand), 100 * *f.shoulder) +
          a.group + fmt("'s sides >= %.0f%%)", 100 * p.min_shoulder);
    strength = past(p.min_shoulder, std::max(*f.shoulder, 1e-6));
  } else if (p.max_rim > 0 && (a.group == "car" || a.group == "van") && f.rim && *f.rim > p.max_rim) {
    why = fmt("an open top: in the middle of its length the outer %.0f%% of its width stands %.0f%% of its "
              "height above its centre on both sides (a flatbed's side boards, an open box's walls; a ",
              100 * (1 - kShoulderBand), 100 * *f.rim) +
          a.group + fmt("'s roof is highest across its middle: <= %.0f%%)", 100 * p.max_rim);
    strength = past(*f.rim, p.max_rim);
  } else if (p.max_notch > 0 && (a.group == "tracked" || a.group == "van" || a.group == "bus") &&
             f.notch > p.max_notch) {
    why = fmt("a step %.0f%% of its height deep under its profile's upper hull", 100 * f.notch) + " (a " +
          a.group + fmt("'s <= %.0f%%)", 100 * p.max_notch);
    strength = past(f.notch, p.max_notch);
  }
  if (!why.empty()) unanswer(a, why, strength);
}

// How far the top's profile lies from a modelbase entry's own (classify.md §18): the largest
// absolute difference of the plateau share and the two end levels; 0 for a family's range or an
// unmeasured entry.
// A class's envelope: the least such difference over its entries' profiles (0 when none was measured).
double profile_difference(const TableRange& k, const Features& f) {
  auto from = [&](const std::array<double, 3>& e) {
    return std::max({std::abs(f.plateau_share - e[0]), std::abs(f.end_low - e[1]), std::abs(f.end_high - e[2])});
  };
  if (k.envelope > 0) {
    double d = k.profiles.empty() ? 0 : kInf;
    for (const std::array<double, 3>& e : k.profiles) d = std::min(d, from(e));
    return d;
  }
  return k.profile ? from(*k.profile) : 0;
}

// The bed's sentence (§39): why the car and van groups' classes other than the pickup were left out.
std::string bed_reason(const Features& f, const Params& p) {
  return fmt(
      "an open bed behind a cab: at an end its sides stand %.0f%% of its height or more above its "
      "centre and below its top (a pickup's bed walls; a car's or van's end is as high in its middle "
      "as at its sides: from %.0f%% no car or van but a pickup)",
      100 * *f.bed, 100 * p.min_bed);
}

// Among the classes the size fits, the best: smallest distance, then most central; profile
// cues move the overlapping pairs (docs/decisions/classify.md §4).
void choose(Answer& a, const Params& p, double sigma, const std::vector<TableRange>& table) {
  const Features& f = a.features;
  // A flat box over the whole length (container, log stack, shed): only a box-truck or a bus
  // has such a top; every other family drops to a bonnet, glacis, bucket or chassis.
  const bool box = f.plateau_share >= p.box_plateau && f.end_low >= p.box_ends;
  // An open bed behind a cab (§39): of the car and van groups only a pickup has one.
  const bool bed = p.min_bed > 0 && f.bed && *f.bed >= p.min_bed;
  bool bed_took = false;  // and it left out a class its size fits
  std::vector<Fit> fits;
  // The nearest entry set aside because its own profile is not this top's (--entry-profile).
  std::optional<Fit> aside;
  for (const TableRange& k : table) {
    if (box && !k.flat_box) continue;
    const Fit x = fit(k, f, sigma, p);
    if (bed && (k.group == "car" || k.group == "van") && k.name != "pickup") {
      bed_took = bed_took || x.distance <= p.size_gate;
      continue;
    }
    if (p.entry_profile > 0 && profile_difference(k, f) > p.entry_profile) {
      if (!aside || x.distance < aside->distance) aside = x;
      continue;
    }
    fits.push_back(x);
  }
  auto better = [](const Fit& x, const Fit& y) {
    if (std::abs(x.distance - y.distance) > 1e-9) return x.distance < y.distance;
    return x.centrality < y.centrality;
  };
  std::stable_sort(fits.begin(), fits.end(), better);
  if (fits.empty() || fits.front().distance > p.size_gate) {
    const Fit* best = fits.empty() ? nullptr : &fits.front();
    const std::string nearest =
        best ? "nearest " + label(*best->cls) + fmt(" at %.1f sigma", best->distance) : "no class left";
    std::string why =
        box ? fmt("a flat box: %.0f%% of its length within the top's plateau, both ends at %.0f%% of H or "
                  "more; %.2f x ",
                  100 * f.plateau_share, 100 * f.end_low, f.length) +
                  fmt("%.2f x %.2f m is no box-truck or bus (", f.width, f.height) + nearest + ")"
            : fmt("%.2f x %.2f x %.2f m fits no class's ranges (", f.length, f.width, f.height) + nearest +
                  fmt("; gate %.1f)", p.size_gate);
    if (bed_took) why = bed_reason(f, p) + ": " + why;
    if (aside && aside->distance <= p.size_gate && aside->cls->envelope > 0) {
      why +=
          "; the envelope of the modelbase's " + std::to_string(aside->cls->envelope) + " " + aside->cls->name +
          fmt(" entries fits its size (%.1f sigma) but none of their profiles", aside->distance) +
          fmt(": plateau %.0f%% of the length, ends at %.0f%% and ", 100 * f.plateau_share, 100 * f.end_low) +
          fmt("%.0f%% of H (tolerance %.0f%%)", 100 * f.end_high, 100 * p.entry_profile);
    } else if (aside && aside->distance <= p.size_gate) {
      const std::array<double, 3>& e = *aside->cls->profile;
      why +=
          "; modelbase entry " + aside->cls->entry +
          fmt("'s size fits (%.1f sigma) but not its profile", aside->distance) +
          fmt(": plateau %.0f%% of the length, ends at %.0f%% and ", 100 * f.plateau_share, 100 * f.end_low) +
          fmt("%.0f%% of H against its %.0f%%, ", 100 * f.end_high, 100 * e[0]) +
          fmt("%.0f%% and %.0f%% (", 100 * e[1], 100 * e[2]) + fmt("tolerance %.0f%%)", 100 * p.entry_profile);
    }
    // A flat box is refused on its shape (its top leaves only the box-truck and the bus), as is a
    // bed that left out a class its size fits; any other top on its size alone (no class's ranges
    // hold it).
    refuse(a, "not_vehicle_shape", why, best ? past(best->distance, p.size_gate) : 1.0,
           box || bed_took ? "shape" : "size");
    return;
  }
  const Fit& best = fits.front();
  a.cls = best.cls->name;
  a.group = best.cls->group;
  a.entry = best.cls->entry;
  if (best.cls->envelope > 0) {
    const TableRange& k = *best.cls;
    a.detail = "its size fits the envelope of the modelbase's " + std::to_string(k.envelope) + " " + k.name +
               fmt(" entries (%.2f-%.2f x %.2f-%.2f", k.length[0], k.length[1], k.width[0], k.width[1]) +
               fmt(" x %.2f-%.2f m, +-%.0f%%)", k.height[0], k.height[1], 100 * p.class_envelope) +
               fmt(" at %.1f sigma", best.distance);
  } else if (!a.entry.empty()) {
    const TableRange& k = *best.cls;
    a.detail =
        "its size fits modelbase entry " + k.entry +
        fmt("'s (%.2f x %.2f x %.2f m, +-%.0f%%)", 0.5 * (k.length[0] + k.length[1]),
            0.5 * (k.width[0] + k.width[1]), 0.5 * (k.height[0] + k.height[1]), 100 * p.entry_tolerance) +
        fmt(" at %.1f sigma", best.distance);
  }
  if (bed_took) a.detail = bed_reason(f, p) + (a.detail.empty() ? "" : "; " + a.detail);
  a.class_score = std::exp(-0.5 * best.distance * best.distance);
  double other = kInf;
  for (const Fit& x : fits) {
    if (x.cls->group != a.group) other = std::min(other, x.distance);
  }
  a.class_margin = std::isfinite(other) ? other - best.distance : 0;
  // Confidence: the size fit, how clearly another group is excluded, how far the vegetation
  // cues stay below their thresholds (each 0.5 at its threshold).
  // A hard object's waived cues (classify.md §25) count at most at their threshold.
  const bool hard = hard_echoes(f, p);
  auto cue = [](double value, double threshold, bool waived) {
    return 1 - past(waived ? std::min(value, threshold) : value, threshold);
  };
  double shape =
      (1 - past(f.below_share, p.max_below_share)) * cue(f.ground_through, p.max_ground_through, hard);
  if (f.fill) shape *= 1 - past(p.min_fill, std::max(*f.fill, 1e-6));
  if (f.late_returns) shape *= cue(*f.late_returns, p.max_late_returns, late_waivable(f, p));
  const double group = 0.5 + 0.5 * (1 - std::exp(-0.5 * a.class_margin * a.class_margin));
  a.confidence = std::clamp(a.class_score * group * shape, 0.0, 1.0);
}

}  // namespace

const std::vector<ClassRange>& class_ranges() {
  // Length, width, height (m): tools/rangetrace/families.cpp, docs/decisions/families.md §2. Each
  // family's group is the taxonomy's (common/vehicle_classes.h, which collect reads too).
  static const std::vector<ClassRange> k = [] {
    std::vector<ClassRange> v = {
        {"sedan", {}, {4.40, 5.10}, {1.72, 1.90}, {1.38, 1.50}, 0, -1},
        {"hatchback", {}, {3.55, 4.40}, {1.62, 1.80}, {1.42, 1.56}, 0, +1},
        {"suv", {}, {4.40, 5.30}, {1.80, 2.05}, {1.65, 1.95}, 0, +1},
        {"pickup", {}, {5.00, 5.90}, {1.80, 2.05}, {1.75, 2.00}, -1, -1},
        {"van", {}, {4.90, 6.00}, {1.90, 2.06}, {1.95, 2.75}, +1, +1},
        {"box-truck", {}, {7.00, 10.00}, {2.30, 2.55}, {3.00, 3.90}, +1, 0, true},
        {"semi-tractor", {}, {5.80, 7.50}, {2.45, 2.55}, {3.00, 4.00}, -1, 0},
        {"bus", {}, {10.50, 13.50}, {2.50, 2.55}, {2.90, 3.40}, +1, 0, true},
        {"wheeled-apc", {}, {6.40, 8.00}, {2.50, 3.00}, {2.30, 2.90}, 0, 0},
        {"tracked-apc", {}, {4.90, 7.00}, {2.70, 3.30}, {1.90, 2.70}, 0, 0},
        {"tank", {}, {8.70, 11.40}, {3.40, 3.80}, {2.20, 3.00}, 0, 0, false, {6.50, 8.00}},
        {"wheel-loader", {}, {6.80, 9.00}, {2.50, 3.20}, {3.00, 3.70}, -1, 0},
    };
    for (ClassRange& r : v) r.group = common::family_group(r.name);
    return v;
  }();
  return k;
}

std::vector<TableRange> class_table(const Params& p, const std::vector<ModelEntry>& entries) {
  std::vector<TableRange> table;
  // With --modelbase-classes-only a family is kept when --family-entries entries (or more) name it
  // by its name or its group: with fewer, the class is its entries' own ranges.
  auto named = [&](const ClassRange& family) {
    if (!p.modelbase_classes_only || entries.empty()) return true;
    const auto n = std::count_if(entries.begin(), entries.end(), [&](const ModelEntry& e) {
      return e.cls == family.name || e.cls == family.group;
    });
    return n > 0 && static_cast<std::size_t>(n) >= p.family_entries;
  };
  for (const ClassRange& family : class_ranges()) {
    if (named(family)) table.push_back({family, "", false, std::nullopt, 0, {}});
  }
  if (!p.entry_classes) return table;
  const double t = p.entry_tolerance;
  for (const ModelEntry& e : entries) {
    TableRange k;
    for (const ClassRange& family : class_ranges()) {
      if (family.name == e.cls)
        static_cast<ClassRange&>(k) = family;  // its profile expectations and flat-box flag
    }
    k.name = e.cls;
    k.group = common::class_group(e.cls);  // a family's group, a group's own name, else the class
    k.length = {e.size[0] * (1 - t), e.size[0] * (1 + t)};
    k.width = {e.size[1] * (1 - t), e.size[1] * (1 + t)};
    k.height = {e.size[2] * (1 - t), e.size[2] * (1 + t)};
    k.hull_length = {0, 0};
    k.entry = e.name;
    if (e.profile) {
      const ModelEntry::Profile& f = *e.profile;
      k.profile = std::array<double, 3>{f.plateau_share, f.end_low, f.end_high};
      k.plateau = f.plateau_share >= p.plateau_split ? +1 : -1;
      k.tail = f.end_high >= p.tail_split ? +1 : -1;
      k.flat_box = f.plateau_share >= p.box_plateau && f.end_low >= p.box_ends;
      k.open_end = f.end_fill < p.min_end_fill;
    } else {
      k.open_end = e.cls == "tank";
    }
    table.push_back(std::move(k));
  }
  if (p.class_envelope <= 0) return table;
  // A class's envelope (--class-envelope): its entries' smallest box, widened; the entries' own
  // ranges stay. Classes in their order of first entry.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const TableRange*>> of;
  for (const TableRange& k : table) {
    if (k.entry.empty()) continue;
    if (of[k.name].empty()) order.push_back(k.name);
    of[k.name].push_back(&k);
  }
  std::vector<TableRange> envelopes;
  const double m = p.class_envelope;
  for (const std::string& cls : order) {
    const std::vector<const TableRange*>& ks = of[cls];
    if (ks.size() < 2) continue;
    TableRange k;
    for (const ClassRange& family : class_ranges()) {
      if (family.name == cls) static_cast<ClassRange&>(k) = family;  // its profile expectations
    }
    k.name = cls;
    k.group = ks.front()->group;
    k.hull_length = {0, 0};
    k.envelope = ks.size();
    // The entries' own sizes (the middles of their ranges) and profiles.
    std::array<std::array<double, 2>, 3> box{{{kInf, -kInf}, {kInf, -kInf}, {kInf, -kInf}}};
    // A flat box (a container, a tent, a shed) only when every entry is one: the envelope must not
    // join one entry's flat top to another's size.
    k.flat_box = true;
    for (const TableRange* e : ks) {
      const std::array<double, 3> size{0.5 * (e->length[0] + e->length[1]), 0.5 * (e->width[0] + e->width[1]),
                                       0.5 * (e->height[0] + e->height[1])};
      for (int i = 0; i < 3; ++i) box[i] = {std::min(box[i][0], size[i]), std::max(box[i][1], size[i])};
      if (e->profile) k.profiles.push_back(*e->profile);
      k.flat_box = k.flat_box && e->flat_box;
      k.open_end = k.open_end || e->open_end;
    }
    if (k.profiles.size() < ks.size()) k.profiles.clear();  // an unmeasured entry: no profile to match
    k.length = {box[0][0] * (1 - m), box[0][1] * (1 + m)};
    k.width = {box[1][0] * (1 - m), box[1][1] * (1 + m)};
    k.height = {box[2][0] * (1 - m), box[2][1] * (1 + m)};
    envelopes.push_back(std::move(k));
  }
  table.insert(table.end(), envelopes.begin(), envelopes.end());
  return table;
}

void validate(const Params& p) {
  auto need = [](bool ok, const char* message) {
    if (!ok) throw common::UsageError(message);
  };
  need(p.ground_cut >= 0 && p.ground_cut <= 2, "--ground-cut must be in [0, 2 m]");
  need(p.link_factor > 0 && p.link_factor <= 20, "--link-factor must be in (0, 20]");
  need(p.link_min > 0 && p.link_min <= 1.5, "--link-min must be in (0, 1.5 m]");
  need(p.bridge >= 0 && p.bridge <= 3, "--bridge must be in [0, 3 m]");
  need(p.bridge_length > 0 && p.bridge_length <= 20, "--bridge-length must be in (0, 20 m]");
  need(p.bridge_min_share >= 0 && p.bridge_min_share <= 1, "--bridge-min-share must be in [0, 1]");
  need(p.min_points >= 3, "--min-points must be at least 3");
  need(p.min_density >= 0 && std::isfinite(p.min_density), "--min-density must be >= 0");
  need(p.edge_factor >= 0 && p.edge_factor <= 5, "--edge-factor must be in [0, 5]");
  need(p.height_quantile > 0 && p.height_quantile <= 1, "--height-quantile must be in (0, 1]");
  need(p.size_sigma > 0 && p.size_sigma <= 5, "--size-sigma must be in (0, 5 m]");
  need(p.spacing_sigma >= 0 && p.spacing_sigma <= 10, "--spacing-sigma must be in [0, 10]");
  need(p.size_gate > 0 && p.size_gate <= 100, "--size-gate must be in (0, 100]");
  need(p.plateau_drop >= 0 && p.plateau_drop <= 5, "--plateau-drop must be in [0, 5 m]");
  need(p.max_roughness > 0 && p.max_roughness <= 100, "--max-roughness must be in (0, 100]");
  need(p.roughness_floor >= 0 && p.roughness_floor <= 1, "--roughness-floor must be in [0, 1 m]");
  need(p.max_roughness_line >= 0 && p.max_roughness_line <= 100,
       "--max-roughness-line must be 0 (off) or in (0, 100]");
  need(p.max_below_share > 0 && p.max_below_share <= 1, "--max-below-share must be in (0, 1]");
  need(p.max_ground_through > 0 && p.max_ground_through <= 1, "--max-ground-through must be in (0, 1]");
  need(p.min_fill >= 0 && p.min_fill <= 10, "--min-fill must be in [0, 10]");
  need(p.max_late_returns > 0 && p.max_late_returns <= 1, "--max-late-returns must be in (0, 1]");
  need(p.max_echo_widening == 0 || (p.max_echo_widening >= 1 && p.max_echo_widening <= 10),
       "--max-echo-widening must be 0 (off) or in [1, 10]");
  need(p.min_plateau >= 0 && p.min_plateau <= 1, "--min-plateau must be in [0, 1]");
  need(p.plateau_split > 0 && p.plateau_split < 1, "--plateau-split must be in (0, 1)");
  need(p.tail_split > 0 && p.tail_split < 1.5, "--tail-split must be in (0, 1.5)");
  need(p.profile_penalty >= 0 && p.profile_penalty <= 100, "--profile-penalty must be in [0, 100]");
  need(p.box_plateau > 0 && p.box_plateau <= 1, "--box-plateau must be in (0, 1]");
  need(p.box_ends > 0 && p.box_ends <= 1, "--box-ends must be in (0, 1]");
  need(p.model_density > 0 && std::isfinite(p.model_density), "--model-density must be > 0");
  need(p.entry_tolerance >= 0 && p.entry_tolerance <= 0.5, "--entry-tolerance must be in [0, 0.5]");
  need(p.entry_profile >= 0 && p.entry_profile <= 1, "--entry-profile must be in [0, 1]");
  need(p.class_envelope >= 0 && p.class_envelope <= 1, "--class-envelope must be in [0, 1]");
  need(p.family_entries >= 1 && p.family_entries <= 100, "--family-entries must be in [1, 100]");
  need(p.pass_share > 0 && p.pass_share <= 0.5, "--pass-share must be in (0, 0.5]");
  need(p.min_end_fill >= 0 && p.min_end_fill <= 1, "--min-end-fill must be in [0, 1]");
  need(p.min_notch >= 0 && p.min_notch <= 1, "--min-notch must be in [0, 1]");
  need(p.max_notch >= 0 && p.max_notch <= 1, "--max-notch must be in [0, 1]");
  need(p.drawbar_width >= 0 && p.drawbar_width <= 1, "--drawbar-width must be in [0, 1]");
  need(p.echo_late_drawbar >= 0 && p.echo_late_drawbar <= 1, "--echo-late-drawbar must be in [0, 1]");
  need(p.echo_late_widening >= 0, "--echo-late-widening must be >= 0");
  need(p.drawbar_level >= 0 && p.drawbar_level <= 1, "--drawbar-level must be in [0, 1]");
  need(p.min_rectangularity >= 0 && p.min_rectangularity <= 1, "--min-rectangularity must be in [0, 1]");
  need(p.min_shoulder >= 0 && p.min_shoulder <= 1, "--min-shoulder must be in [0, 1]");
  need(p.max_rim >= 0 && p.max_rim <= 1, "--max-rim must be in [0, 1]");
  need(p.min_bed >= 0 && p.min_bed <= 1, "--min-bed must be in [0, 1]");
  need(p.rectangularity_notch >= 0 && p.rectangularity_notch <= 1,
       "--rectangularity-notch must be in [0, 1]");
}

Outputs run(const Params& p, const Inputs& in) {
  Answer a;
  Candidate c = read_candidate(in.cloud, in.name);
  c.tile_ground_density = in.tile_ground_density;
  c.tile_ground_from_first = in.tile_ground_from_first;
  a.features = measure(c, p);
  a.measured = a.features.object_points >= 3;
  if (sparse(a, p)) return a;
  const double s = a.features.spacing;
  const double sigma = std::sqrt(p.size_sigma * p.size_sigma + p.spacing_sigma * p.spacing_sigma * s * s);
  const std::vector<TableRange> table = class_table(p, in.modelbase);
  if (vegetation(a, p) || size_gates(a, p, sigma, table) || roofless(a, p)) return a;
  choose(a, p, sigma, table);
  open_end(a, p, table);
  outline(a, p);
  return a;
}

const ModelEntry* nearest(const Answer& a, const std::vector<ModelEntry>& entries) {
  const ModelEntry* best = nullptr;
  double d_best = kInf;
  if (a.cls.empty()) return nullptr;
  const std::array<double, 3> m{a.features.length, a.features.width, a.features.height};
  for (const ModelEntry& e : entries) {
    if (e.cls != a.cls) continue;
    double d = 0;
    for (int i = 0; i < 3; ++i) d += (e.size[i] - m[i]) * (e.size[i] - m[i]);
    if (d < d_best) {
      d_best = d;
      best = &e;
    }
  }
  return best;
}

}  // namespace canopy::classify
