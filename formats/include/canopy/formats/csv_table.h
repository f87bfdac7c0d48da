// canopy's CSV tables: a header line, then rows of cells separated by commas (no quoting: no
// cell holds a comma). The thesis's results table (share/thesis/results.csv) is read here; the
// report's tables (results/*.csv) write their numbers with format_number.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace canopy::formats {

// One line of a CSV text: its 1-based line number and its cells.
struct CsvRow {
  int line = 0;
  std::vector<std::string> cells;
};

// The non-empty lines of a CSV text (a trailing '\r' dropped first), each split at every comma
// (so a trailing comma gives an empty last cell), with their line numbers. The one splitter of
// canopy's CSV readers; what a row must hold is the reader's to check.
std::vector<CsvRow> split_csv(const std::string& text);

// One row of the thesis's results table: the correct model's score, its rank and the entropy
// of the scores over the models (bits).
struct ThesisRow {
  double score = 0;
  int rank = 0;
  double entropy = 0;
};

// share/thesis/results.csv: header object,scene,noise_mm,score,rank,entropy (the first line is
// skipped as the header), then one trial a line; empty lines are skipped. Rows by key
// "<object>/<scene>/<noise_mm>". Throws common::DataError(name, "line N: ...") for a row of
// other than 6 cells or a value that is not a number.
std::map<std::string, ThesisRow> parse_thesis_csv(const std::string& text, const std::string& name);

// One number as printf's `printf_format` (one conversion of a double, e.g. "%.3f", "%.0f%%")
// writes it; at most 63 characters. The tables' cells and the report's numbers.
std::string format_number(const char* printf_format, double v);

}  // namespace canopy::formats
