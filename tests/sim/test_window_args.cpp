// POV-Ray's render-window options for a run (povray_run.h window_args): 1-based and inclusive,
// none for the whole image, never a value POV-Ray would read as a fraction of the image.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "canopy/sim/povray_run.h"

using canopy::sim::FrameRange;
using canopy::sim::window_args;
using Args = std::vector<std::string>;

namespace {

FrameRange range(int w, int h, int c0, int c1, int r0, int r1) {
  FrameRange r;
  r.width = w;
  r.height = h;
  r.col0 = c0;
  r.col1 = c1;
  r.row0 = r0;
  r.row1 = r1;
  return r;
}

}  // namespace

TEST_CASE("window_args: 1-based inclusive pixels, nothing for the whole image") {
  CHECK(window_args(range(512, 512, -1, -1, -1, -1)).empty());  // no window
  CHECK(window_args(range(512, 512, 0, 511, 0, 511)).empty());  // the whole image
  CHECK(window_args(range(512, 512, 0, 600, 0, 900)).empty());  // clipped: the whole image
  CHECK(window_args(range(512, 512, 186, 325, 88, 423)) == Args{"+SC187", "+EC326", "+SR89", "+ER424"});
  CHECK(window_args(range(512, 256, 0, 10, 100, 255)) == Args{"+SC1", "+EC11", "+SR101", "+ER256"});
}

TEST_CASE("window_args: at least 2 pixels a side, so no end is ever 1 (POV-Ray: 100 %)") {
  CHECK(window_args(range(64, 64, 0, 0, 0, 0)) == Args{"+SC1", "+EC2", "+SR1", "+ER2"});
  CHECK(window_args(range(64, 64, 63, 63, 30, 30)) == Args{"+SC63", "+EC64", "+SR31", "+ER32"});
  CHECK(window_args(range(64, 64, 20, 10, 5, 5)) == Args{"+SC21", "+EC22", "+SR6", "+ER7"});  // empty: widened
  CHECK(window_args(range(1, 1, 0, 0, 0, 0)).empty());  // a 1-pixel image is traced whole
}
