#include "detect/output.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/provenance.h"
#include "canopy/formats/ply.h"

namespace canopy::detect {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

double finite(double v) {
  if (!std::isfinite(v)) throw common::Error("detect: refusing to write a non-finite number");
  return v;
}

// Removes a temporary directory unless released.
class TempDir {
 public:
  explicit TempDir(fs::path p) : path_(std::move(p)) {}
  ~TempDir() {
    if (!path_.empty()) {
      std::error_code ec;
      fs::remove_all(path_, ec);
    }
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  void release() { path_.clear(); }

 private:
  fs::path path_;
};

}  // namespace

std::string serialize_index(const Result& r, const Params& p, const formats::Provenance& prov,
                            const std::string& tile, const std::string& classes) {
  Json j{{"format", "canopy.candidates"},
         {"version", 1},
         {"provenance", formats::provenance_json(prov)},
         {"tile", tile},
         {"tile_points", r.stats.points},
         {"origin", Json::array({finite(r.origin.x()), finite(r.origin.y()), finite(r.origin.z())})},
         {"classes", classes.empty() ? Json(nullptr) : Json(classes)},
         {"ground", Json{{"cell", p.cell},
                         {"cells", r.stats.cells},
                         {"ground_cells", r.stats.ground_cells},
                         {"filled_cells", r.stats.filled_cells},
                         {"ground_points", r.stats.ground_points}}}};
  Json cands = Json::array();
  for (const Candidate& c : r.candidates) {
    Json t = Json::array();
    for (int row = 0; row < 4; ++row) {
      t.push_back(Json::array({finite(c.to_tile(row, 0)), finite(c.to_tile(row, 1)),
                               finite(c.to_tile(row, 2)), finite(c.to_tile(row, 3))}));
    }
    Json cj{{"id", c.id},
            {"file", c.id + ".pcd"},
            {"transform", t},
            {"centre", Json::array({c.to_tile(0, 3), c.to_tile(1, 3), c.to_tile(2, 3)})},
            {"length", finite(c.length)},
            {"width", finite(c.width)},
            {"heading", finite(c.heading)},
            {"height", finite(c.height)},
            {"point_count", c.cloud.size()},
            {"object_points", c.object_points},
            {"planarity", finite(c.planarity)},
            {"planar_area", finite(c.planar_area)}};
    if (c.has_truth) {
      cj["truth"] = c.truth.instance == 0 ? Json(nullptr)
                                          : Json{{"instance", c.truth.instance},
                                                 {"points", c.truth.points},
                                                 {"coverage", finite(c.truth.coverage)},
                                                 {"purity", finite(c.truth.purity)}};
    }
    cands.push_back(std::move(cj));
  }
  j["candidates"] = std::move(cands);
  if (r.has_truth) {
    Json inst = Json::array();
    for (const auto& it : r.instances) {
      inst.push_back(Json{{"instance", it.instance}, {"points", it.points}, {"candidates", it.candidates}});
    }
    j["instances"] = std::move(inst);
  }
  return j.dump(1) + "\n";
}

void write_output(const std::string& dir, const formats::PointCloud& tile, const Result& result,
                  const Params& params, const formats::Provenance& provenance, const std::string& tile_name,
                  bool write_classes) {
  fs::path final = fs::path(dir).lexically_normal();
  if (final.has_filename() == false) final = final.parent_path();  // "cands/" -> "cands"
  if (final.empty() || final == "." || final == "..")
    throw common::UsageError("-o must name a directory to create");
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(final, ec);
  const bool exists = fs::exists(st);
  if (exists && !fs::is_directory(st)) {
    throw common::DataError(final.string(), "exists and is not a directory; refusing to overwrite it");
  }
  if (exists && !fs::is_empty(final, ec) && !fs::exists(final / "index.json")) {
    throw common::DataError(final.string(),
                            "is a directory that is neither empty nor a detect output "
                            "(no index.json); refusing to replace it");
  }
  fs::path parent = final.parent_path();
  if (parent.empty()) parent = ".";
  fs::create_directories(parent, ec);
  if (!fs::is_directory(parent))
    throw common::DataError(parent.string(), "cannot create the output's parent directory");
  const std::string stem = final.filename().string();
  TempDir tmp(parent / ("." + stem + ".tmp" + std::to_string(::getpid())));
  fs::remove_all(tmp.path(), ec);
  if (!fs::create_directory(tmp.path(), ec)) {
    throw common::DataError(tmp.path().string(), "cannot create a temporary directory: " + ec.message());
  }
  // Every file's comments: the tile's own (a candidate's crop keeps them), detect's
  // provenance, then what the file holds.
  const std::vector<std::string> prov = formats::provenance_comments(provenance);
  for (const Candidate& c : result.candidates) {
    formats::PointCloud cloud = c.cloud;
    cloud.comments.insert(cloud.comments.end(), prov.begin(), prov.end());
    cloud.comments.push_back("candidate " + c.id +
                             " in its local frame; index.json gives the transform back to the tile");
    formats::write_pcd(cloud, (tmp.path() / (c.id + ".pcd")).string());
  }
  std::string classes;
  if (write_classes) {
    classes = "classes.ply";
    formats::Mesh m;
    m.vertices = classification_cloud(tile, result);
    char origin[160];
    std::snprintf(origin, sizeof origin, "origin %.17g %.17g %.17g (add to x y z for tile coordinates)",
                  result.origin.x(), result.origin.y(), result.origin.z());
    m.vertices.comments = prov;
    m.vertices.comments.push_back("classes 1 ground (brown), 2 vegetation/other (green), 3 candidate (red)");
    m.vertices.comments.push_back(origin);
    formats::write_ply(m, (tmp.path() / classes).string());
  }
  common::write_file_atomic((tmp.path() / "index.json").string(),
                            serialize_index(result, params, provenance, tile_name, classes));
  if (exists) {
    const fs::path old = parent / ("." + stem + ".old" + std::to_string(::getpid()));
    fs::remove_all(old, ec);
    fs::rename(final, old, ec);
    if (ec) throw common::DataError(final.string(), "cannot move the previous output aside: " + ec.message());
    fs::rename(tmp.path(), final, ec);
    if (ec) {
      std::error_code ec2;
      fs::rename(old, final, ec2);
      throw common::DataError(final.string(), "cannot rename the new output into place: " + ec.message());
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(tmp.path(), final, ec);
    if (ec)
      throw common::DataError(final.string(), "cannot rename the new output into place: " + ec.message());
  }
  tmp.release();
}

}  // namespace canopy::detect
