// LAZ reader (formats/laz.h). Known answers come from other decoders, never from ours:
//  - small files from laspy's and PDAL's test data against the uncompressed LAS of the same
//    points (simple, extra bytes, LAS 1.4 with EVLRs, COPC with variable chunks);
//  - the committed real tiles (share/real/, one copy for the experiment and the tests) against
//    SHA-256 digests of the point records of the LAS that laz-perf 0.0.7 decoded from them
//    (../shared/data/real/reference, digests and hand-checked records read with python3
//    hashlib / struct; tests/las/data/README.md);
//  - with CANOPY_REAL_DATA present, every record of every shared pair compared byte for byte.
// Broken files are generated from the good ones.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/laz.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/points_io.h"
#include "las_bytes.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using namespace canopy::formats;
using canopy::common::DataError;

namespace {

using canopy::las_test::data;
using canopy::las_test::get;
using canopy::las_test::real;
using canopy::las_test::set;
using canopy::las_test::slurp;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The point records of a LAS file, `prefix` bytes of each (0: whole records).
struct Records {
  std::uint64_t n = 0;
  std::size_t record = 0, offset = 0;
};

Records records(const std::string& las) {
  Records r;
  r.offset = get<std::uint32_t>(las, 96);
  r.record = get<std::uint16_t>(las, 105);
  r.n = get<std::uint32_t>(las, 107);
  if (las[25] >= 4 && get<std::uint64_t>(las, 247) != 0) r.n = get<std::uint64_t>(las, 247);
  return r;
}

std::string record_bytes(const std::string& las, std::size_t prefix = 0) {
  const Records r = records(las);
  const std::size_t k = prefix ? prefix : r.record;
  std::string out;
  out.reserve(static_cast<std::size_t>(r.n) * k);
  for (std::uint64_t i = 0; i < r.n; ++i) out.append(las, r.offset + i * r.record, k);
  return out;
}

// SHA-256 by coreutils' sha256sum (an implementation that is not ours).
std::string sha256(const std::string& bytes) {
  static int count = 0;
  const fs::path dir = fs::path(CANOPY_TEST_TMP) / "las" / "laz-digest";
  fs::create_directories(dir);
  const fs::path file = dir / ("bytes" + std::to_string(count++));
  std::ofstream(file, std::ios::binary) << bytes;
  const fs::path out = dir / "sum";
  REQUIRE(canopy::test::run("sha256sum " + file.string() + " > " + out.string()) == 0);
  fs::remove(file);
  return slurp(out.string()).substr(0, 64);
}

// The DataError message of reading `bytes` as LAS/LAZ, or "" when it reads.
std::string laz_error(const std::string& bytes, const std::string& name = "t.laz") {
  try {
    parse_las(bytes, name);
  } catch (const DataError& e) { return e.what(); }
  return "";
}

void check_bounds(const PointCloud& c, const std::string& file_bytes) {
  const char* axis[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) {
    const auto& v = c.col(axis[d]);
    CHECK(*std::max_element(v.begin(), v.end()) == Approx(get<double>(file_bytes, 179 + 16 * d)).margin(1e-7));
    CHECK(*std::min_element(v.begin(), v.end()) == Approx(get<double>(file_bytes, 187 + 16 * d)).margin(1e-7));
  }
}

}  // namespace

TEST_CASE("simple.laz (LAS 1.2 format 3): the records of simple.las, the same points uncompressed", "[laz]") {
  const std::string laz = slurp(data("simple.laz"));
  REQUIRE(laszip_compressed(laz));
  const std::string las = laz_to_las(laz, "simple.laz");
  CHECK_FALSE(laszip_compressed(las));
  CHECK(las[104] == 3);
  const Records r = records(las);
  REQUIRE(r.n == 1065);
  REQUIRE(r.record == 34);
  const std::string ref = slurp(data("simple.las"));
  CHECK(record_bytes(las) == record_bytes(ref));
  // extrabytes.las (PDAL) holds the same points with extra bytes after each 34-byte record.
  CHECK(record_bytes(las) == record_bytes(slurp(data("extrabytes.las")), 34));
  // The same, as a digest computed with python3 hashlib from simple.las.
  CHECK(sha256(record_bytes(las)) == "0717948a72e6bf719db8d96ded1e76b760d73fb683347ebe3dd603832e3d5015");

  const PointCloud c = parse_las(laz, "simple.laz");
  REQUIRE(c.size() == 1065);
  check_bounds(c, laz);
  CHECK(c.col("x")[0] == 637012.24);
  CHECK(c.col("y")[0] == 849028.31);
  CHECK(c.col("z")[0] == 431.66);
  CHECK(c.col("intensity")[0] == 143);
  CHECK(c.col("scan_angle")[0] == -9);
  CHECK(c.col("point_source_id")[0] == 7326);
  CHECK(c.col("gps_time")[0] == 245380.78254962614);
  CHECK(c.col("red")[0] == 68);
  CHECK(c.col("green")[0] == 77);
  CHECK(c.col("blue")[0] == 88);
  CHECK(c.col("x")[1064] == 637342.85);
  CHECK(c.col("gps_time")[1064] == 249773.20172406783);
  CHECK(c.col("red")[1064] == 138);
  // Every column equals the LAS reader's on the uncompressed file.
  const PointCloud e = read_las(data("simple.las"));
  REQUIRE(c.names() == e.names());
  for (const std::string& name : c.names()) {
    INFO(name);
    CHECK(c.col(name) == e.col(name));
  }
}

TEST_CASE("extra.laz (LAS 1.4 format 3 + 27 extra bytes, BYTE item) = PDAL's extrabytes.las", "[laz]") {
  const std::string las = laz_to_las(slurp(data("extra.laz")), "extra.laz");
  const std::string ref = slurp(data("extrabytes.las"));
  REQUIRE(records(las).record == 61);
  REQUIRE(records(las).n == 1065);
  CHECK(record_bytes(las) == record_bytes(ref));
  // The Extra Bytes VLR survives: the same columns as the LAS.
  CHECK(read_las(data("extra.laz")).names() == read_las(data("extrabytes.las")).names());
}

TEST_CASE("1_4_w_evlr.laz (LAS 1.4 format 6, EVLRs): decompresses to 1_4_w_evlr.las byte for byte", "[laz]") {
  const std::string las = laz_to_las(slurp(data("1_4_w_evlr.laz")), "1_4_w_evlr.laz");
  const std::string ref = slurp(data("1_4_w_evlr.las"));
  CHECK(records(las).n == 1000);
  CHECK(get<std::uint32_t>(las, 243) == 1);  // one EVLR, moved behind the decoded records
  CHECK(las == ref);                         // header, VLRs, records and EVLR
}

TEST_CASE("simple.copc.laz (COPC: LAS 1.4 format 7, variable chunks) holds simple.las's points", "[laz]") {
  const std::string laz = slurp(data("simple.copc.laz"));
  REQUIRE(get<std::uint32_t>(laz, 96 + 0) > 0);
  const PointCloud c = parse_las(laz, "simple.copc.laz");
  const PointCloud e = read_las(data("simple.las"));
  REQUIRE(c.size() == 1065);
  check_bounds(c, laz);
  // The octree reorders the points: compare them sorted, coordinates on their 0.01 grid.
  auto rows = [](const PointCloud& p) {
    std::vector<std::vector<double>> out(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (const char* f : {"x", "y", "z"}) out[i].push_back(std::round(p.col(f)[i] * 100));
      for (const char* f : {"gps_time", "intensity", "return_number", "number_of_returns", "classification",
                            "point_source_id", "red", "green", "blue"}) {
        out[i].push_back(p.col(f)[i]);
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  CHECK(rows(c) == rows(e));
}

TEST_CASE("real LAZ tiles (AHN3 format 1; IGN format 8 with and without extra bytes) = laz-perf's LAS",
          "[laz]") {
  struct Case {
    const char* file;
    int format;
    std::uint64_t n;
    std::size_t record;
    const char* digest;  // SHA-256 of the reference LAS's point records
  };
  const Case cases[] = {
      {"ahn3_delft_2.laz", 1, 208432, 28, "d7dc9001393324a70d34c119b9fa4b0ed973d353e26e1ecebdadcd3ac5a97bde"},
      {"forest_lareunion.laz", 8, 59712, 38,
       "1a31de2ea79b28dcec81d158654a83fa86aa5a47d31187498754a4b58790f0a2"},
      {"ign_lidarhd_870000_6618000.laz", 8, 70840, 94,
       "320fd1c4b13d99ff9dd0581bf43fd291a0c62042570dd7aa28834c6d6ad022cc"},
  };
  for (const Case& k : cases) {
    INFO(k.file);
    const std::string laz = slurp(real(k.file));
    const std::string las = laz_to_las(laz, k.file);
    const Records r = records(las);
    CHECK(las[104] == k.format);
    CHECK(r.n == k.n);
    CHECK(r.record == k.record);
    CHECK(sha256(record_bytes(las)) == k.digest);
    const PointCloud c = parse_las(laz, k.file);
    CHECK(c.size() == k.n);
    check_bounds(c, laz);
  }

  // Hand-checked records (python3 struct on the reference LAS): first, middle, last.
  const PointCloud ahn = read_las(real("ahn3_delft_2.laz"));
  CHECK(ahn.col("x")[0] == 85000.016);
  CHECK(ahn.col("y")[0] == 447414.207);
  CHECK(ahn.col("z")[0] == 0.81);
  CHECK(ahn.col("intensity")[0] == 222);
  CHECK(ahn.col("classification")[0] == 2);
  CHECK(ahn.col("scan_angle")[0] == -13);
  CHECK(ahn.col("point_source_id")[0] == 57139);
  CHECK(ahn.col("gps_time")[0] == 230039.2449662844);
  CHECK(ahn.col("return_number")[104216] == 2);
  CHECK(ahn.col("number_of_returns")[104216] == 4);
  CHECK(ahn.col("z")[104216] == 6.018);
  CHECK(ahn.col("gps_time")[104216] == 230769.85708578053);
  CHECK(ahn.col("x")[208431] == 85000.009);
  CHECK(ahn.col("classification")[208431] == 6);
  CHECK(ahn.col("intensity")[208431] == 401);

  const PointCloud reunion = read_las(real("forest_lareunion.laz"));
  CHECK(reunion.col("x")[0] == 377016.62);
  CHECK(reunion.col("return_number")[0] == 3);
  CHECK(reunion.col("number_of_returns")[0] == 3);
  CHECK(reunion.col("scan_angle")[0] == Approx(2384 * 0.006));
  CHECK(reunion.col("gps_time")[29856] == 375761439.0196904);
  CHECK(reunion.col("point_source_id")[29856] == 4);
  CHECK(reunion.col("z")[59711] == 204.99);
  CHECK(reunion.col("intensity")[59711] == 5);

  const PointCloud ign = read_las(real("ign_lidarhd_870000_6618000.laz"));
  CHECK(ign.col("x")[0] == 870277.39);
  CHECK(ign.col("classification")[0] == 208);
  CHECK(ign.col("red")[0] == 38144);
  CHECK(ign.col("green")[0] == 39424);
  CHECK(ign.col("blue")[0] == 32512);
  CHECK(ign.col("nir")[0] == 0);
  CHECK(ign.col("gps_time")[35420] == 297417271.87130487);
  CHECK(ign.col("number_of_returns")[35420] == 3);
  CHECK(ign.col("intensity")[70839] == 967);
  CHECK(ign.col("blue")[70839] == 49152);
  CHECK(ign.names().size() == 22 + 7);  // format 8's columns and 7 described extra bytes
  CHECK(ign.col("entropy")[0] == 0.016576556488871574);
  CHECK(ign.col("PredictedClassification")[0] == 2);
}

TEST_CASE("every shared real LAZ equals its reference LAS, record for record", "[laz][real]") {
  const fs::path root = CANOPY_REAL_DATA;
  if (!fs::is_directory(root / "reference") || !fs::is_directory(root / "laz")) {
    WARN("no real data at " << root.string() << " (CMake cache variable CANOPY_REAL_DATA): comparison skipped");
    return;
  }
  std::vector<fs::path> refs;
  for (const auto& e : fs::directory_iterator(root / "reference")) {
    if (e.path().extension() == ".las") refs.push_back(e.path());
  }
  std::sort(refs.begin(), refs.end());
  CHECK(refs.size() >= 7);
  for (const fs::path& ref_path : refs) {
    const fs::path laz_path = root / "laz" / (ref_path.stem().string() + ".laz");
    INFO(laz_path.string());
    REQUIRE(fs::exists(laz_path));
    const std::string laz = slurp(laz_path.string());
    const std::string ref = slurp(ref_path.string());
    const std::string las = laz_to_las(laz, laz_path.string());
    const Records a = records(las), b = records(ref);
    REQUIRE(a.n == b.n);
    REQUIRE(a.record == b.record);
    CHECK(las[104] == ref[104]);
    CHECK(las.compare(131, 48, ref, 131, 48) == 0);  // scale and offset
    std::uint64_t differ = 0;
    for (std::uint64_t i = 0; i < a.n; ++i) {
      if (las.compare(a.offset + i * a.record, a.record, ref, b.offset + i * b.record, b.record) != 0)
        ++differ;
    }
    CHECK(differ == 0);
    // Through the column reader too.
    CHECK(parse_las(laz, laz_path.string()).size() == parse_las(ref, ref_path.string()).size());
  }
  // The LAZ files without a reference decode to the header's count and bounds.
  for (const auto& e : fs::directory_iterator(root / "laz")) {
    if (fs::exists(root / "reference" / (e.path().stem().string() + ".las"))) continue;
    INFO(e.path().string());
    const std::string laz = slurp(e.path().string());
    const PointCloud c = parse_las(laz, e.path().string());
    CHECK(c.size() == records(laz).n);
    check_bounds(c, laz);
  }
}

TEST_CASE("broken LAZ: a clear error naming the file, memory bounded by the file", "[laz]") {
  const std::string good = slurp(data("simple.laz"));  // 1.2 format 3, points at 333, 18 217 bytes
  REQUIRE(laz_error(good).empty());
  const std::size_t data_at = get<std::uint32_t>(good, 96);
  const auto table_at = static_cast<std::size_t>(get<std::int64_t>(good, data_at));
  REQUIRE(table_at == 18203);

  // Truncated anywhere: never a crash, always the file's name.
  for (std::size_t len : {std::size_t{100}, std::size_t{300}, data_at + 4, data_at + 40, std::size_t{9000},
                          table_at + 4, good.size() - 1}) {
    INFO(len);
    const std::string e = laz_error(good.substr(0, len), "cut.laz");
    CHECK(contains(e, "cut.laz: "));
  }
  CHECK(contains(laz_error(good.substr(0, 9000), "cut.laz"), "chunk table offset 18203 is not between"));

  // A lying point count: refused from the chunk table, before anything is allocated.
  std::string b = good;
  set<std::uint32_t>(&b, 107, 4000000000u);
  CHECK(contains(laz_error(b), "t.laz: LAZ chunks hold 50000 points, the header says 4000000000"));
  // A lying chunk size too: the one chunk would expand beyond what LASzip can compress.
  const std::size_t vlr = 227 + 54;
  set<std::uint32_t>(&b, vlr + 12, 4000000000u);
  CHECK(contains(laz_error(b), "LAZ chunk 1 of 1 claims 4000000000 points of 34 bytes in 17862 bytes"));
  // Fewer points than the chunk holds: decoded up to the header's count.
  b = good;
  set<std::uint32_t>(&b, 107, 1000u);
  const std::string cut = laz_to_las(b, "t.laz");
  CHECK(record_bytes(cut) == record_bytes(laz_to_las(good, "t.laz")).substr(0, 1000 * 34));

  // The chunk table pointing elsewhere, or of an unknown version.
  b = good;
  set<std::int64_t>(&b, data_at, 12);
  CHECK(contains(laz_error(b), "LAZ chunk table offset 12 is not between the point data"));
  b = good;
  set<std::uint32_t>(&b, table_at, 7);
  CHECK(contains(laz_error(b), "LAZ chunk table version 7 is unknown"));
  b = good;
  set<std::uint32_t>(&b, table_at + 4, 1000000000u);
  CHECK(contains(laz_error(b), "LAZ chunk table lists 1000000000 chunks for 17862 bytes"));

  // The compression bit without a LASzip VLR, and the VLR's contents.
  b = good;
  std::memcpy(&b[vlr - 54 + 2], "not laszip     ", 15);
  CHECK(contains(laz_error(b),
                 "t.laz: the point format byte says LAZ (compression bit set) but the file has no "
                 "LASzip VLR"));
  b = good;
  set<std::uint16_t>(&b, vlr + 34 + 4, 1);  // POINT10 version 1
  CHECK(contains(laz_error(b), "LASzip item type 6 version 1 is not supported"));
  b = good;
  set<std::uint16_t>(&b, vlr + 34 + 12, 9);  // the third item a waveform packet
  CHECK(contains(laz_error(b), "(waveform packets)"));
  b = good;
  set<std::uint16_t>(&b, 105, 35);
  CHECK(contains(laz_error(b), "LASzip items add up to 34 bytes, the point record has 35"));
  b = good;
  set<std::uint16_t>(&b, 105, 0);
  for (int k = 0; k < 3; ++k) set<std::uint16_t>(&b, vlr + 34 + 6 * k + 2, 0);  // items of 0 bytes
  // The header check shared with the LAS reader (formats/src/las_header.h) refuses it first.
  CHECK(contains(laz_error(b), "t.laz: point record length 0 is below the"));
  b = good;
  set<std::uint16_t>(&b, vlr, 4);
  CHECK(contains(laz_error(b), "LASzip compressor 4 is unknown"));

  // Damaged compressed bytes: an error or wrong values, never a crash or a hang.
  for (std::size_t at = data_at + 8 + 40; at < table_at; at += 211) {
    b = good;
    b[at] = static_cast<char>(b[at] ^ 0x5A);
    const std::string e = laz_error(b, "flip.laz");
    if (!e.empty()) CHECK(contains(e, "flip.laz: LAZ chunk 1 of 1 (bytes 341-18203) is corrupt"));
  }
  // LAS 1.4 EVLRs (1_4_w_evlr.laz: one, "pylastest" 42 of 16 bytes, ending the file): the first's
  // offset before the point data, inside the compressed records, past the end; its count too
  // large; its length past the end (stop 70: the CRS EVLRs are read from the same walk).
  const std::string evlr = slurp(data("1_4_w_evlr.laz"));
  const std::size_t evlr_at = get<std::uint64_t>(evlr, 235);
  REQUIRE(evlr_at + 60 + 16 == evlr.size());
  b = evlr;
  set<std::uint64_t>(&b, 235, 100);
  CHECK(
      contains(laz_error(b), "t.laz: EVLR start 100 is not between the point data and the end of the file"));
  b = evlr;
  set<std::uint64_t>(&b, 235, get<std::uint32_t>(evlr, 96) + 100);  // garbage read as an EVLR header
  CHECK(contains(laz_error(b), "t.laz: EVLR 1 of "));
  CHECK(contains(laz_error(b), " bytes runs past the end of the file"));
  b = evlr;
  set<std::uint64_t>(&b, 235, evlr.size() + 1);
  CHECK(contains(laz_error(b), "t.laz: EVLR start " + std::to_string(evlr.size() + 1) + " is not between"));
  b = evlr;
  set<std::uint32_t>(&b, 243, 2);
  CHECK(contains(laz_error(b), "t.laz: LAS header says 2 EVLRs but EVLR 2 does not fit in the file"));
  b = evlr;
  set<std::uint64_t>(&b, evlr_at + 20, 17);
  CHECK(contains(laz_error(b), "t.laz: EVLR 1 of 17 bytes runs past the end of the file"));

  // A layered (LAS 1.4) chunk whose layer sizes lie.
  const std::string ign = slurp(real("forest_lareunion.laz"));
  const std::size_t ign_data = get<std::uint32_t>(ign, 96);
  b = ign;
  set<std::uint32_t>(&b, ign_data + 8 + 38 + 4, 0x7FFFFFFFu);  // the XY layer
  CHECK(contains(laz_error(b, "l.laz"), "l.laz: LAZ chunk 1 of 2 (bytes"));
  CHECK(contains(laz_error(b, "l.laz"), "is corrupt: a layer runs past the end of the chunk"));
  b = ign;
  set<std::uint32_t>(&b, ign_data + 8 + 38, 12);  // the chunk's point count
  CHECK(contains(laz_error(b, "l.laz"), "it holds 12 points, the chunk table and header ask for 50000"));
}

TEST_CASE("tools read LAZ by content; a broken LAZ exits 1 without output", "[laz][cli]") {
  const fs::path d = canopy::test::fresh_dir("las", "laz-cli");
  const std::string pcd2ply = std::string(CANOPY_BIN_DIR) + "/pcd2ply";
  REQUIRE(canopy::test::run(pcd2ply + " -q -i " + data("simple.laz") + " -o " + (d / "simple.ply").string()) ==
          0);
  const Mesh m = read_ply((d / "simple.ply").string());
  CHECK(m.vertices.size() == 1065);
  CHECK(m.vertices.col("gps_time")[0] == 245380.78254962614);

  std::string bad = slurp(data("simple.laz"));
  bad.resize(9000);
  std::ofstream((d / "cut.laz").string(), std::ios::binary) << bad;
  std::string err;
  CHECK(canopy::test::sh(pcd2ply + " -q -i " + (d / "cut.laz").string() + " -o " + (d / "cut.ply").string(),
                         d / "err.txt", &err) == 1);
  CHECK(contains(err, "cut.laz: LAZ chunk table offset"));
  CHECK_FALSE(fs::exists(d / "cut.ply"));
}
