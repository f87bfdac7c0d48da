#include "canopy/formats/csv_table.h"

#include <cstdio>
#include <sstream>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::formats {

std::vector<CsvRow> split_csv(const std::string& text) {
  std::vector<CsvRow> rows;
  std::istringstream in(text);
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    CsvRow row{no, {std::string()}};
    for (char c : line) {
      if (c == ',')
        row.cells.emplace_back();
      else
        row.cells.back() += c;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::map<std::string, ThesisRow> parse_thesis_csv(const std::string& text, const std::string& name) {
  std::map<std::string, ThesisRow> rows;
  for (const CsvRow& r : split_csv(text)) {
    if (r.line == 1) continue;  // the header
    const std::vector<std::string>& f = r.cells;
    if (f.size() != 6)
      throw common::DataError(name, "line " + std::to_string(r.line) + ": expected 6 columns");
    try {
      rows[f[0] + "/" + f[1] + "/" + f[2]] = {std::stod(f[3]), std::stoi(f[4]), std::stod(f[5])};
    } catch (const std::exception&) {
      throw common::DataError(name, "line " + std::to_string(r.line) + ": not a number");
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
