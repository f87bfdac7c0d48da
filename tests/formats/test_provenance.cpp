// formats/provenance.h: the one provenance comment format of every tool's PCD/PLY/LAS output.
#include <catch2/catch.hpp>

#include "canopy/formats/pcd.h"
#include "canopy/formats/provenance.h"

using namespace canopy;

TEST_CASE("provenance_comments: tool line, one line per parameter, one per input") {
  const formats::Provenance p{
      "cocone", "0.1.0", {{"flat-angle", "60deg"}, {"keep-orphans", ""}}, {"a.pcd", "b.pcd"}};
  CHECK(formats::provenance_comments(p) ==
        std::vector<std::string>{"cocone (canopy) 0.1.0", "parameter flat-angle = 60deg",
                                 "parameter keep-orphans = ", "input a.pcd", "input b.pcd"});
  CHECK(formats::provenance_comments({"pcd2ply", "0.1.0", {}, {}}) ==
        std::vector<std::string>{"pcd2ply (canopy) 0.1.0"});
}
