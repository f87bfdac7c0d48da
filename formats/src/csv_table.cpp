#include "canopy/formats/csv_table.h"

#include <cstdio>
#include <sstream>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::formats {

std::map<std::string, ThesisRow> parse_thesis_csv(const std::string& text, const std::string& name) {
  std::map<std::string, ThesisRow> rows;
  std::istringstream ss(text);
  std::string line;
  int lineno = 0;
  while (std::getline(ss, line)) {
    ++lineno;
    if (lineno == 1 || line.empty()) continue;
    std::vector<std::string> f;
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) f.push_back(cell);
    if (f.size() != 6)
      throw common::DataError(name, "line " + std::to_string(lineno) + ": expected 6 columns");
    try {
      rows[f[0] + "/" + f[1] + "/" + f[2]] = {std::stod(f[3]), std::stoi(f[4]), std::stod(f[5])};
    } catch (const std::exception&) {
      throw common::DataError(name, "line " + std::to_string(lineno) + ": not a number");
    }
  }
  return rows;
}

std::string format_number(const char* printf_format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, v);
  return buf;
}

}  // namespace canopy::formats
