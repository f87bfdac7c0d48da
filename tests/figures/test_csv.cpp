// parse_scores_csv: header-named columns in any order, missing values, errors naming the line.
#include <catch2/catch.hpp>

#include <cmath>

#include "canopy/common/error.h"
#include "figures/figures.h"

using namespace canopy;
using namespace canopy::figures;

TEST_CASE("scores CSV: columns by header name, missing values, comments") {
  const auto rows = parse_scores_csv(
      "# comment\nscene,object,rank,noise_mm,score,entropy,extra\n"
      "circle,tank,1,0,0.91,0.5,x\r\n"
      "\n"
      "\"flyby\",sedan,,32,nan,,y\n",
      "s.csv");
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].object == "tank");
  CHECK(rows[0].scene == "circle");
  CHECK(rows[0].noise_mm == 0);
  CHECK(rows[0].score == Approx(0.91));
  CHECK(rows[0].rank == 1);
  CHECK(rows[0].entropy == Approx(0.5));
  CHECK(rows[1].scene == "flyby");
  CHECK(rows[1].noise_mm == 32);
  CHECK(std::isnan(rows[1].score));
  CHECK(rows[1].rank == 0);
  CHECK(std::isnan(rows[1].entropy));
}

TEST_CASE("scores CSV: bad input is a DataError naming the file and line") {
  auto message = [](const std::string& text) {
    try {
      parse_scores_csv(text, "s.csv");
    } catch (const common::DataError& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  CHECK(message("").find("s.csv") != std::string::npos);
  CHECK(message("object,scene,noise_mm\n").find("'score'") != std::string::npos);
  CHECK(message("object,scene,noise_mm,score\ntank,circle,4,high\n").find("line 2") != std::string::npos);
  CHECK(message("object,scene,noise_mm,score\ntank,circle,,0.5\n").find("noise_mm") != std::string::npos);
  CHECK(message("object,scene,noise_mm,score\ntank,circle\n").find("line 2") != std::string::npos);
}

TEST_CASE("scores CSV: other columns (scene experiment tables), summary rows left out") {
  PlotColumns c;
  c.x = "cover_lo";
  c.y = "recognition";
  c.series = "noise_mm";
  c.panel = "";
  c.strict = false;
  const auto rows = parse_scores_csv(
      "cover_lo,cover_hi,noise_mm,true,recognition\n"
      "0,0.25,all,4,0.75\n"
      "0.25,0.5,all,2,\n"
      "0,0.25,8,2,0.5\n",
      "cover_bins.csv", c);
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].object == "all");
  CHECK(rows[0].scene.empty());
  CHECK(rows[0].noise_mm == 0);
  CHECK(rows[0].score == Approx(0.75));
  CHECK(rows[1].noise_mm == Approx(0.25));
  CHECK(std::isnan(rows[1].score));
  CHECK(rows[2].object == "8");
  CHECK(rows[2].score == Approx(0.5));
  CHECK(rows[2].rank == 0);

  // x = noise_mm of the summary table: the noise "all" rows are summaries, left out.
  PlotColumns n;
  n.y = "recall";
  n.series = "cover";
  n.panel = "";
  n.strict = false;
  const auto s = parse_scores_csv(
      "cover,noise_mm,recall\nall,all,0.9\nall,0,1\nlight,all,0.8\nlight,32,0.5\n", "summary.csv", n);
  REQUIRE(s.size() == 2);
  CHECK(s[0].object == "all");
  CHECK(s[0].noise_mm == 0);
  CHECK(s[1].object == "light");
  CHECK(s[1].noise_mm == 32);
  CHECK(s[1].score == Approx(0.5));

  // The default (strict) reading still refuses text where a number belongs.
  CHECK_THROWS_AS(parse_scores_csv("object,scene,noise_mm,score\ntank,circle,all,0.5\n", "s.csv"),
                  common::DataError);
  // A column that is not there is named.
  c.y = "precision";
  try {
    parse_scores_csv("cover_lo,noise_mm,recognition\n0,all,1\n", "b.csv", c);
    FAIL("no error");
  } catch (const common::DataError& e) {
    CHECK(std::string(e.what()).find("'precision'") != std::string::npos);
  }
}

TEST_CASE(
    "series colours: 16 table colours pairwise distinct, then generated ones, for any number of series") {
  auto distance = [](const std::array<std::uint8_t, 3>& a, const std::array<std::uint8_t, 3>& b) {
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
    return std::sqrt(d);
  };
  // The thesis's five objects keep ColorBrewer Dark2's first five (unchanged figures).
  CHECK(series_colour(0) == std::array<std::uint8_t, 3>{27, 158, 119});
  CHECK(series_colour(4) == std::array<std::uint8_t, 3>{102, 166, 30});
  // Twelve vehicle classes (and four more) get clearly different colours, none white or black.
  for (std::size_t i = 0; i < 16; ++i) {
    CHECK(distance(series_colour(i), {255, 255, 255}) > 60);
    CHECK(distance(series_colour(i), {0, 0, 0}) > 60);
    for (std::size_t j = 0; j < i; ++j) {
      INFO(i << " vs " << j);
      CHECK(distance(series_colour(i), series_colour(j)) >= 60);
    }
  }
  // Beyond the table: still distinct from each other and from the table.
  for (std::size_t i = 16; i < 48; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      INFO(i << " vs " << j);
      CHECK(series_colour(i) != series_colour(j));
    }
  }
}
