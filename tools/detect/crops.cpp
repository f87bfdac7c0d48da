#include "detect/crops.h"

#include <algorithm>
#include <cstdio>

#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"

namespace canopy::detect {

std::string candidate_pcd(const Candidate& c, const std::vector<std::string>& provenance,
                          const std::string& path) {
  formats::PointCloud cloud = c.cloud;
  cloud.comments.insert(cloud.comments.end(), provenance.begin(), provenance.end());
  cloud.comments.push_back("candidate " + c.id +
                           " in its local frame; index.json gives the transform back to the tile");
  formats::check_coordinates(cloud, path);
  return formats::serialize_pcd(cloud);
}

std::string classes_ply(const formats::PointCloud& tile, const Result& result,
                        const std::vector<std::string>& provenance) {
  formats::Mesh m;
  m.vertices = classification_cloud(tile, result);
  char origin[160];
  std::snprintf(origin, sizeof origin, "origin %.17g %.17g %.17g (add to x y z for tile coordinates)",
                result.origin.x(), result.origin.y(), result.origin.z());
  m.vertices.comments = provenance;
  m.vertices.comments.push_back("classes 1 ground (brown), 2 vegetation/other (green), 3 candidate (red)");
  m.vertices.comments.push_back(origin);
  return formats::serialize_ply(m);
}

formats::PointCloud classification_cloud(const formats::PointCloud& tile, const Result& result) {
  // The columns packed at their width in the file (float32, uint8: 20 bytes a point, not 8
  // doubles' 64); the PLY writer takes the values as they are (cost.md §17).
  formats::PointCloud out;
  const std::size_t n = tile.size();
  auto& x = out.add_packed<float>("x", formats::kFloat32);
  auto& y = out.add_packed<float>("y", formats::kFloat32);
  auto& z = out.add_packed<float>("z", formats::kFloat32);
  auto& h = out.add_packed<float>("height", formats::kFloat32);
  auto& cls = out.add_packed<std::uint8_t>("class", formats::kUint8);
  auto& red = out.add_packed<std::uint8_t>("red", formats::kUint8);
  auto& green = out.add_packed<std::uint8_t>("green", formats::kUint8);
  auto& blue = out.add_packed<std::uint8_t>("blue", formats::kUint8);
  for (auto* v : {&x, &y, &z, &h}) v->resize(n);
  for (auto* v : {&cls, &red, &green, &blue}) v->resize(n);
  const auto& tx = tile.col("x");
  const auto& ty = tile.col("y");
  const auto& tz = tile.col("z");
  static const unsigned char kColour[4][3] = {{128, 128, 128}, {150, 110, 60}, {40, 160, 40}, {230, 30, 30}};
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<float>(tx[i] - result.origin.x());
    y[i] = static_cast<float>(ty[i] - result.origin.y());
    z[i] = static_cast<float>(tz[i] - result.origin.z());
    h[i] = static_cast<float>(result.height[i]);
    cls[i] = result.classes[i];
    const auto* col = kColour[std::min<int>(result.classes[i], 3)];
    red[i] = col[0];
    green[i] = col[1];
    blue[i] = col[2];
  }
  out.resize(n);  // sets the size; the columns are full
  return out;
}

}  // namespace canopy::detect
