#include "canopy/documents/tile_list.h"

#include <cmath>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/formats/text_lines.h"

namespace canopy::documents {

std::vector<TileListEntry> parse_tile_list(const std::string& text, const std::string& name) {
  std::vector<TileListEntry> tiles;
  for (const formats::TextLine& line : formats::text_lines(text)) {
    const std::vector<std::string>& words = line.words;
    const std::string where = "line " + std::to_string(line.number);
    if (words.size() < 2 || words.size() > 4) {
      throw common::DataError(name, where + ": expected DETECTIONS TRUTH [NOISE_MM [COVER]]");
    }
    TileListEntry t;
    t.detections = words[0];
    t.truth = words[1];
    if (words.size() >= 3) {
      std::size_t used = 0;
      double noise = std::nan("");
      try {
        noise = std::stod(words[2], &used);
      } catch (const std::exception&) { used = 0; }
      if (used != words[2].size() || !(noise >= 0 && noise < 1e6)) {
        throw common::DataError(name, where + ": noise '" + words[2] + "' is not a number of millimetres");
      }
      t.noise_mm = noise;
    }
    if (words.size() == 4) t.cover = words[3];
    if (tiles.size() >= kMaxTileListEntries) {
      throw common::DataError(name, "more than " + std::to_string(kMaxTileListEntries) + " tiles");
    }
    tiles.push_back(std::move(t));
  }
  if (tiles.empty()) throw common::DataError(name, "lists no tiles");
  return tiles;
}

std::string write_tile_list(const std::vector<TileListEntry>& tiles) {
  std::ostringstream out;
  out.precision(17);  // every noise level read back exactly (6 digits rounded 999999.5 to 1e+06)
  for (const TileListEntry& t : tiles) {
    out << t.detections << ' ' << t.truth;
    if (!std::isnan(t.noise_mm)) out << ' ' << t.noise_mm;
    if (!t.cover.empty()) out << ' ' << t.cover;
    out << '\n';
  }
  return out.str();
}

}  // namespace canopy::documents
