#include "addnoise/addnoise.h"

#include "canopy/common/error.h"
#include "canopy/common/rng.h"

namespace canopy::addnoise {

void validate(const Params& params) {
  if (!(params.sigma >= 0 && params.sigma <= 100)) throw common::UsageError("--sigma must be in [0, 100m]");
}

void apply(const Params& params, formats::PointCloud* scan) {
  if (params.sigma == 0.0) return;
  common::Rng rng(common::derive_seed(params.seed, "addnoise"));
  auto& x = scan->col("x");
  auto& y = scan->col("y");
  auto& z = scan->col("z");
  for (std::size_t i = 0; i < scan->size(); ++i) {
    x[i] += params.sigma * rng.normal();
    y[i] += params.sigma * rng.normal();
    z[i] += params.sigma * rng.normal();
  }
}

Outputs run(const Params& params, const Inputs& inputs) {
  formats::PointCloud out = *inputs.scan;
  apply(params, &out);
  return out;
}

}  // namespace canopy::addnoise
