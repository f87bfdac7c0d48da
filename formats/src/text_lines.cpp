#include "canopy/formats/text_lines.h"

#include <sstream>

namespace canopy::formats {

std::vector<TextLine> text_lines(const std::string& text) {
  std::vector<TextLine> lines;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream ls(line);
    TextLine t;
    t.number = number;
    for (std::string w; ls >> w;) t.words.push_back(std::move(w));
    if (!t.words.empty()) lines.push_back(std::move(t));
  }
  return lines;
}

}  // namespace canopy::formats
