// The classes of models (documents/model_classes.h).
#include "canopy/documents/model_classes.h"

#include "canopy/common/error.h"
#include "canopy/formats/text_lines.h"

namespace canopy::documents {

std::map<std::string, std::string> parse_model_classes(const std::string& text, const std::string& name) {
  auto valid = [](const std::string& c) {
    if (c.empty() || c.size() > 64) return false;
    for (char ch : c)
      if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '-')) return false;
    return true;
  };
  std::map<std::string, std::string> classes;
  bool header = false;
  for (const formats::TextLine& l : formats::text_lines(text)) {
    // A line is one word "model,class"; words split at blanks are put back for the message.
    std::string line = l.words[0];
    for (std::size_t i = 1; i < l.words.size(); ++i) line += " " + l.words[i];
    const std::string where = "line " + std::to_string(l.number) + ": ";
    const std::size_t comma = line.find(',');
    if (comma == std::string::npos || line.find(',', comma + 1) != std::string::npos)
      throw common::DataError(name, where + "expected 'model,class', got '" + line.substr(0, 80) + "'");
    const std::string model = line.substr(0, comma), cls = line.substr(comma + 1);
    if (!header) {
      if (model != "model" || cls != "class")
        throw common::DataError(name, where + "the first line must be the header 'model,class'");
      header = true;
      continue;
    }
    if (model.empty() || model.size() > 128)
      throw common::DataError(name, where + "empty or over-long model name");
    if (!valid(cls))
      throw common::DataError(
          name, where + "class '" + cls.substr(0, 80) + "' is not 1-64 characters of [a-z0-9-]");
    if (!classes.emplace(model, cls).second)
      throw common::DataError(name, where + "model '" + model + "' given twice");
  }
  if (!header) throw common::DataError(name, "no header line 'model,class'");
  return classes;
}

}  // namespace canopy::documents
