// The figures' parameter ranges (the CLI's options; figures.h).
#include "canopy/common/error.h"
#include "figures/figures.h"

namespace canopy::figures {
namespace {

void check_size(int w, int h) {
  if (w < 16 || h < 16 || w > 8192 || h > 8192) {
    throw common::UsageError("--width/--height must be within [16, 8192] pixels");
  }
}

}  // namespace

void validate(const MeshView& view) {
  check_size(view.width, view.height);
  if (!(view.elevation_deg > -90 && view.elevation_deg < 90)) {
    throw common::UsageError("--elevation must be within (-90, 90) degrees");
  }
  if (!(view.box[0] > 0 && view.box[1] > 0 && view.box[2] > 0)) {
    throw common::UsageError("--box-length/--box-width/--box-height must be positive");
  }
}

void validate(const GridParams& params) {
  if (params.cols < 1) throw common::UsageError("--cols must be at least 1");
  if (params.font_size < 4 || params.font_size > 200) throw common::UsageError("--font-size: 4..200");
  if (params.gap < 0 || params.gap > 1000) throw common::UsageError("--gap: 0..1000");
  if (params.margin < 0 || params.margin > 1000) throw common::UsageError("--margin: 0..1000");
}

void validate(const PlotParams& params) { check_size(params.width, params.height); }

}  // namespace canopy::figures
