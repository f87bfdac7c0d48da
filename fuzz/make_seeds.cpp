// Writes the seed corpora of the fuzz targets: <out>/pcd, <out>/ply, <out>/json, <out>/laz,
// <out>/las, <out>/las_crs. Valid files in every encoding our writers produce, and the malformed cases of
// issue 12 (huge counts, overflowing headers, NUL bytes, ...), built here rather than committed
// as binaries; for LAZ (which canopy does not write) the small LAZ test files and damaged copies
// of them; for fuzz_las_crs the CRS records of the LAS test files and cut copies.
// Usage: make_seeds <out dir>
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "canopy/documents/match_result.h"
#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "canopy/documents/segment_graph.h"

namespace d = canopy::documents;
namespace f = canopy::formats;

namespace {

std::string out_dir;

void put(const std::string& kind, const std::string& name, const std::string& bytes) {
  mkdir((out_dir + "/" + kind).c_str(), 0755);
  std::ofstream(out_dir + "/" + kind + "/" + name, std::ios::binary) << bytes;
}

std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

f::PointCloud cloud() {
  f::PointCloud c;
  c.resize(6);
  c.add("x") = {0, 1, 2, 3, 4, 5};
  c.add("y") = {0.5, 0.25, 0.125, 1, 1, 1};
  c.add("z", f::kFloat64) = {1.0 / 3, 2, 2, 2, 2, 2};
  c.add("view_idx", f::kInt32) = {-1, 0, 1, 1, 1, 1};
  c.add("label", f::kUint32) = {1, 2, 3, 0, 0, 0};
  c.add("flag", f::kUint8) = {255, 0, 7, 7, 7, 7};
  c.add("s", {'I', 2}) = {-300, 300, 0, 0, 0, 0};
  c.comments = {"seed"};
  return c;
}

void pcd_seeds() {
  const f::PointCloud c = cloud();
  for (auto [name, enc] : {std::pair<const char*, f::PcdEncoding>{"binary.pcd", f::PcdEncoding::binary},
                           {"compressed.pcd", f::PcdEncoding::binary_compressed},
                           {"ascii.pcd", f::PcdEncoding::ascii}}) {
    f::PcdWriteOptions o;
    o.encoding = enc;
    put("pcd", name, f::serialize_pcd(c, o));
  }
  const std::string xyz = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  put("pcd", "count-padding.pcd",
      "FIELDS x y _ n\nSIZE 4 4 1 2\nTYPE F F U I\nCOUNT 1 1 3 2\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n"
      "1 2 0 0 0 5 6\n3 4 0 0 0 7 8\n");
  put("pcd", "padded.pcd", f::serialize_pcd(c) + std::string(512, '\0'));
  put("pcd", "blank-header-line.pcd",
      "VERSION 0.7\n   \nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n");
  put("pcd", "count-20000.pcd",
      "FIELDS x y z f\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 20000\nWIDTH 0\nHEIGHT 1\n"
      "POINTS 0\nDATA binary\n");
  const std::string body(36, '\x01');
  for (const char* n : {"100000000", "4294967295", "9223372036854775807"}) {
    put("pcd", std::string("points-") + n + ".pcd",
        xyz + "WIDTH " + n + "\nHEIGHT 1\nPOINTS " + n + "\nDATA binary\n" + body);
  }
  put("pcd", "compressed-huge.pcd",
      "FIELDS x\nSIZE 4\nTYPE F\nCOUNT 1\nWIDTH 1073741823\nHEIGHT 1\n"
      "POINTS 1073741823\nDATA binary_compressed\n" +
          u32(2) + u32(4294967292u) + "\xfc\xff");
  put("pcd", "wh-overflow.pcd", xyz + "WIDTH 4294967296\nHEIGHT 4294967296\nPOINTS 0\nDATA binary\n");
  put("pcd", "size-4294967300.pcd", "FIELDS x\nSIZE 4294967300\nTYPE F\nWIDTH 1\nPOINTS 1\nDATA binary\n1234");
  put("pcd", "x-1e30.pcd", xyz + "WIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n1e30 0 0\n0 0 0\n0.1 0 nan\n");
  put("pcd", "nul.pcd", std::string("VERSION 0.7\nFIE\0LDS x\n", 22));
}

f::Mesh mesh() {
  f::Mesh m;
  m.vertices = cloud();
  m.vertices.add("normal_z") = {1, 1, 1, 1, 1, 1};
  m.vertices.add("red", f::kUint8) = {1, 2, 3, 4, 5, 6};
  m.faces = {{0, 1, 2}, {2, 3, 4}, {3, 4, 5}};
  return m;
}

void ply_seeds() {
  const f::Mesh m = mesh();
  put("ply", "binary.ply", f::serialize_ply(m));
  put("ply", "ascii.ply", f::serialize_ply(m, true));
  f::PlyWriteOptions o;
  o.scalar_prefix = true;
  put("ply", "scalar.ply", f::serialize_ply(m, o));
  std::string be =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_index\nelement extra 1\n"
      "property list ushort short stuff\nend_header\n";
  be += std::string(48, '\0') + "\x04" + std::string("\0\0\0\0\0\0\0\x01\0\0\0\x02\0\0\0\x03", 16) +
        std::string("\0\x02\0\x05\0\x06", 6);
  put("ply", "big-endian-quad.ply", be);
  const std::string hdr =
      "ply\nformat binary_little_endian 1.0\nelement vertex COUNT\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  for (const char* n : {"100000000", "4294967295", "9223372036854775807"}) {
    std::string h = hdr;
    h.replace(h.find("COUNT"), 5, n);
    put("ply", std::string("vertex-") + n + ".ply", h + std::string(36, '\0'));
  }
  const std::string tri =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face FACES\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  std::string face = tri;
  face.replace(face.find("FACES"), 5, "4294967295");
  put("ply", "face-4294967295.ply", face);
  face = tri;
  face.replace(face.find("FACES"), 5, "1");
  put("ply", "uchar-259.ply", face + "259 0 1 2\n");
  put("ply", "nul.ply", std::string("ply\nformat ascii 1.0\nelem\0ent vertex 1\nend_header\n", 47));
}

void json_seeds() {
  d::SegmentGraph g;
  g.provenance = {"ncut", "0.1.0", {{"r", "512mm"}}, {"mesh.ply"}};
  g.mesh = "mesh.ply";
  d::Segment s;
  s.vertex_count = 3;
  s.area = 1.5;
  s.radii = {0.7, 0.4, 0.01};
  s.normal = {0, 0, 1};
  s.vertices = {0, 1, 2};
  g.segments.push_back(s);
  s.segment_id = 1;
  g.segments.push_back(s);
  g.adjacency.push_back({0, 1, 3});
  const std::string graph = d::serialize_segment_graph(g);
  put("json", "graph.json", graph);
  auto variant = [&](const std::string& from, const std::string& to) {
    std::string t = graph;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  put("json", "area-1e400.json", variant("\"area\": 1.5", "\"area\": 1e400"));
  put("json", "version-4294967297.json", variant("\"version\": 1", "\"version\": 4294967297"));
  put("json", "segment-id-1e20.json", variant("\"segment_id\": 0", "\"segment_id\": 1e20"));
  put("json", "dangling.json",
      variant("\"shared_edges\": 3",
              "\"shared_edges\": 3}, {\"a\": 0, \"b\": 99999, "
              "\"shared_edges\": 1}, {\"a\": 1, \"b\": 1, \"shared_edges\": 1"));
  put("json", "deep.json", "{\"format\": " + std::string(100, '[') + std::string(100, ']') + "}");
  d::MatchResult r;
  r.provenance = {"gmatch", "0.1.0", {}, {"s.json"}};
  r.object = "s.json";
  r.error_form = "bounded";
  d::ModelScore a;
  a.model = "sedan";
  a.score = 0.8;
  a.rank = 1;
  a.pairs = {{0, 2, 0.1}, {1, -1, 0}};
  d::ModelScore b = a;
  b.model = "tank";
  b.score = 0.5;
  b.rank = 2;
  r.models = {a, b};
  put("json", "match.json", d::serialize_match_result(r));
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The small LAZ files of tests/las/data, and copies with a lying point count, a lying chunk
// table offset, a cut chunk and a damaged byte in every kilobyte.
void laz_seeds() {
  const std::string dir = std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/";
  for (const char* name : {"simple.laz", "extra.laz", "1_4_w_evlr.laz", "simple.copc.laz"}) {
    const std::string laz = slurp(dir + name);
    if (laz.size() < 400) continue;
    const std::string base = std::string(name).substr(0, std::string(name).size() - 4);
    put("laz", base + ".laz", laz);
    std::uint32_t data_at;
    std::memcpy(&data_at, &laz[96], 4);
    std::string b = laz;
    std::memcpy(&b[laz[25] >= 4 ? 247 : 107], "\xff\xff\xff\x0f", 4);  // LAS 1.4: the 64-bit count
    put("laz", base + "-count.laz", b);
    b = laz;
    if (data_at + 8 <= b.size()) std::memcpy(&b[data_at], "\x10\0\0\0\0\0\0\0", 8);
    put("laz", base + "-table.laz", b);
    put("laz", base + "-cut.laz", laz.substr(0, laz.size() / 2));
    b = laz;
    for (std::size_t at = data_at + 8; at < b.size(); at += 1024) b[at] = static_cast<char>(b[at] ^ 0x41);
    put("laz", base + "-flips.laz", b);
  }
}

// fuzz_las: a LAS 1.4 file (canopy's writer) with CRS EVLRs after its points (a WKT, a GeoKey
// directory, a record of another user), and copies with a lying EVLR count and length.
void las_seeds() {
  std::string las = f::serialize_las(cloud(), "seed.las");
  const std::string wkt = "PROJCS[\"RGF93 v1 / Lambert-93\",UNIT[\"metre\",1],AUTHORITY[\"EPSG\",\"2154\"]]";
  const std::string keys("\1\0\1\0\0\0\1\0\0\x0c\0\0\1\0\x6a\x08", 16);  // 3072 = 2154
  const std::uint64_t first = las.size();
  std::uint32_t count = 0;
  for (const auto& [user, id, payload] : {std::tuple<std::string, std::uint16_t, std::string>{"other", 7, "x"},
                                          {"LASF_Projection", 2112, wkt},
                                          {"LASF_Projection", 34735, keys}}) {
    std::string v(60, '\0');
    std::memcpy(&v[2], user.data(), user.size());
    std::memcpy(&v[18], &id, 2);
    const std::uint64_t len = payload.size();
    std::memcpy(&v[20], &len, 8);
    las += v + payload;
    ++count;
  }
  std::memcpy(&las[235], &first, 8);
  std::memcpy(&las[243], &count, 4);
  put("las", "evlr_crs.las", las);
  std::string b = las;
  std::memcpy(&b[243], "\xff\xff\xff\x0f", 4);
  put("las", "evlr_crs-count.las", b);
  b = las;
  std::memcpy(&b[first + 61 + 20], "\0\0\0\x40\0\0\0\0", 8);  // the WKT's length: 1 GiB
  put("las", "evlr_crs-length.las", b);
}

}  // namespace

// fuzz_las_crs's input (its header comment) from a LAS file's CRS records.
std::string crs_seed(const f::LasHeaderBlock& h) {
  std::string keys, wkt;
  bool has_keys = false, liblas = false;
  for (const f::LasVlr& v : h.vlrs) {
    if (v.record_id == 34735 && !has_keys) {
      keys = v.payload;
      has_keys = true;
    }
    if (v.record_id == 2112 && wkt.empty()) {
      wkt = v.payload;
      liblas = v.user_id == "liblas";
    }
  }
  const std::uint16_t len = has_keys ? static_cast<std::uint16_t>(keys.size()) : 0xffff;
  std::string out(1, static_cast<char>(((h.global_encoding & 16) ? 1 : 0) | (liblas ? 2 : 0)));
  out.append(reinterpret_cast<const char*>(&len), 2);
  return out + keys + wkt;
}

// The CRS records (GeoTIFF keys, WKT 1, compound WKT) of tests/las/data, and copies cut short.
void las_crs_seeds() {
  const std::string dir = std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/";
  for (const char* name : {"perm-1.2_0.las", "test1_4.las", "simple.copc.laz", "bad_vlr_count.las"}) {
    f::LasHeaderBlock h;
    try {
      h = f::read_las_header_block(dir + name);
    } catch (const std::exception&) { continue; }
    const std::string seed = crs_seed(h);
    put("las_crs", std::string(name) + ".crs", seed);
    put("las_crs", std::string(name) + "-cut.crs", seed.substr(0, seed.size() * 2 / 3));
  }
  const std::string wkt2 =
      "PROJCRS[\"RGF93 / Lambert-93\",BASEGEOGCRS[\"RGF93\",ID[\"EPSG\",4171]],ID[\"EPSG\",2154]]";
  put("las_crs", "wkt2.crs", std::string("\1\xff\xff", 3) + wkt2);
  put("las_crs", "evlr.crs", std::string("\5\xff\xff", 3) + wkt2);  // an EVLR
  put("las_crs", "evlr-vlr.crs",
      std::string("\x0d\x10\0", 3) + std::string("\1\0\1\0\0\0\1\0\0\x0c\0\0\1\0\xe8\x64", 16) +
          wkt2);  // a VLR (3072 = 25832) and two EVLRs
  put("las_crs", "bound.crs",
      std::string("\1\xff\xff", 3) + "BOUNDCRS[SOURCECRS[" + wkt2 + "],TARGETCRS[GEOGCRS[\"WGS 84\"]]]");
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds <out dir>\n");
    return 2;
  }
  out_dir = argv[1];
  mkdir(out_dir.c_str(), 0755);
  pcd_seeds();
  ply_seeds();
  json_seeds();
  laz_seeds();
  las_seeds();
  las_crs_seeds();
  return 0;
}
