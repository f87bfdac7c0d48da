// areas: the target's surface area at each stage of one trial, as areas.json (issue 19).
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/pcd.h"
#include "areas/areas.h"

using namespace canopy;

namespace {

std::vector<areas::ScanPoint> scan_targets(const formats::PointCloud& c, const std::string& name) {
  c.require({"x", "y", "z", "sensor_x", "sensor_y", "sensor_z", "view_idx", "label"}, name,
            "a labelled rangetrace scan is needed");
  std::vector<areas::ScanPoint> out;
  const auto& l = c.col("label");
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (l[i] != formats::kLabelTarget) continue;
    areas::ScanPoint p;
    p.p = Eigen::Vector3d(c.col("x")[i], c.col("y")[i], c.col("z")[i]);
    p.toward = Eigen::Vector3d(c.col("sensor_x")[i], c.col("sensor_y")[i], c.col("sensor_z")[i]);
    p.view = static_cast<int>(c.col("view_idx")[i]);
    out.push_back(p);
  }
  return out;
}

std::vector<Eigen::Vector3d> target_points(const formats::PointCloud& c, const std::string& name,
                                           const char* fx, const char* fy, const char* fz) {
  c.require({fx, fy, fz, "label"}, name, "a labelled cloud is needed");
  std::vector<Eigen::Vector3d> out;
  const auto& l = c.col("label");
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (l[i] == formats::kLabelTarget) out.emplace_back(c.col(fx)[i], c.col(fy)[i], c.col(fz)[i]);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  common::Tool tool("areas", "Target surface area at each stage of a trial: visible (labelled scan), "
                             "fitvox samples, cocone mesh, ncut segments, gmatch's largest segments.");
  std::string scan, samples, mesh, segments, out = "-";
  areas::Areas a;
  a.spacing = 0.03;
  a.cell = 0.045;
  a.voxel = 0.128;
  a.max_segments = 15;
  tool.add("--scan", &scan, "labelled noise-free scan PCD (the visible surface)")->required();
  tool.add("--samples", &samples, "fitvox samples PCD")->required();
  tool.add("--mesh", &mesh, "cocone mesh PLY")->required();
  tool.add("--segments", &segments, "ncut segment graph JSON")->required();
  tool.add_output(&out, "areas JSON");
  tool.add_length("--spacing", &a.spacing, "the scan's pixel spacing (rangetrace --spacing)");
  tool.add_length("--cell", &a.cell, "lattice cell of the visible-area estimate (normals, view overlap)");
  tool.add_length("--voxel", &a.voxel, "fitvox's voxel edge (each sample stands for its voxel)");
  tool.add("--max-segments", &a.max_segments, "gmatch's X: largest segments matched");
  return tool.run(argc, argv, [&] {
    if (!(a.spacing > 0) || !(a.cell > 0) || !(a.voxel > 0) || a.max_segments < 1) {
      throw common::UsageError("need --spacing > 0, --cell > 0, --voxel > 0, --max-segments >= 1");
    }
    common::log::Phase phase("areas");
    const auto pts = scan_targets(formats::read_pcd(scan), common::display_name(scan));
    a.target_points = pts.size();
    a.visible = areas::visible_area(pts, a.spacing, a.cell);
    const auto normals = target_points(formats::read_pcd(samples), common::display_name(samples),
                                       "normal_x", "normal_y", "normal_z");
    a.target_samples = normals.size();
    a.samples = areas::samples_area(normals, a.voxel);
    const formats::Mesh m = formats::read_ply(mesh);
    m.vertices.require({"x", "y", "z", "label"}, common::display_name(mesh), "a labelled cocone mesh is needed");
    a.mesh = areas::mesh_area(m, formats::kLabelTarget);
    const formats::SegmentGraph g = formats::read_segment_graph(segments);
    a.segments = areas::segments_area(g, formats::kLabelTarget, 0);
    a.matched = areas::segments_area(g, formats::kLabelTarget, a.max_segments);
    common::write_file_atomic(out, areas::serialize(a, {scan, samples, mesh, segments}));
    char buf[200];
    std::snprintf(buf, sizeof buf, "visible %.2f, samples %.2f, mesh %.2f, segments %.2f, largest %d %.2f m2",
                  a.visible, a.samples, a.mesh, a.segments, a.max_segments, a.matched);
    phase.done(buf);
  });
}
