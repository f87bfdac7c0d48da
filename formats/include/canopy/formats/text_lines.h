// Line-oriented text files of words (the manifests make writes, documents/tile_list.h and
// documents/experiment_manifest.h): each line split at blanks (spaces, tabs, a final "\r"),
// '#' starts a comment to the end of the line, lines left without words skipped.
#pragma once

#include <string>
#include <vector>

namespace canopy::formats {

struct TextLine {
  int number = 0;                  // 1-based line number in the text
  std::vector<std::string> words;  // at least one
};

std::vector<TextLine> text_lines(const std::string& text);

}  // namespace canopy::formats
