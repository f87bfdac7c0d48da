// addnoise: scan PCD -> scan PCD with isotropic Gaussian noise on x, y, z.
#include <string>

#include "addnoise/addnoise.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/provenance.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("addnoise",
                    "Isotropic Gaussian noise on the coordinates of a scan; every "
                    "other field is kept (thesis ch. 2).",
                    true);
  tool.without_threads();
  addnoise::Params p;
  std::string in = "-", out = "-";
  tool.add_input(&in, "scan: PCD, PLY point set or LAS (x y z and any other fields)");
  tool.add_output(&out, "noisy scan: .pcd, .ply or .las (- = PCD)");
  tool.add_length("--sigma", &p.sigma, "standard deviation per axis (0 = exact copy)", 1.0);
  std::string pcd_encoding = "binary";
  tool.add("--pcd-encoding", &pcd_encoding,
           "DATA of a PCD output: binary, binary_compressed (PCL tools' default) or ascii");
  return tool.run(argc, argv, [&] {
    formats::output_format(out);
    const formats::PcdWriteOptions pcd = formats::parse_pcd_encoding(pcd_encoding);
    p.seed = tool.seed();
    addnoise::validate(p);
    common::log::Phase read("read");
    formats::PointCloud noisy = formats::read_points(in, "addnoise");
    noisy.require({"x", "y", "z"}, common::display_name(in), "is this a point cloud?");
    read.done(std::to_string(noisy.size()) + " points");
    addnoise::apply(p, &noisy);
    const std::vector<std::string> provenance =
        formats::provenance_comments({"addnoise", CANOPY_VERSION, tool.parameters(), {in}});
    noisy.comments.insert(noisy.comments.end(), provenance.begin(), provenance.end());
    formats::write_points(noisy, out, pcd);
    common::log::info("wrote " + std::to_string(noisy.size()) + " points, sigma " +
                      common::format_length(p.sigma) + ", to " + common::display_name(out, true));
  });
}
