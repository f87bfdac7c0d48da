// fitvox: scan PCD -> samples PCD (one PCA frame + biquadratic fit per accepted voxel).
#include <cstdio>
#include <string>
#include <vector>

#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/provenance.h"
#include "fitvox/fitvox.h"

using namespace canopy;

namespace {

// The fit phase's INFO line: voxel verdicts, noise level and bounds. The RMS bound is given as
// its least and greatest value over the voxels' point counts (min-points to the most populated
// voxel's), in that order: it is not monotone in the count (fitvox.h Stats::rms_bound_least), and
// until stop 67 the line gave the bound at the most and at the fewest points, which read as a
// reversed range with --min-points 6 ("43.54-8.00 mm"; docs/decisions/hardening.md).
std::string summary(const fitvox::Params& p, const fitvox::Stats& s) {
  char bound[200];
  if (s.rms_bound_greatest - s.rms_bound_least < 0.005e-3) {
    std::snprintf(bound, sizeof bound, "RMS bound %.2f mm", s.rms_bound_greatest * 1e3);
  } else {
    std::snprintf(bound, sizeof bound, "RMS bound %.2f-%.2f mm over voxels of %d-%zu points%s",
                  s.rms_bound_least * 1e3, s.rms_bound_greatest * 1e3, p.min_points, s.max_points,
                  p.min_points == 6 ? " (--max-rms at 6 points: a biquadratic fits 6 points exactly)" : "");
  }
  char buf[400];
  std::snprintf(buf, sizeof buf, "sigma %s %.2f mm, %s, resampling support %.1f mm",
                p.noise < 0 ? "estimated" : "given", s.sigma * 1e3, bound, s.support * 1e3);
  return "kept " + std::to_string(s.kept) + " of " + std::to_string(s.voxels) + " voxels (too few points " +
         std::to_string(s.too_few) + ", undetermined " + std::to_string(s.degenerate) + ", too rough " +
         std::to_string(s.too_rough) + ", plane fallback " + std::to_string(s.plane_fallback) + ", merged " +
         std::to_string(s.merged) + "); " + buf;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("fitvox",
                    "Local surface fits: PCA frame + least-squares biquadratic in "
                    "cubic voxels (thesis ch. 3); one sample point per kept voxel.");
  fitvox::Params p;
  std::string in = "-", out = "-", noise = "auto", support = "auto";
  tool.add_input(&in, "scan: PCD, PLY point set or LAS (x y z [sensor_x sensor_y sensor_z] [label])");
  tool.add_output(&out, "samples: .pcd, .ply or .las (- = PCD)");
  tool.add_length("--voxel", &p.voxel, "voxel edge; voxel centres at multiples of it from the world origin",
                  1.0);
  tool.add("--min-points", &p.min_points, "reject voxels with fewer points (>= 6)");
  std::string pcd_encoding = "binary";
  tool.add("--pcd-encoding", &pcd_encoding,
           "DATA of a PCD output: binary, binary_compressed (PCL tools' default) or ascii");
  tool.add_length("--max-rms", &p.max_rms, "RMS fit-error bound for noiseless data");
  tool.add("--noise", &noise,
           "noise sigma that widens the RMS bound: 'auto' = estimate from "
           "the scan's fits, a length = known sigma, 0 = fixed --max-rms");
  tool.add("--noise-margin", &p.noise_margin,
           "standard deviations of the RMS sampling spread allowed above the noise (>= 0)");
  tool.add("--resample", &p.resample,
           "project each sample onto a surface fitted to the scan within --support and merge "
           "near-duplicates (false = the thesis: the raw input point nearest the voxel centre, voxel fit)");
  tool.add("--from-centroid", &p.from_centroid,
           "resampling starts from the voxel's point centroid (false: "
           "from its point nearest the voxel centre)");
  tool.add("--support", &support,
           "resampling fit radius in voxel edges (> 0), or 'auto' = 6 x the noise "
           "sigma, clamped to 0.5-1 voxel edges");
  tool.add("--merge", &p.merge, "resampled samples closer than this many voxel edges merge (>= 0; 0 = off)");
  return tool.run(argc, argv, [&] {
    formats::output_format(out);
    const formats::PcdWriteOptions pcd = formats::parse_pcd_encoding(pcd_encoding);
    // Decimal only (std::stod read "0x1p0" as 1 and "1e-400" as 0).
    if (support != "auto") p.support = common::parse_decimal(support, "--support ('auto' or a number)");
    // The bound: auto is 0.5-1 voxel edges and the cost grows with its square (docs/decisions/hardening.md).
    if (support != "auto" && !(p.support > 0 && p.support <= fitvox::kMaxSupport)) {
      throw common::UsageError("--support must be 'auto' or in " + fitvox::support_range() +
                               " voxel edges (given " + support + ")");
    }
    if (noise != "auto") {
      // The same warnings as addnoise --sigma (the same quantity).
      p.noise = tool.length_value("--noise", noise, 0, 1.0);
      if (!(p.noise >= 0 && p.noise <= 100)) {
        throw common::UsageError("--noise must be 'auto' or in [0, 100m] (given " + noise + ")");
      }
    }
    p.threads = tool.threads();
    fitvox::validate(p);
    common::log::Phase read("read");
    const formats::PointCloud cloud = formats::read_points(in, "fitvox");
    bool has_sensor = false;
    const fitvox::Scan scan = fitvox::scan_from_cloud(cloud, common::display_name(in), &has_sensor);
    read.done(std::to_string(scan.points.size()) + " points");
    if (!has_sensor) {
      common::log::warn(common::display_name(in) + ": no sensor_x/y/z fields: normals oriented toward +z");
    }
    common::log::Phase fit("fit");
    const fitvox::Result r = common::naming_input(in, [&] { return fitvox::run(p, scan); });
    const fitvox::Stats& s = r.stats;
    fit.done(summary(p, s));
    if (r.samples.empty()) {
      throw common::DataError(common::display_name(in),
                              "no voxel passed the tests (check --voxel, --min-points, --max-rms)");
    }
    formats::PointCloud samples = fitvox::samples_to_cloud(r);
    // What a real (LAS) tile tells about the sensor, carried from each sample's input point so
    // that verify can derive the direction toward the sensor (issue 26; the simulator's scans
    // have none of these columns, so their samples are unchanged).
    for (const char* name : {"gps_time", "scan_angle", "point_source_id"}) {
      if (!cloud.has(name)) continue;
      const std::vector<double>& from = cloud.col(name);
      std::vector<double>& to = samples.add(name, cloud.type(name));
      for (std::size_t i = 0; i < r.samples.size(); ++i) to[i] = from[r.samples[i].source_index];
    }
    samples.comments = formats::provenance_comments({"fitvox", CANOPY_VERSION, tool.parameters(), {in}});
    char buf[160];
    std::snprintf(buf, sizeof buf, "noise_sigma_used %.6g m (estimated %.6g m)", s.sigma, s.sigma_estimated);
    samples.comments.push_back(buf);
    formats::write_points(samples, out, pcd);
    common::log::info("wrote " + std::to_string(r.samples.size()) + " samples to " +
                      common::display_name(out, true));
  });
}
