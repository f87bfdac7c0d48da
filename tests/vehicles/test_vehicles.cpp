// share/vehicles/: the third-party vehicle library (docs/decisions/vehicle-library.md). Every
// mesh of catalogue.csv loads through canopy's own mesh reader (formats/mesh_import.h), has the
// catalogue's dimensions (1 cm), sits in the modelbase frame (bottom z = 0, bounding box centred
// in x and y, length along x), has dimensions plausible for its class (classes.csv), a licence
// entry from the accepted list and a reproducible transform (transforms.csv); split.csv covers
// the catalogue with disjoint modelbase and test instances; the library stays under 25 MB.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/formats/mesh_import.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

const std::string kDir = std::string(CANOPY_SOURCE_DIR) + "/share/vehicles";

using Row = std::map<std::string, std::string>;

// The library's CSV files: a header, then rows of as many cells (no quoting, no comma in a cell).
std::vector<Row> read_csv(const std::string& name) {
  std::istringstream in(common::read_file(kDir + "/" + name));
  std::string line;
  std::vector<std::string> header;
  std::vector<Row> rows;
  auto cells = [](const std::string& l) {
    std::vector<std::string> out;
    std::string cell;
    std::istringstream s(l);
    while (std::getline(s, cell, ',')) out.push_back(cell);
    if (!l.empty() && l.back() == ',') out.push_back("");
    return out;
  };
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (header.empty()) {
      header = cells(line);
      continue;
    }
    const std::vector<std::string> c = cells(line);
    INFO(name << ": " << line);
    REQUIRE(c.size() == header.size());
    Row r;
    for (std::size_t i = 0; i < c.size(); ++i) r[header[i]] = c[i];
    rows.push_back(r);
  }
  return rows;
}

struct Box {
  Eigen::Vector3d lo, hi;
};

Box bounds(const formats::TriangleMesh& m) {
  Box b{Eigen::Vector3d::Constant(INFINITY), Eigen::Vector3d::Constant(-INFINITY)};
  for (const int i : std::set<int>([&] {
         std::set<int> used;
         for (const auto& f : m.faces) used.insert(f.begin(), f.end());
         return used;
       }())) {
    b.lo = b.lo.cwiseMin(m.vertices[i]);
    b.hi = b.hi.cwiseMax(m.vertices[i]);
  }
  return b;
}

// The layout scripts/vehicles/convert.py writes: binary little-endian PLY, float x y z, faces
// as uchar-counted int lists.
std::string binary_ply(const std::vector<Eigen::Vector3f>& v, const std::vector<std::array<int, 3>>& f) {
  std::string s = "ply\nformat binary_little_endian 1.0\ncomment t\nelement vertex " +
                  std::to_string(v.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  std::to_string(f.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : v) s.append(reinterpret_cast<const char*>(p.data()), 12);
  for (const auto& t : f) {
    s.push_back('\3');
    s.append(reinterpret_cast<const char*>(t.data()), 12);
  }
  return s;
}

}  // namespace

TEST_CASE("the library's PLY layout reads back through the mesh reader with its known box") {
  // A 4 x 2 x 1.5 m box, bottom at z = 0, centred in x and y: 8 corners, 12 triangles.
  std::vector<Eigen::Vector3f> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? 2.f : -2.f, i & 2 ? 1.f : -1.f, i & 4 ? 1.5f : 0.f);
  const std::vector<std::array<int, 3>> f = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                             {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                             {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  const formats::TriangleMesh m = formats::parse_triangle_mesh(binary_ply(v, f), "box.ply", "ply");
  REQUIRE(m.faces.size() == 12);
  const Box b = bounds(m);
  CHECK((b.hi - b.lo).isApprox(Eigen::Vector3d(4, 2, 1.5)));
  CHECK(b.lo.z() == 0);
  // A truncated file is refused, naming the file.
  CHECK_THROWS_WITH(formats::parse_triangle_mesh(binary_ply(v, f).substr(0, 300), "cut.ply", "ply"),
                    Catch::Contains("cut.ply"));
}

TEST_CASE("every catalogued vehicle loads, in the modelbase frame, with its catalogue dimensions") {
  const std::vector<Row> cat = read_csv("catalogue.csv");
  REQUIRE(cat.size() >= 8);
  std::map<std::string, Row> ranges;
  for (const Row& r : read_csv("classes.csv")) ranges[r.at("class")] = r;
  std::map<std::string, Row> transforms;
  for (const Row& r : read_csv("transforms.csv")) transforms[r.at("name")] = r;
  const std::set<std::string> licences = {"CC0-1.0",      "CC-BY-3.0",    "CC-BY-4.0",
                                          "CC-BY-SA-3.0", "CC-BY-SA-4.0", "MIT",
                                          "BSD-2-Clause", "BSD-3-Clause", "Apache-2.0"};
  std::set<std::string> names, files;
  for (const Row& e : cat) {
    const std::string& name = e.at("name");
    INFO(name);
    CHECK(names.insert(name).second);
    // Licence, its evidence and the source pinned to a commit.
    CHECK(licences.count(e.at("licence")) == 1);
    CHECK(!e.at("licence_evidence").empty());
    CHECK(!e.at("source_repo").empty());
    CHECK(e.at("source_commit").size() == 40);
    if (e.at("licence").rfind("CC-BY", 0) == 0) CHECK(!e.at("author").empty());
    // The transform is the converter's row.
    REQUIRE(transforms.count(name) == 1);
    const Row& t = transforms.at(name);
    CHECK(t.at("class") == e.at("class"));
    CHECK(t.at("repo") == e.at("source_repo"));
    CHECK(t.at("commit") == e.at("source_commit"));
    CHECK(t.at("path") == e.at("source_path"));
    // The file: in its class folder, read by canopy's reader.
    const std::string file = e.at("file");
    CHECK(file == e.at("class") + "/" + name + ".ply");
    files.insert(file);
    const formats::TriangleMesh m = formats::parse_triangle_mesh(
        common::read_file(kDir + "/" + file), file, fs::path(file).extension().string().substr(1));
    CHECK(m.faces.size() == std::stoul(e.at("triangles")));
    const Box b = bounds(m);
    const Eigen::Vector3d size = b.hi - b.lo;
    CHECK(std::abs(size.x() - std::stod(e.at("length_m"))) <= 0.01);
    CHECK(std::abs(size.y() - std::stod(e.at("width_m"))) <= 0.01);
    CHECK(std::abs(size.z() - std::stod(e.at("height_m"))) <= 0.01);
    CHECK(std::abs(b.lo.z()) <= 1e-3);
    CHECK(std::abs(b.lo.x() + b.hi.x()) <= 2e-3);
    CHECK(std::abs(b.lo.y() + b.hi.y()) <= 2e-3);
    CHECK(size.x() >= size.y());  // length along x
    // Plausible for the class.
    REQUIRE(ranges.count(e.at("class")) == 1);
    const Row& c = ranges.at(e.at("class"));
    CHECK(size.x() >= std::stod(c.at("length_min")));
    CHECK(size.x() <= std::stod(c.at("length_max")));
    CHECK(size.y() >= std::stod(c.at("width_min")));
    CHECK(size.y() <= std::stod(c.at("width_max")));
    CHECK(size.z() >= std::stod(c.at("height_min")));
    CHECK(size.z() <= std::stod(c.at("height_max")));
  }
  CHECK(transforms.size() == cat.size());
  // No mesh file without a catalogue (licence) entry; the whole library within 25 MB.
  std::uintmax_t total = 0;
  for (const auto& p : fs::recursive_directory_iterator(kDir)) {
    if (p.is_symlink() || !p.is_regular_file()) continue;  // modelbase/: links, checked below
    total += p.file_size();
    const std::string ext = p.path().extension().string();
    if (ext == ".ply" || ext == ".obj" || ext == ".stl") {
      INFO(p.path());
      CHECK(files.count(fs::relative(p.path(), kDir).string()) == 1);
    }
  }
  CHECK(total <= 25u * 1000 * 1000);
}

TEST_CASE("modelbase/: one link <class>__<name>.ply per modelbase instance, to its catalogued mesh") {
  std::map<std::string, Row> cat;
  for (const Row& e : read_csv("catalogue.csv")) cat[e.at("name")] = e;
  std::set<std::string> want, have;
  for (const Row& s : read_csv("split.csv")) {
    if (s.at("split") != "modelbase") continue;
    const Row& c = cat.at(s.at("name"));
    want.insert(c.at("class") + "__" + s.at("name") + ".ply");
    const fs::path link = fs::path(kDir) / "modelbase" / (c.at("class") + "__" + s.at("name") + ".ply");
    INFO(link);
    REQUIRE(fs::is_symlink(link));
    CHECK(fs::equivalent(link, fs::path(kDir) / c.at("file")));
  }
  for (const auto& p : fs::directory_iterator(fs::path(kDir) / "modelbase"))
    have.insert(p.path().filename().string());
  CHECK(have == want);  // no test instance among them
}

TEST_CASE("split.csv: modelbase and test instances cover the catalogue and never overlap") {
  std::map<std::string, std::string> cls;
  for (const Row& e : read_csv("catalogue.csv")) cls[e.at("name")] = e.at("class");
  std::map<std::string, std::string> split;
  std::map<std::string, std::map<std::string, int>> per_class;
  for (const Row& s : read_csv("split.csv")) {
    INFO(s.at("name"));
    CHECK(split.emplace(s.at("name"), s.at("split")).second);  // one split per instance
    CHECK((s.at("split") == "modelbase" || s.at("split") == "test"));
    REQUIRE(cls.count(s.at("name")) == 1);
    CHECK(cls.at(s.at("name")) == s.at("class"));
    ++per_class[s.at("class")][s.at("split")];
  }
  CHECK(split.size() == cls.size());
  for (const auto& [c, n] : per_class) {
    INFO(c);
    const int total = (n.count("test") ? n.at("test") : 0) + (n.count("modelbase") ? n.at("modelbase") : 0);
    CHECK(n.count("modelbase") == 1);  // every class has a modelbase instance
    if (total >= 2) CHECK(n.count("test") == 1);
  }
}

TEST_CASE("distances.csv: every test instance against exactly its class's modelbase instances, ranked") {
  // scripts/vehicles/distance.py writes it (the report's instance accuracy reads rank 1); a mesh
  // or split change without re-running it leaves rows that no longer match split.csv.
  std::map<std::string, std::set<std::string>> modelbase_of_class;
  std::map<std::string, std::string> test_class;
  for (const Row& s : read_csv("split.csv")) {
    if (s.at("split") == "modelbase")
      modelbase_of_class[s.at("class")].insert(s.at("name"));
    else
      test_class[s.at("name")] = s.at("class");
  }
  std::map<std::string, std::vector<Row>> rows;
  for (const Row& r : read_csv("distances.csv")) rows[r.at("test")].push_back(r);
  CHECK(rows.size() == test_class.size());
  for (const auto& [test, cls] : test_class) {
    INFO(test);
    REQUIRE(rows.count(test) == 1);
    std::set<std::string> named;
    double last = 0;
    for (std::size_t i = 0; i < rows.at(test).size(); ++i) {
      const Row& r = rows.at(test)[i];
      CHECK(r.at("class") == cls);
      CHECK(std::stoi(r.at("rank")) == static_cast<int>(i) + 1);
      const double d = std::stod(r.at("distance_m"));
      CHECK(d > 0);    // a test instance is never a modelbase mesh
      CHECK(d < 2.0);  // same-class vehicles in one frame: well under the size of a vehicle
      CHECK(d >= last);
      last = d;
      named.insert(r.at("modelbase"));
    }
    CHECK(named == modelbase_of_class[cls]);
  }
}
