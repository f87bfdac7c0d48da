// formats/las_crs.h: the EPSG code and the linear unit of a LAS/LAZ file's CRS records
// (GeoTIFF keys, OGC WKT), and the header block the point reader hands back, checked on
// records written here, on the LAS test files and on real tiles whose records were read by
// hand (python3 struct, stops 67 and 68: docs/decisions/hardening.md).
#include <sys/stat.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/las_crs.h"
#include "canopy/formats/laz.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/point_cloud.h"
#include "canopy/formats/points_io.h"
#include "las_bytes.h"
#include "support/cli.h"

using namespace canopy::formats;
using namespace canopy::las_test;
namespace fs = std::filesystem;

namespace {

// Lambert-93 as IGN's LiDAR HD tiles write it (WKT 1, shortened: the nodes that matter kept).
const std::string kLambert93 =
    R"(PROJCS["RGF93 v1 / Lambert-93",GEOGCS["RGF93 v1",DATUM["Reseau_Geodesique_Francais_1993_v1",)"
    R"(SPHEROID["GRS 1980",6378137,298.257222101,AUTHORITY["EPSG","7019"]],AUTHORITY["EPSG","6171"]],)"
    R"(PRIMEM["Greenwich",0,AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],)"
    R"(AUTHORITY["EPSG","4171"]],PROJECTION["Lambert_Conformal_Conic_2SP"],PARAMETER["false_easting",700000],)"
    R"(UNIT["metre",1,AUTHORITY["EPSG","9001"]],AXIS["Easting",EAST],AXIS["Northing",NORTH],AUTHORITY["EPSG","2154"]])";

// A small tile as canopy writes it (LAS 1.4, point format 6, WKT bit set, no VLR).
std::string small_las() {
  PointCloud c;
  auto& x = c.add("x", kFloat64);
  auto& y = c.add("y", kFloat64);
  auto& z = c.add("z", kFloat64);
  for (int i = 0; i < 10; ++i) {
    x.push_back(870000 + i);
    y.push_back(6618000 + 2 * i);
    z.push_back(100 + 0.1 * i);
  }
  c.resize(10);
  return serialize_las(c, "small");
}

LasCrs crs_of_file(const std::string& bytes, const std::string& name) {
  const fs::path dir = canopy::test::fresh_dir("las", "crs");
  const std::string p = (dir / name).string();
  canopy::test::write_file(p, bytes);
  // The file still reads as a point cloud: the records do not get in the reader's way.
  CHECK(read_las(p).size() == 10);
  return read_las_crs(p);
}

}  // namespace

TEST_CASE("LAS CRS: the WKT's outermost EPSG authority, never a nested one", "[las][crs]") {
  EpsgCode c = epsg_from_wkt(kLambert93);
  CHECK(c.code == 2154);
  CHECK(c.from == "PROJCS AUTHORITY EPSG 2154");
  // Geographic; WKT 2 with a numeric ID; keywords in any case; ( ) brackets; a NUL ends the text.
  CHECK(epsg_from_wkt(R"(GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],)"
                      R"(AUTHORITY["EPSG","4326"]])")
            .code == 4326);
  c = epsg_from_wkt(R"(PROJCRS["RGF93 / Lambert-93",BASEGEOGCRS["RGF93",ID["EPSG",4171]],)"
                    R"(CS[Cartesian,2],LENGTHUNIT["metre",1,ID["EPSG",9001]],ID["EPSG",2154]])");
  CHECK(c.code == 2154);
  CHECK(c.from == "PROJCRS ID EPSG 2154");
  const char lower[] = "projcs(\"x\", authority(\"epsg\", \"32633\"))\0garbage";
  CHECK(epsg_from_wkt(std::string(lower, sizeof lower - 1)).code == 32633);
  // A quoted name holding brackets, commas and a doubled quote (WKT 2) does not confuse it.
  CHECK(epsg_from_wkt(R"(PROJCS["a [b], ""c"" ]",AUTHORITY["EPSG","25832"]])").code == 25832);

  SECTION("compound: the horizontal part's code, else the compound's") {
    // simple.copc.laz's WKT, shortened: its last AUTHORITY (6360) is the vertical CRS's.
    const std::string compd = R"w(COMPD_CS["NAD83 / Oregon LCC (m) + NAVD88 height (ftUS)",)w"
                              R"w(PROJCS["NAD83 / Oregon LCC (m)",GEOGCS["NAD83",AUTHORITY["EPSG","4269"]],)w"
                              R"w(UNIT["metre",1,AUTHORITY["EPSG","9001"]],AUTHORITY["EPSG","2991"]],)w"
                              R"w(VERT_CS["NAVD88 height (ftUS)",AUTHORITY["EPSG","6360"]]])w";
    c = epsg_from_wkt(compd);
    CHECK(c.code == 2991);
    CHECK(c.from == "COMPD_CS's PROJCS AUTHORITY EPSG 2991");
    CHECK(epsg_from_wkt(R"(COMPD_CS["x",PROJCS["p"],VERT_CS["v"],AUTHORITY["EPSG","5698"]])").code == 5698);
    c = epsg_from_wkt(R"(COMPD_CS["x",PROJCS["UTM_10N",UNIT["m",1]],VERT_CS["v",AUTHORITY["EPSG","5703"]]])");
    CHECK(c.code == 0);
    CHECK_THAT(c.problem, Catch::Contains("COMPD_CS names no EPSG code"));
    CHECK(epsg_from_wkt(R"(BOUNDCRS[SOURCECRS[PROJCRS["p",ID["EPSG",2056]]],TARGETCRS[GEOGCRS["w"]]])").code ==
          2056);
  }
  SECTION("no EPSG code at the top: none, with the reason") {
    // autzen_trim.las: a PROJCS whose only EPSG authority is its unit's (9002).
    c = epsg_from_wkt(R"(PROJCS["NAD_1983_HARN_Lambert_Conformal_Conic",GEOGCS["GCS",AUTHORITY["EPSG","4152"]],)"
                      R"(UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]]])");
    CHECK(c.code == 0);
    CHECK(c.problem == "the WKT's PROJCS names no EPSG code");
    CHECK(epsg_from_wkt(R"(PROJCS["x",AUTHORITY["ESRI","102100"]])").code == 0);
    CHECK(epsg_from_wkt(R"(PROJCS["x",AUTHORITY["EPSG","1234567"]])").code == 0);  // over 6 digits
    CHECK(epsg_from_wkt(R"(PROJCS["x",AUTHORITY["EPSG","0"]])").code == 0);
    // WKT2-2015's geodetic CRS: geographic with an ellipsoidal CS, else (Cartesian) geocentric.
    CHECK(epsg_from_wkt(R"(GEODCRS["WGS 84",DATUM["w"],CS[ellipsoidal,2],ID["EPSG",4326]])").code == 4326);
    CHECK(epsg_from_wkt(R"(GEODCRS["WGS 84",DATUM["w"],CS[Cartesian,3],ID["EPSG",4978]])").code == 0);
    CHECK(epsg_from_wkt(R"(VERT_CS["v",AUTHORITY["EPSG","5703"]])").problem ==
          "the WKT's outermost node is VERT_CS, not a projected, geographic or compound CRS");
  }
  SECTION("not well-formed: none, never a throw") {
    for (const std::string& bad :
         {kLambert93.substr(0, kLambert93.size() - 1), kLambert93.substr(0, 200), std::string(),
          std::string("PROJCS"), std::string("PROJCS[\"x\""), std::string("[\"x\"]"),
          kLambert93 + " PROJCS[]", std::string("PROJCS[\"x\",,]"), std::string(100, '[')}) {
      c = epsg_from_wkt(bad);
      CHECK(c.code == 0);
      CHECK_THAT(c.problem, Catch::StartsWith("the WKT is not well-formed (byte "));
    }
    std::string deep;
    for (int i = 0; i < 40; ++i) deep += "A[";
    deep += std::string(40, ']');
    CHECK_THAT(epsg_from_wkt(deep).problem, Catch::Contains("nested deeper than 32 levels"));
  }
}

TEST_CASE("LAS CRS: the GeoKey directory's projected, else geographic, EPSG code", "[las][crs]") {
  EpsgCode c = epsg_from_geokeys(geokeys({{1024, 1}, {3072, 2154}, {3076, 9001}}));
  CHECK(c.code == 2154);
  CHECK(c.from == "ProjectedCSTypeGeoKey 2154");
  CHECK(epsg_from_geokeys(geokeys({{3072, 2154}})).code == 2154);  // forest_chablais3's only key
  c = epsg_from_geokeys(geokeys({{1024, 2}, {2048, 4326}}));
  CHECK(c.code == 4326);
  CHECK(c.from == "GeographicTypeGeoKey 4326");
  // A projected model whose projection is user-defined: 2048 is only its base, not the CRS.
  c = epsg_from_geokeys(geokeys({{1024, 1}, {2048, 4269}, {3072, 32767}}));
  CHECK(c.code == 0);
  CHECK(c.problem == "ProjectedCSTypeGeoKey is 32767 (user-defined): no EPSG code");
  CHECK(epsg_from_geokeys(geokeys({{1024, 1}, {2048, 4269}})).code == 0);
  CHECK(epsg_from_geokeys(geokeys({{1024, 3}})).problem ==
        "the GeoTIFF keys give a geocentric model (no map coordinates)");
  CHECK(epsg_from_geokeys(geokeys({})).code == 0);
  // A projected model with only a geographic key: said as such (it said "no ... or
  // GeographicTypeGeoKey" beside one); GeoTIFF has no CRS code below 1024 (1-1023 obsolete).
  CHECK(epsg_from_geokeys(geokeys({{1024, 1}, {2048, 4326}})).problem ==
        "the GeoTIFF keys give a projected model without ProjectedCSTypeGeoKey");
  c = epsg_from_geokeys(geokeys({{3072, 1}}));
  CHECK(c.code == 0);
  CHECK(c.problem == "ProjectedCSTypeGeoKey is 1 (not an EPSG code)");
  CHECK(epsg_from_geokeys(geokeys({{3072, 1024}})).code == 1024);
  SECTION("cut short or too small: none") {
    const std::string whole = geokeys({{1024, 1}, {3072, 2154}});
    c = epsg_from_geokeys(whole.substr(0, whole.size() - 1));
    CHECK(c.code == 0);
    CHECK(c.problem == "GeoKey directory says 2 keys but holds 1 (cut short)");
    CHECK(epsg_from_geokeys("abc").problem == "GeoKey directory of 3 bytes (its header has 8)");
    // A key whose value is not inline (location 34736) is not read.
    std::string off = geokeys({{3072, 2154}});
    set<std::uint16_t>(&off, 10, 34736);
    CHECK(epsg_from_geokeys(off).code == 0);
  }
}

TEST_CASE("LAS CRS: files written here with a GeoKey directory, a WKT, both, none", "[las][crs]") {
  const std::string las = small_las();
  SECTION("no record: none, no note") {
    const LasCrs c = crs_of_file(las, "none.las");
    CHECK(c.epsg == 0);
    CHECK(c.code().empty());
    CHECK(c.note.empty());
  }
  SECTION("a GeoKey directory") {
    const LasCrs c =
        crs_of_file(with_vlr(las, "LASF_Projection", 34735, geokeys({{1024, 1}, {3072, 25832}})), "keys.las");
    CHECK(c.code() == "EPSG:25832");
    CHECK(c.from == "LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 25832");
    CHECK(c.note.empty());
  }
  SECTION("a WKT VLR (NUL-terminated, as the writers pad it)") {
    const LasCrs c =
        crs_of_file(with_vlr(las, "LASF_Projection", 2112, kLambert93 + std::string(3, '\0')), "wkt.las");
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.from == "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
  }
  SECTION("both, disagreeing: the global encoding's WKT bit says which, and a note says so") {
    const std::string both = with_vlr(with_vlr(las, "LASF_Projection", 34735, geokeys({{3072, 25832}})),
                                      "LASF_Projection", 2112, kLambert93);
    LasCrs c = crs_of_file(both, "both.las");  // canopy's writer sets the WKT bit
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.note ==
          "its LASF_Projection 2112 (OGC WKT) gives EPSG:2154, its LASF_Projection 34735 (GeoTIFF keys) "
          "EPSG:25832; the first taken (the global encoding's WKT bit is set)");
    std::string legacy = both;
    set<std::uint16_t>(&legacy, 6, 0);
    c = crs_of_file(legacy, "legacy.las");
    CHECK(c.code() == "EPSG:25832");
    // Before LAS 1.4 the bit is reserved: the GeoTIFF keys come first whatever it says.
    canopy::formats::LasHeaderBlock h;
    h.major = 1;
    h.minor = 3;
    h.global_encoding = 16;
    h.vlrs = {{"LASF_Projection", 34735, geokeys({{3072, 25832}})}, {"LASF_Projection", 2112, kLambert93}};
    CHECK(las_crs(h).code() == "EPSG:25832");
    h.minor = 4;
    CHECK(las_crs(h).code() == "EPSG:2154");
  }
  SECTION("a bad record beside a good one: the good one's code") {
    const std::string cut = geokeys({{3072, 25832}}).substr(0, 12);
    LasCrs c = crs_of_file(with_vlr(with_vlr(las, "LASF_Projection", 34735, cut), "liblas", 2112, kLambert93),
                           "mixed.las");
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.from == "liblas 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
  }
  SECTION("only malformed records: none, one line of note, the file still reads") {
    const LasCrs c =
        crs_of_file(with_vlr(with_vlr(las, "LASF_Projection", 34735, std::string("\1\0\1\0\0\0\7\0", 8)),
                             "LASF_Projection", 2112, kLambert93.substr(0, 300)),
                    "bad.las");
    CHECK(c.epsg == 0);
    CHECK(c.note ==
          "LASF_Projection 2112 (OGC WKT): the WKT is not well-formed (byte 300: GEOGCS not closed (cut "
          "short?)); LASF_Projection 34735 (GeoTIFF keys): GeoKey directory says 7 keys but holds 0 "
          "(cut short)");
    CHECK(c.note.find('\n') == std::string::npos);
  }
  SECTION("not LAS, missing, a directory: none") {
    const fs::path dir = canopy::test::fresh_dir("las", "crs_none");
    canopy::test::write_file((dir / "t.pcd").string(), "# .PCD v0.7\nFIELDS x\n");
    CHECK(read_las_crs((dir / "t.pcd").string()).epsg == 0);
    CHECK(read_las_crs((dir / "missing.las").string()).epsg == 0);
    CHECK(read_las_crs(dir.string()).epsg == 0);
    CHECK(read_las_crs("-").epsg == 0);
  }
}

TEST_CASE("LAS CRS: the LAS test files and the committed real tiles", "[las][crs]") {
  // perm-1.2_0.las: GeoKeys 3072 = 26915 and libLAS's WKT copy (NAD83 / UTM zone 15N).
  LasCrs c = read_las_crs(data("perm-1.2_0.las"));
  CHECK(c.code() == "EPSG:26915");
  CHECK(c.from == "LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 26915");
  CHECK(c.note.empty());
  // test1_4.las: a PROJCS (2903) holding a VERTCS whose AUTHORITY (5703) ends the text.
  CHECK(read_las_crs(data("test1_4.las")).code() == "EPSG:2903");
  // simple.copc.laz: COMPD_CS of NAD83 / Oregon LCC (m) (2991) and NAVD88 height (ftUS) (6360).
  CHECK(read_las_crs(data("simple.copc.laz")).code() == "EPSG:2991");
  // autzen-like garbage VLRs: no crash, none.
  CHECK(read_las_crs(data("garbage_nVariableLength.las")).epsg == 0);
  CHECK(read_las_crs(data("simple.laz")).epsg == 0);
  // The IGN LiDAR HD tile (LAZ, LAS 1.4 format 8, WKT bit set): its LASF_Projection 2112 WKT is
  // RGF93 v1 / Lambert-93, AUTHORITY["EPSG","2154"] (read by hand).
  c = read_las_crs(real("ign_lidarhd_870000_6618000.laz"));
  CHECK(c.code() == "EPSG:2154");
  CHECK(c.from == "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
  // The IGN Loiret forest plot (LAS 1.4 format 6): the same Lambert-93 WKT.
  CHECK(read_las_crs(real("forest_ign_loiret_crop2.laz")).code() == "EPSG:2154");
  // AHN3 Delft (RD New, EPSG:28992) and NEON: no CRS record in the files.
  c = read_las_crs(real("ahn3_delft_2.laz"));
  CHECK(c.epsg == 0);
  CHECK(c.note.empty());
  CHECK(read_las_crs(real("forest_neon_teak_043.laz")).epsg == 0);
}

TEST_CASE("LAS CRS: the shared development tiles, when present", "[las][crs]") {
  const fs::path laz = fs::path(CANOPY_REAL_DATA) / "laz";
  if (!fs::exists(laz / "forest_chablais3.laz")) {
    WARN("no " << laz.string() << ": the shared development tiles' CRS not checked");
    return;
  }
  auto crs = [&](const char* f) { return read_las_crs((laz / f).string()); };
  // GeoKeys only, one key: 3072 = 2154 (Lambert-93).
  CHECK(crs("forest_chablais3.laz").code() == "EPSG:2154");
  // GeoKeys 3072 = 26912 (NAD83 / UTM 12N).
  CHECK(crs("forest_mixedconifer.laz").code() == "EPSG:26912");
  // GeoKeys 3072 = 3005 (BC Albers) and a COMPD_CS WKT whose PROJCS says 3005 too.
  CHECK(crs("forest_bcts_1.laz").code() == "EPSG:3005");
  CHECK(crs("forest_bcts_1.laz").note.empty());
  // A WKT 2 PROJCRS with ID["EPSG",2154] (WKT bit set) and GeoKeys 3072 = 2154.
  CHECK(crs("las14_pf8_extra_bytes.laz").code() == "EPSG:2154");
  // A Leica COMPD_CS whose PROJCS "UTM_10N" names no code, and which one ']' too many closes
  // before its VERT_CS (byte 555): none, and the note says why.
  const LasCrs leica = crs("las14_pf6_classes_over_31.laz");
  CHECK(leica.epsg == 0);
  CHECK(
      leica.note ==
      "LASF_Projection 2112 (OGC WKT): the WKT is not well-formed (byte 555: text after the outermost node)");
  CHECK(crs("ahn3_delft_1.laz").epsg == 0);
}

TEST_CASE("LAS CRS: the GeoKey directory's linear unit, from the same walk", "[las][crs]") {
  CrsRecord r = read_geokeys(geokeys({{1024, 1}, {3072, 2154}, {3076, 9001}}));
  CHECK(r.code.code == 2154);
  REQUIRE(r.unit);
  CHECK(r.unit->name == "metre");
  CHECK(r.unit->metres == 1.0);
  CHECK(r.unit->source == "GeoTIFF key ProjLinearUnits = 9001");
  r = read_geokeys(geokeys({{3076, 9002}, {3072, 2229}}));
  REQUIRE(r.unit);
  CHECK(r.unit->name == "foot");
  CHECK(r.unit->metres == 0.3048);
  CHECK(r.code.code == 2229);  // keys in any order
  r = read_geokeys(geokeys({{3076, 9003}}));
  REQUIRE(r.unit);
  CHECK(r.unit->name == "US survey foot");
  CHECK(r.unit->metres == Approx(0.3048006096012192).epsilon(1e-15));
  CHECK(r.code.code == 0);  // a unit without a CRS code
  r = read_geokeys(geokeys({{3076, 9036}}));
  REQUIRE(r.unit);
  CHECK(r.unit->name == "EPSG unit 9036");
  CHECK(r.unit->metres == 0);
  // The first ProjLinearUnitsGeoKey; none without one.
  CHECK(read_geokeys(geokeys({{3076, 9002}, {3076, 9001}})).unit->name == "foot");
  CHECK_FALSE(read_geokeys(geokeys({{3072, 2154}})).unit);
  CHECK_FALSE(read_geokeys("abc").unit);
  SECTION("not inline: none") {
    std::string off = geokeys({{3076, 9002}});
    set<std::uint16_t>(&off, 10, 34736);  // location: another tag
    CHECK_FALSE(read_geokeys(off).unit);
    std::string two = geokeys({{3076, 9002}});
    set<std::uint16_t>(&two, 12, 2);  // count 2 at location 0: not a GeoTIFF key
    CHECK_FALSE(read_geokeys(two).unit);
  }
  SECTION("cut short: the unit of the keys it holds, no code") {
    const std::string whole = geokeys({{3076, 9002}, {3072, 2229}});
    r = read_geokeys(whole.substr(0, whole.size() - 1));
    CHECK(r.code.code == 0);
    CHECK(r.code.problem == "GeoKey directory says 2 keys but holds 1 (cut short)");
    REQUIRE(r.unit);
    CHECK(r.unit->name == "foot");
  }
}

TEST_CASE("LAS CRS: the WKT's linear unit is the projected CRS's own", "[las][crs]") {
  CrsRecord r = read_wkt(kLambert93);
  CHECK(r.code.code == 2154);
  REQUIRE(r.unit);
  CHECK(r.unit->name == "metre");
  CHECK(r.unit->metres == 1.0);
  CHECK(r.unit->source == R"(WKT UNIT["metre",1,AUTHORITY["EPSG","9001"]])");
  SECTION("a PROJCS holding a VERTCS after its own UNIT (test1_4.las): the PROJCS's, not the last") {
    r = read_wkt(
        R"w(PROJCS["NAD83(HARN) / New Mexico Central (ftUS)",GEOGCS["NAD83(HARN)",)w"
        R"w(UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],AUTHORITY["EPSG","4152"]],)w"
        R"w(UNIT["US survey foot",0.3048006096012192,AUTHORITY["EPSG","9003"]],AXIS["X",EAST],)w"
        R"w(AUTHORITY["EPSG","2903"],VERTCS["NAVD88",UNIT["US survey foot",1.0],AUTHORITY["EPSG","5703"]]])w");
    CHECK(r.code.code == 2903);
    REQUIRE(r.unit);
    CHECK(r.unit->name == "US survey foot");
    CHECK(r.unit->metres == 0.3048006096012192);
    CHECK(r.unit->source == R"(WKT UNIT["US survey foot",0.3048006096012192,AUTHORITY["EPSG","9003"]])");
  }
  SECTION("compound: the horizontal part's, never the vertical CRS's") {
    r = read_wkt(R"(COMPD_CS["x",PROJCS["p",UNIT["metre",1],AUTHORITY["EPSG","2991"]],)"
                 R"(VERT_CS["v",UNIT["US survey foot",0.304800609601219]]])");
    CHECK(r.code.code == 2991);
    REQUIRE(r.unit);
    CHECK(r.unit->name == "metre");
    // No code in the horizontal part: the compound's code, the horizontal part's unit.
    r = read_wkt(R"(COMPD_CS["x",PROJCS["p",UNIT["foot",0.3048]],VERT_CS["v"],AUTHORITY["EPSG","5698"]])");
    CHECK(r.code.code == 5698);
    REQUIRE(r.unit);
    CHECK(r.unit->name == "foot");
    CHECK(r.unit->source == R"(WKT UNIT["foot",0.3048])");
    r = read_wkt(
        R"(BOUNDCRS[SOURCECRS[PROJCRS["p",LENGTHUNIT["foot",0.3048],ID["EPSG",2229]]],TARGETCRS[GEOGCRS["w"]]])");
    CHECK(r.code.code == 2229);
    REQUIRE(r.unit);
    CHECK(r.unit->metres == 0.3048);
  }
  SECTION("WKT 2: the CS-wide LENGTHUNIT, else the first axis's; the base CRS's never") {
    r = read_wkt(
        R"(PROJCRS["p",BASEGEOGCRS["g",ELLIPSOID["e",6378137,298.25,LENGTHUNIT["metre",1]]],)"
        R"(CS[Cartesian,2],AXIS["x",east],AXIS["y",north],LENGTHUNIT["US survey foot",0.304800609601219],)"
        R"(ID["EPSG",2227]])");
    REQUIRE(r.unit);
    CHECK(r.unit->name == "US survey foot");
    r = read_wkt(
        R"(PROJCRS["p",BASEGEOGCRS["g",ANGLEUNIT["degree",0.0174532925199433]],CS[Cartesian,2],)"
        R"(AXIS["x",east,LENGTHUNIT["foot",0.3048]],AXIS["y",north,LENGTHUNIT["foot",0.3048]],ID["EPSG",2229]])");
    REQUIRE(r.unit);
    CHECK(r.unit->name == "foot");
    CHECK_FALSE(read_wkt(R"(PROJCRS["p",BASEGEOGCRS["g",LENGTHUNIT["metre",1]],ID["EPSG",2154]])").unit);
  }
  SECTION("none: geographic, no unit, a factor not a number > 0, not well-formed") {
    CHECK_FALSE(read_wkt(R"(GEOGCS["WGS 84",UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]])").unit);
    CHECK_FALSE(read_wkt(R"(PROJCS["x",AUTHORITY["EPSG","2154"]])").unit);
    for (const char* f : {"0", "-1", "abc", "0.3048x", "nan", "inf", "\"1\"x"}) {
      CHECK_FALSE(read_wkt(std::string(R"(PROJCS["x",UNIT["u",)") + f + "]]").unit);
    }
    CHECK_FALSE(read_wkt(R"(PROJCS["x",UNIT["u"]])").unit);
    CHECK_FALSE(read_wkt(kLambert93.substr(0, kLambert93.size() - 1)).unit);
  }
  SECTION("the source is one line of at most 200 bytes; so is the name") {
    r = read_wkt("PROJCS[\"x\",\n  UNIT [ \"US\tfoot\",\n    0.3048 ] ]");
    REQUIRE(r.unit);
    CHECK(r.unit->name == "US foot");
    CHECK(r.unit->source == R"(WKT UNIT [ "US foot", 0.3048 ])");
    r = read_wkt("PROJCS[\"x\",UNIT[\"a\x01\x1b[31mb\",0.3048]]");  // control bytes escaped
    REQUIRE(r.unit);
    CHECK(r.unit->name == "a\\x01\\x1b[31mb");
    CHECK(r.unit->source == "WKT UNIT[\"a\\x01\\x1b[31mb\",0.3048]");
    r = read_wkt(R"(PROJCS["x",UNIT[")" + std::string(500, 'f') + R"(",0.3048]])");
    REQUIRE(r.unit);
    CHECK(r.unit->name == std::string(200, 'f') + "...");
    CHECK(r.unit->source.size() == 4 + 200 + 3);
  }
}

TEST_CASE("LAS CRS: the unit of a header block follows the records' order", "[las][crs]") {
  canopy::formats::LasHeaderBlock h;
  h.major = 1;
  h.minor = 4;
  h.global_encoding = 16;
  h.vlrs = {{"LASF_Projection", 34735, geokeys({{3072, 2229}, {3076, 9002}})},
            {"LASF_Projection", 2112, kLambert93}};
  // The WKT bit: the WKT's code and unit.
  LasCrs c = las_crs(h);
  CHECK(c.code() == "EPSG:2154");
  REQUIRE(c.unit);
  CHECK(c.unit->name == "metre");
  CHECK(c.unit->source == R"(WKT UNIT["metre",1,AUTHORITY["EPSG","9001"]])");
  // Without it: the keys'.
  h.global_encoding = 0;
  c = las_crs(h);
  CHECK(c.code() == "EPSG:2229");
  REQUIRE(c.unit);
  CHECK(c.unit->name == "foot");
  // The first record giving no unit: the other's (here the code from the keys, the unit from
  // the WKT).
  h.vlrs[0] = {"LASF_Projection", 34735, geokeys({{3072, 2229}})};
  c = las_crs(h);
  CHECK(c.code() == "EPSG:2229");
  REQUIRE(c.unit);
  CHECK(c.unit->name == "metre");
  // libLAS's WKT copy serves like LASF_Projection's; another user's 2112 is not read.
  h.vlrs = {{"liblas", 2112, kLambert93}};
  CHECK(las_crs(h).unit->name == "metre");
  h.vlrs = {{"someone", 2112, kLambert93}};
  CHECK_FALSE(las_crs(h).unit);
  CHECK(las_crs(h).epsg == 0);
}

TEST_CASE("LAS CRS: the units of the LAS test files and the committed real tiles", "[las][crs]") {
  // perm-1.2_0.las: GeoKey 3076 = 9001.
  LasCrs c = read_las_crs(data("perm-1.2_0.las"));
  REQUIRE(c.unit);
  CHECK(c.unit->source == "GeoTIFF key ProjLinearUnits = 9001");
  // test1_4.las (and 1_4_w_evlr.las/.laz): NAD83(HARN) / New Mexico Central (ftUS), a WKT only;
  // the last UNIT of its text is its VERTCS's ("US survey foot", 1.0), which detect took until
  // stop 68 (then no feet warning).
  for (const char* f : {"test1_4.las", "1_4_w_evlr.las", "1_4_w_evlr.laz"}) {
    c = read_las_crs(data(f));
    REQUIRE(c.unit);
    CHECK(c.unit->name == "US survey foot");
    CHECK(c.unit->metres == 0.3048006096012192);
  }
  // simple.copc.laz: a COMPD_CS whose PROJCS is in metres, its VERT_CS in US survey feet.
  c = read_las_crs(data("simple.copc.laz"));
  REQUIRE(c.unit);
  CHECK(c.unit->name == "metre");
  CHECK(c.unit->metres == 1.0);
  CHECK_FALSE(read_las_crs(data("simple.las")).unit);
  c = read_las_crs(real("ign_lidarhd_870000_6618000.laz"));
  REQUIRE(c.unit);
  CHECK(c.unit->source == R"(WKT UNIT["metre",1,AUTHORITY["EPSG","9001"]])");
  CHECK_FALSE(read_las_crs(real("ahn3_delft_2.laz")).unit);
}

TEST_CASE("LAS CRS: the header block the point reader hands back is read_las_header_block's", "[las][crs]") {
  for (const std::string& f :
       {data("perm-1.2_0.las"), data("test1_4.las"), data("simple.copc.laz"), data("1_4_w_evlr.laz"),
        data("simple.las"), real("ign_lidarhd_870000_6618000.laz")}) {
    INFO(f);
    const LasHeaderBlock want = read_las_header_block(f);
    auto same = [&](const LasHeaderBlock& h) {
      CHECK(h.major == want.major);
      CHECK(h.minor == want.minor);
      CHECK(h.point_format == want.point_format);
      CHECK(h.global_encoding == want.global_encoding);
      REQUIRE(h.vlrs.size() == want.vlrs.size());
      for (std::size_t i = 0; i < h.vlrs.size(); ++i) {
        CHECK(h.vlrs[i].user_id == want.vlrs[i].user_id);
        CHECK(h.vlrs[i].record_id == want.vlrs[i].record_id);
        CHECK(h.vlrs[i].payload == want.vlrs[i].payload);
      }
      CHECK(h.evlrs.empty());  // no CRS EVLR in these files (their EVLRs: pylastest 42, copc 1000)
      CHECK(want.evlrs.empty());
      CHECK(h.evlr_note == want.evlr_note);
    };
    LasHeaderBlock h;
    const std::size_t n = read_las(f, {}, &h).size();
    same(h);
    LasHeaderBlock m;
    CHECK(parse_las(slurp(f), f, {}, &m).size() == n);
    same(m);
    std::optional<LasHeaderBlock> p;
    CHECK(read_points(f, "test", {}, &p).size() == n);
    REQUIRE(p);
    same(*p);
  }
  // Not LAS: none (and what a caller had is cleared).
  const fs::path dir = canopy::test::fresh_dir("las", "crs_handback");
  canopy::formats::PointCloud c;
  c.add("x", kFloat32).push_back(1);
  c.add("y", kFloat32).push_back(2);
  c.add("z", kFloat32).push_back(3);
  c.resize(1);
  write_pcd(c, (dir / "t.pcd").string());
  std::optional<LasHeaderBlock> p = LasHeaderBlock{};
  CHECK(read_points((dir / "t.pcd").string(), "test", {}, &p).size() == 1);
  CHECK_FALSE(p);
}

TEST_CASE("LAS CRS: a tile read from a FIFO gets its CRS and unit from the handed-back block", "[las][crs]") {
  const fs::path dir = canopy::test::fresh_dir("las", "crs_fifo");
  const std::string fifo = (dir / "tile").string();
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  // read_las_crs cannot read it again (the writer would block for ever): none.
  CHECK(read_las_crs(fifo).epsg == 0);
  REQUIRE(canopy::test::run("cat '" + data("test1_4.las") + "' > '" + fifo + "' &") == 0);
  std::optional<LasHeaderBlock> h;
  CHECK(read_points(fifo, "test", {}, &h).size() > 0);
  REQUIRE(h);
  const LasCrs c = las_crs(*h);
  CHECK(c.code() == "EPSG:2903");
  REQUIRE(c.unit);
  CHECK(c.unit->name == "US survey foot");
}

TEST_CASE("LAS CRS: is_epsg_code is the pattern EPSG:[1-9][0-9]{0,5}", "[las][crs]") {
  for (const char* ok : {"EPSG:1", "EPSG:2154", "EPSG:32633", "EPSG:999999", "EPSG:100000"}) {
    CHECK(is_epsg_code(ok));
  }
  for (const char* bad :
       {"", "EPSG:", "EPSG:0", "EPSG:02154", "EPSG:1234567", "epsg:2154", "EPSG: 2154", "EPSG:2154 ",
        " EPSG:2154", "EPSG:21a4", "EPSG:-1", "EPSG:+1", "ESRI:102100", "EPSG::2154", "Lambert-93", "EPSG"}) {
    CHECK_FALSE(is_epsg_code(bad));
  }
  // Every string of up to 7 characters after "EPSG:" over 0, 1, 9, a letter and a colon
  // (97 656), against the regex the index reader and collect --crs used until stop 68.
  const std::regex pattern("EPSG:[1-9][0-9]{0,5}");
  const std::string alphabet = "019a:";
  std::size_t n = 0, matched = 0;
  for (std::size_t len = 0; len <= 7; ++len) {
    std::vector<std::size_t> digit(len, 0);
    for (bool more = true; more;) {
      std::string s = "EPSG:";
      for (std::size_t d : digit) s += alphabet[d];
      const bool want = std::regex_match(s, pattern);
      if (is_epsg_code(s) != want) FAIL_CHECK(s);
      ++n;
      matched += want;
      more = false;
      for (std::size_t i = 0; i < len && !more; ++i) {
        if (++digit[i] < alphabet.size()) {
          more = true;
        } else {
          digit[i] = 0;
        }
      }
    }
  }
  CHECK(n == 97656);
  CHECK(matched == 728);  // 2 first digits, then 3 each: 2 (3^6 - 1) / 2
  // The codes las_crs writes are of that form.
  LasCrs c;
  c.epsg = 2154;
  CHECK(is_epsg_code(c.code()));
}

namespace {

// The header block of a file each way the readers give one: read_las_header_block(path),
// read_las's and parse_las's (the bytes in memory, as standard input and FIFOs are read) and
// read_points's; all the same (checked), the first returned.
LasHeaderBlock blocks_of(const std::string& path) {
  const LasHeaderBlock want = read_las_header_block(path);
  std::vector<LasHeaderBlock> got(3);
  read_las(path, {}, &got[0]);
  parse_las(slurp(path), path, {}, &got[1]);
  std::optional<LasHeaderBlock> p;
  read_points(path, "test", {}, &p);
  REQUIRE(p);
  got[2] = *p;
  for (const LasHeaderBlock& h : got) {
    CHECK(h.vlrs.size() == want.vlrs.size());
    REQUIRE(h.evlrs.size() == want.evlrs.size());
    for (std::size_t i = 0; i < h.evlrs.size(); ++i) {
      CHECK(h.evlrs[i].user_id == want.evlrs[i].user_id);
      CHECK(h.evlrs[i].record_id == want.evlrs[i].record_id);
      CHECK(h.evlrs[i].payload == want.evlrs[i].payload);
    }
    CHECK(h.evlr_note == want.evlr_note);
  }
  return want;
}

// `bytes` written to <test tmp>/las/<dir_name>/<name>/<name> (a directory of its own).
std::string write_tile(const std::string& dir_name, const std::string& name, const std::string& bytes) {
  const fs::path dir = canopy::test::fresh_dir("las", dir_name + "/" + name);
  const std::string p = (dir / name).string();
  canopy::test::write_file(p, bytes);
  return p;
}

std::string error_of_read(const std::string& path) {
  try {
    read_las(path);
  } catch (const canopy::common::DataError& e) { return e.what(); }
  return "";
}

}  // namespace

TEST_CASE("LAS CRS: a WKT or GeoKey directory in an EVLR (LAS 1.4 R15 2.6)", "[las][crs][evlr]") {
  const std::string las = small_las();  // 1.4, WKT bit, points at 375, 10 x 30 bytes, no EVLR
  SECTION("the WKT only in an EVLR: its code and unit, each reader's block the same") {
    const std::string p = write_tile(
        "crs_evlr", "wkt.las", with_evlr(las, "LASF_Projection", 2112, kLambert93 + std::string(2, '\0')));
    CHECK(read_las(p).size() == 10);
    const LasHeaderBlock h = blocks_of(p);
    CHECK(h.vlrs.empty());
    REQUIRE(h.evlrs.size() == 1);
    CHECK(h.evlr_note.empty());
    for (const LasCrs& c : {las_crs(h), read_las_crs(p)}) {
      CHECK(c.code() == "EPSG:2154");
      CHECK(c.from == "EVLR LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
      CHECK(c.note.empty());
      REQUIRE(c.unit);
      CHECK(c.unit->name == "metre");
      CHECK(c.unit->metres == 1.0);
    }
  }
  SECTION("the GeoKey directory only in an EVLR, in feet; other EVLRs beside it are skipped") {
    std::string b = with_evlr(las, "pylastest", 42, std::string(16, 'x'));
    b = with_evlr(b, "someone", 2112, kLambert93);  // not a CRS record las_crs reads
    b = with_evlr(b, "LASF_Projection", 34735, geokeys({{1024, 1}, {3072, 2229}, {3076, 9002}}));
    b = with_evlr(b, "LASF_Projection", 34735, geokeys({{3072, 25832}}));  // the first of a kind only
    const std::string p = write_tile("crs_evlr", "keys.las", b);
    const LasHeaderBlock h = blocks_of(p);
    REQUIRE(h.evlrs.size() == 1);
    const LasCrs c = read_las_crs(p);
    CHECK(c.code() == "EPSG:2229");
    CHECK(c.from == "EVLR LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 2229");
    REQUIRE(c.unit);
    CHECK(c.unit->name == "foot");
  }
  SECTION("a VLR and an EVLR: the VLR's code; another code in the EVLR is noted") {
    const std::string keys = with_vlr(las, "LASF_Projection", 34735, geokeys({{3072, 25832}}));
    LasCrs c =
        read_las_crs(write_tile("crs_evlr", "both.las", with_evlr(keys, "LASF_Projection", 2112, kLambert93)));
    CHECK(c.code() == "EPSG:25832");
    CHECK(c.from == "LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 25832");
    CHECK(
        c.note ==
        "its LASF_Projection 34735 (GeoTIFF keys) gives EPSG:25832, its EVLR LASF_Projection 2112 (OGC WKT) "
        "EPSG:2154; the first taken (a VLR before an EVLR)");
    // The same code in both: no note.
    const std::string same = with_vlr(las, "LASF_Projection", 2112, kLambert93);
    c = read_las_crs(write_tile("crs_evlr", "same.las",
                                with_evlr(same, "LASF_Projection", 34735, geokeys({{3072, 2154}}))));
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.from == "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
    CHECK(c.note.empty());
    // A VLR giving no code (a WKT cut short): the EVLR's.
    const std::string cut = with_vlr(las, "LASF_Projection", 2112, kLambert93.substr(0, 300));
    c = read_las_crs(write_tile("crs_evlr", "cut_vlr.las",
                                with_evlr(cut, "LASF_Projection", 34735, geokeys({{3072, 2154}}))));
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.from == "EVLR LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 2154");
    CHECK(c.note.empty());
    // Two EVLRs disagreeing: the WKT bit says which, as for VLRs.
    std::string two = with_evlr(las, "LASF_Projection", 34735, geokeys({{3072, 25832}}));
    two = with_evlr(two, "liblas", 2112, kLambert93);
    c = read_las_crs(write_tile("crs_evlr", "two.las", two));
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.note ==
          "its EVLR liblas 2112 (OGC WKT) gives EPSG:2154, its EVLR LASF_Projection 34735 (GeoTIFF keys) "
          "EPSG:25832; the first taken (the global encoding's WKT bit is set)");
  }
  SECTION("a CRS EVLR over 1 MiB: not read, a note; the points read") {
    std::string big = kLambert93;
    big.resize(kLasCrsEvlrBytes + 1, '\0');
    const std::string p = write_tile("crs_evlr", "big.las", with_evlr(las, "LASF_Projection", 2112, big));
    CHECK(read_las(p).size() == 10);
    const LasHeaderBlock h = blocks_of(p);
    CHECK(h.evlrs.empty());
    const std::string note =
        "EVLR 1 (LASF_Projection 2112) of 1048577 bytes is over the 1048576 canopy reads of a CRS record: "
        "not read";
    CHECK(h.evlr_note == note);
    const LasCrs c = las_crs(h);
    CHECK(c.epsg == 0);
    CHECK(c.note == note);
    // A VLR naming a code: that code, no note.
    const std::string q = write_tile("crs_evlr", "big_vlr.las",
                                     with_evlr(with_vlr(las, "LASF_Projection", 34735, geokeys({{3072, 2154}})),
                                               "LASF_Projection", 2112, big));
    CHECK(read_las_crs(q).code() == "EPSG:2154");
    CHECK(read_las_crs(q).note.empty());
  }
  SECTION("EVLRs not in the file: the point reader's error naming the file; read_las_crs a note") {
    for (const bool vlr : {false, true}) {
      // Without, then with a GeoKey VLR naming a code: then the code, no note.
      const std::string base = vlr ? with_vlr(las, "LASF_Projection", 34735, geokeys({{3072, 25832}})) : las;
      const std::size_t data_end = get<std::uint32_t>(base, 96) + 10 * 30;
      const std::string good = with_evlr(base, "LASF_Projection", 2112, kLambert93);
      std::string inside = good, count = good;
      set<std::uint64_t>(&inside, 235, data_end - 30);  // inside the last point record
      set<std::uint32_t>(&count, 243, 4000000000u);
      const std::vector<std::vector<std::string>> bad = {
          {"cut.las", good.substr(0, good.size() - 10),
           "EVLR 1 of " + std::to_string(kLambert93.size()) + " bytes runs past the end of the file"},
          {"huge.las", with_evlr(base, "LASF_Projection", 2112, kLambert93, std::uint64_t(1) << 62),
           "EVLR 1 of 4611686018427387904 bytes runs past the end of the file"},
          {"inside.las", inside,
           "EVLR start " + std::to_string(data_end - 30) + " is not between the end of the point data (" +
               std::to_string(data_end) + ") and the end of the file (" + std::to_string(good.size()) + ")"},
          {"count.las", count,
           "LAS header says 4000000000 EVLRs but EVLR 2 does not fit in the file (truncated or broken "
           "count)"},
      };
      for (const auto& b : bad) {
        INFO(b[0] << (vlr ? " with a VLR" : ""));
        const std::string p = write_tile("crs_evlr_bad", b[0], b[1]);
        CHECK(error_of_read(p) == p + ": " + b[2]);
        const LasHeaderBlock h = read_las_header_block(p);
        CHECK(h.evlr_note == "EVLRs not read: " + b[2]);
        const LasCrs c = read_las_crs(p);
        if (vlr) {
          CHECK(c.code() == "EPSG:25832");
          // The count case walked the first EVLR (the WKT) before the problem: kept, and noted.
          CHECK(c.note == (b[0] == "count.las"
                               ? "its LASF_Projection 34735 (GeoTIFF keys) gives EPSG:25832, its "
                                 "EVLR LASF_Projection 2112 (OGC WKT) EPSG:2154; the first taken "
                                 "(a VLR before an EVLR)"
                               : ""));
        } else if (b[0] == "count.las") {
          CHECK(c.code() == "EPSG:2154");
          CHECK(c.note.empty());
        } else {
          CHECK(c.epsg == 0);
          CHECK(c.note == "EVLRs not read: " + b[2]);
        }
      }
    }
  }
}

TEST_CASE("LAS CRS: a WKT EVLR in a LAZ file (1_4_w_evlr.laz) and its LAS twin", "[las][crs][evlr][laz]") {
  // 1_4_w_evlr.laz/.las (LAS 1.4 format 6, WKT bit): VLRs LASF_Projection 2112 and liblas 2112
  // (NAD83(HARN) / New Mexico Central (ftUS), EPSG:2903), then one EVLR "pylastest" 42 of 16
  // bytes ending the file (python3 struct by hand). Here the two VLRs' record ids are made 2111
  // (no longer CRS records) and Lambert-93's WKT is appended as a second EVLR.
  auto moved = [](std::string b) {
    std::size_t pos = get<std::uint16_t>(b, 94);
    for (std::uint32_t i = 0; i < get<std::uint32_t>(b, 100); ++i) {
      if (get<std::uint16_t>(b, pos + 18) == 2112) set<std::uint16_t>(&b, pos + 18, 2111);
      pos += 54 + get<std::uint16_t>(b, pos + 20);
    }
    return with_evlr(b, "LASF_Projection", 2112, kLambert93);
  };
  const std::string laz = slurp(data("1_4_w_evlr.laz")), las = slurp(data("1_4_w_evlr.las"));
  REQUIRE(get<std::uint32_t>(laz, 243) == 1);
  REQUIRE(get<std::uint32_t>(las, 243) == 1);
  CHECK(read_las_crs(data("1_4_w_evlr.laz")).code() == "EPSG:2903");  // the VLRs', as before
  const std::string z = write_tile("crs_evlr_laz", "evlr.laz", moved(laz));
  const std::string s = write_tile("crs_evlr_laz", "evlr.las", moved(las));
  // The LAZ decodes to the LAS byte for byte (as 1_4_w_evlr.laz does), EVLRs included.
  CHECK(laz_to_las(slurp(z), z) == slurp(s));
  for (const std::string& p : {z, s}) {
    INFO(p);
    CHECK(read_las(p).size() == 1000);
    const LasHeaderBlock h = blocks_of(p);
    REQUIRE(h.evlrs.size() == 1);
    CHECK(h.evlrs[0].payload == kLambert93);
    const LasCrs c = read_las_crs(p);
    CHECK(c.code() == "EPSG:2154");
    CHECK(c.from == "EVLR LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
    REQUIRE(c.unit);
    CHECK(c.unit->name == "metre");
  }
  SECTION("the LAZ's EVLR cut short, or its count too large: the reader's error, a note") {
    const std::string whole = moved(laz);
    const std::string cut = write_tile("crs_evlr_laz", "cut.laz", whole.substr(0, whole.size() - 10));
    const std::string why =
        "EVLR 2 of " + std::to_string(kLambert93.size()) + " bytes runs past the end of the file";
    CHECK(error_of_read(cut) == cut + ": " + why);
    LasCrs c = read_las_crs(cut);
    CHECK(c.epsg == 0);
    CHECK(c.note == "EVLRs not read: " + why);
    std::string b = whole;
    set<std::uint32_t>(&b, 243, 3);
    const std::string three = write_tile("crs_evlr_laz", "three.laz", b);
    const std::string count =
        "LAS header says 3 EVLRs but EVLR 3 does not fit in the file (truncated or broken count)";
    CHECK(error_of_read(three) == three + ": " + count);
    c = read_las_crs(three);  // the WKT, walked before the problem
    CHECK(c.code() == "EPSG:2154");
    CHECK(read_las_header_block(three).evlr_note == "EVLRs not read: " + count);
    // The first EVLR's offset before the point data: the LAZ reader's own message.
    b = whole;
    set<std::uint64_t>(&b, 235, 100);
    const std::string before = write_tile("crs_evlr_laz", "before.laz", b);
    CHECK(error_of_read(before) ==
          before + ": EVLR start 100 is not between the point data and the end of the file (" +
              std::to_string(b.size()) + " bytes)");
    CHECK(read_las_crs(before).note == "EVLRs not read: EVLR start 100 is not between the point data (" +
                                           std::to_string(get<std::uint32_t>(b, 96)) +
                                           ") and the end of the file (" + std::to_string(b.size()) + ")");
  }
}

TEST_CASE("LAS CRS: a tile with its CRS in an EVLR, read from a FIFO", "[las][crs][evlr]") {
  const fs::path dir = canopy::test::fresh_dir("las", "crs_evlr_fifo");
  const std::string file = (dir / "t.las").string();
  canopy::test::write_file(file, with_evlr(small_las(), "LASF_Projection", 2112, kLambert93));
  const std::string fifo = (dir / "tile").string();
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(read_las_crs(fifo).epsg == 0);  // not read again
  REQUIRE(canopy::test::run("cat '" + file + "' > '" + fifo + "' &") == 0);
  std::optional<LasHeaderBlock> h;
  CHECK(read_points(fifo, "test", {}, &h).size() == 10);
  REQUIRE(h);
  const LasCrs c = las_crs(*h);
  CHECK(c.code() == "EPSG:2154");
  CHECK(c.from == "EVLR LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
}
