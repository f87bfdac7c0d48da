// rangetrace's scene-recipe parser (single-vehicle scenes and tiles): parse_scene on the bytes
// must return a recipe within the documented bounds or throw common::Error naming the recipe.
// Any other exception, crash, sanitizer report or allocation over -malloc_limit_mb is a
// finding. Nothing is rendered (no POV-Ray). Seeds: share/scenes/*.scene (fuzz/run.sh).
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "rangetrace/rangetrace.h"
#include "rangetrace/tile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  canopy::rangetrace::SceneRecipe s;
  try {
    s = canopy::rangetrace::parse_scene(text, "fuzz.scene");
  } catch (const canopy::common::Error& e) {
    if (std::string(e.what()).find("fuzz.scene") == std::string::npos) std::abort();
    return 0;
  }
  if (s.views.size() > 10000 || s.foliage_count < 0 || s.foliage_count > 100000) std::abort();
  if (s.tile) {
    const auto& t = *s.tile;
    if (!s.views.empty()) std::abort();  // a tile refuses the single-vehicle keys
    if (!(t.extent_x >= 5 && t.extent_x <= 100 && t.extent_y >= 5 && t.extent_y <= 100)) std::abort();
    if (t.random_vehicles < 0 || t.random_vehicles > 200) std::abort();
    if (!(t.spacing > 0) || !(t.canopy_spacing > 0) || t.flight_lines < 1) std::abort();
  }
  return 0;
}
