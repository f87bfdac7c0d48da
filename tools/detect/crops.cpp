#include "detect/crops.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "canopy/common/error.h"
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

namespace {

// classes.ply's columns (classification_cloud's) and their bytes a row.
constexpr std::size_t kClassesRow = 4 * 4 + 4 * 1;
const unsigned char kClassColour[4][3] = {{128, 128, 128}, {150, 110, 60}, {40, 160, 40}, {230, 30, 30}};

}  // namespace

void classes_ply(const formats::PointCloud& tile, const Result& result,
                 const std::vector<std::string>& provenance,
                 const std::function<void(const char*, std::size_t)>& sink) {
  // The header: serialize_ply's text for the columns without a point, then the count.
  formats::Mesh m;
  for (const char* c : {"x", "y", "z", "height"}) m.vertices.add_packed<float>(c, formats::kFloat32);
  for (const char* c : {"class", "red", "green", "blue"})
    m.vertices.add_packed<std::uint8_t>(c, formats::kUint8);
  char origin[160];
  std::snprintf(origin, sizeof origin, "origin %.17g %.17g %.17g (add to x y z for tile coordinates)",
                result.origin.x(), result.origin.y(), result.origin.z());
  m.vertices.comments = provenance;
  m.vertices.comments.push_back("classes 1 ground (brown), 2 vegetation/other (green), 3 candidate (red)");
  m.vertices.comments.push_back(origin);
  std::string header = formats::serialize_ply(m);
  const std::string none = "\nelement vertex 0\n";
  const std::size_t at = header.find(none);
  if (at == std::string::npos) throw common::Error("detect: classes.ply header without its vertex count");
  const std::size_t n = tile.size();
  header.replace(at, none.size(), "\nelement vertex " + std::to_string(n) + "\n");
  sink(header.data(), header.size());
  // The rows, as serialize_ply writes classification_cloud's: float32 x y z height (a float
  // of the double, to_field), uint8 class red green blue, little-endian.
  const auto& tx = tile.col("x");
  const auto& ty = tile.col("y");
  const auto& tz = tile.col("z");
  constexpr std::size_t kBlock = 1 << 16;
  std::vector<char> buf(kClassesRow * std::min(kBlock, std::max<std::size_t>(n, 1)));
  for (std::size_t first = 0; first < n; first += kBlock) {
    const std::size_t k = std::min(kBlock, n - first);
    char* o = buf.data();
    for (std::size_t i = first; i < first + k; ++i, o += kClassesRow) {
      const float f[4] = {static_cast<float>(tx[i] - result.origin.x()),
                          static_cast<float>(ty[i] - result.origin.y()),
                          static_cast<float>(tz[i] - result.origin.z()), result.height[i]};
      std::memcpy(o, f, sizeof f);  // little-endian hosts only, as formats' writers
      const auto* col = kClassColour[std::min<int>(result.classes[i], 3)];
      const unsigned char b[4] = {result.classes[i], col[0], col[1], col[2]};
      std::memcpy(o + sizeof f, b, sizeof b);
    }
    sink(buf.data(), k * kClassesRow);
  }
}

std::string classes_ply(const formats::PointCloud& tile, const Result& result,
                        const std::vector<std::string>& provenance) {
  std::string out;
  classes_ply(tile, result, provenance, [&out](const char* p, std::size_t n) { out.append(p, n); });
  return out;
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
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<float>(tx[i] - result.origin.x());
    y[i] = static_cast<float>(ty[i] - result.origin.y());
    z[i] = static_cast<float>(tz[i] - result.origin.z());
    h[i] = static_cast<float>(result.height[i]);
    cls[i] = result.classes[i];
    const auto* col = kClassColour[std::min<int>(result.classes[i], 3)];
    red[i] = col[0];
    green[i] = col[1];
    blue[i] = col[2];
  }
  out.resize(n);  // sets the size; the columns are full
  return out;
}

}  // namespace canopy::detect
