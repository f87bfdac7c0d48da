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
    } catch (const common::DataError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message("").find("s.csv") != std::string::npos);
  CHECK(message("object,scene,noise_mm\n").find("'score'") != std::string::npos);
  CHECK(message("object,scene,noise_mm,score\ntank,circle,4,high\n").find("line 2") != std::string::npos);
  CHECK(message("object,scene,noise_mm,score\ntank,circle,,0.5\n").find("noise_mm") != std::string::npos);
  CHECK(message("object,scene,noise_mm,score\ntank,circle\n").find("line 2") != std::string::npos);
}
