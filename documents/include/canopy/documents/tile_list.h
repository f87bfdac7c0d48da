// The scene experiment's tile list (mk/scenes.mk writes $(SCENE_DIR)/tiles.txt at parse time;
// `score --tiles` reads it): one tile a line, "DETECTIONS TRUTH [NOISE_MM [COVER]]", blanks
// between fields (no path holds one), '#' starts a comment, blank lines skipped. Paths as
// written (relative to the working directory). Every refusal is a common::DataError naming the
// file and the line.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace canopy::documents {

struct TileListEntry {
  std::string detections, truth;                               // paths
  double noise_mm = std::numeric_limits<double>::quiet_NaN();  // NaN = not given
  std::string cover;                                           // "" = not given
};

// At most this many tiles (a list beyond it is refused).
inline constexpr std::size_t kMaxTileListEntries = 100000;

// The list in `text` (of file `name`); at least one tile.
std::vector<TileListEntry> parse_tile_list(const std::string& text, const std::string& name);
// Its text, one line a tile (noise written when given, cover when given; a cover needs a noise).
std::string write_tile_list(const std::vector<TileListEntry>& tiles);

}  // namespace canopy::documents
