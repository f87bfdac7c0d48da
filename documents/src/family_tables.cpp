#include "canopy/documents/family_tables.h"

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/formats/csv_table.h"

namespace canopy::documents {

namespace {

using common::DataError;

// The non-empty lines of a CSV table, split at commas, with their line numbers.
struct Table {
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
};

Table read_table(const std::string& text, const std::string& name) {
  Table t;
  for (formats::CsvRow& r : formats::split_csv(text)) {
    t.rows.push_back(std::move(r.cells));
    t.lines.push_back(r.line);
  }
  if (t.rows.empty()) throw DataError(name, "empty table (no header)");
  return t;
}

std::string at_line(int line) { return "line " + std::to_string(line) + ": "; }

// Row r has as many cells as the header (row 0); DataError naming the file and line otherwise.
void check_width(const Table& t, std::size_t r, const std::string& name) {
  if (t.rows[r].size() != t.rows.front().size()) {
    throw DataError(name, at_line(t.lines[r]) + std::to_string(t.rows[r].size()) +
                              " columns, the header has " + std::to_string(t.rows.front().size()));
  }
}

// The header's column of each name; DataError naming the first of `needed` that is missing.
std::map<std::string, std::size_t> header_columns(const Table& t, const std::string& name,
                                                  std::initializer_list<const char*> needed) {
  std::map<std::string, std::size_t> col;
  for (std::size_t k = 0; k < t.rows.front().size(); ++k) col[t.rows.front()[k]] = k;
  for (const char* n : needed) {
    if (!col.count(n)) throw DataError(name, at_line(t.lines[0]) + "no column '" + n + "' in the header");
  }
  return col;
}

int count(const std::string& s, const std::string& name, int line, const std::string& column) {
  std::size_t used = 0;
  long v = -1;
  try {
    v = std::stol(s, &used);
  } catch (const std::exception&) { used = 0; }
  if (s.empty() || used != s.size() || v < 0 || v > 1000000000) {
    throw DataError(name, at_line(line) + column + " '" + s + "' is not a count (a whole number >= 0)");
  }
  return static_cast<int>(v);
}

std::string share(int k, int n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", static_cast<double>(k) / n);
  return buf;
}

}  // namespace

std::string serialize_family_confusion(const FamilyConfusion& table, bool per_method) {
  std::string out = per_method ? "method,true_class" : "true_class";
  for (const auto& c : table.answers) out += "," + c;
  out += "\n";
  for (const auto& r : table.rows) {
    out += per_method ? r.method + "," + r.true_class : r.true_class;
    for (int n : r.answered) out += "," + std::to_string(n);
    out += "\n";
  }
  return out;
}

std::string serialize_family_accuracy(const std::vector<FamilyAccuracyRow>& rows) {
  std::string out =
      "cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,"
      "nearest_accuracy,failed\n";
  for (const auto& r : rows) {
    out += r.cover + "," + r.noise + "," + std::to_string(r.trials) + "," + std::to_string(r.class_right) +
           "," + share(r.class_right, r.trials) + "," + std::to_string(r.accepted) + "," +
           std::to_string(r.accepted_right) + "," + std::to_string(r.nearest_right) + "," +
           share(r.nearest_right, r.trials) + "," + std::to_string(r.failed) + "\n";
  }
  return out;
}

std::string serialize_family_methods(const std::vector<FamilyMethodRow>& rows) {
  std::string out =
      "method,class,cover,noise,trials,class_right,class_accuracy,nearest_right,nearest_accuracy,failed,"
      "timed,seconds_mean\n";
  for (const auto& r : rows) {
    std::string mean;
    if (r.timed > 0) {
      char s[64];
      std::snprintf(s, sizeof s, "%.3f", r.seconds_mean);
      mean = s;
    }
    out += r.method + "," + r.vehicle_class + "," + r.cover + "," + r.noise + "," + std::to_string(r.trials) +
           "," + std::to_string(r.class_right) + "," + share(r.class_right, r.trials) + "," +
           std::to_string(r.nearest_right) + "," + share(r.nearest_right, r.trials) + "," +
           std::to_string(r.failed) + "," + std::to_string(r.timed) + "," + mean + "\n";
  }
  return out;
}

FamilyConfusion parse_family_confusion(const std::string& text, const std::string& name, bool per_method) {
  const Table c = read_table(text, name);
  const auto& head = c.rows.front();
  const std::size_t first = per_method ? 2 : 1;  // the first count column
  if (head.size() < first + 1 || (per_method && (head[0] != "method" || head[1] != "true_class")) ||
      (!per_method && head[0] != "true_class")) {
    throw DataError(name, at_line(c.lines[0]) + "expected the header " +
                              (per_method ? "method,true_class" : "true_class") + ",<answered classes...>");
  }
  FamilyConfusion t;
  t.answers.assign(head.begin() + static_cast<std::ptrdiff_t>(first), head.end());
  for (std::size_t r = 1; r < c.rows.size(); ++r) {
    const auto& row = c.rows[r];
    check_width(c, r, name);
    FamilyConfusion::Row x;
    if (per_method) x.method = row[0];
    x.true_class = row[first - 1];
    for (std::size_t k = first; k < row.size(); ++k)
      x.answered.push_back(count(row[k], name, c.lines[r], head[k]));
    t.rows.push_back(std::move(x));
  }
  return t;
}

std::vector<FamilyAccuracyRow> parse_family_accuracy(const std::string& text, const std::string& name) {
  const Table a = read_table(text, name);
  std::map<std::string, std::size_t> col = header_columns(
      a, name,
      {"cover", "noise", "trials", "class_right", "accepted", "accepted_right", "nearest_right", "failed"});
  std::vector<FamilyAccuracyRow> rows;
  for (std::size_t r = 1; r < a.rows.size(); ++r) {
    const auto& row = a.rows[r];
    const int line = a.lines[r];
    check_width(a, r, name);
    FamilyAccuracyRow l;
    l.cover = row[col["cover"]];
    l.noise = row[col["noise"]];
    auto get = [&](const char* column) { return count(row[col[column]], name, line, column); };
    l.trials = get("trials");
    l.class_right = get("class_right");
    l.accepted = get("accepted");
    l.accepted_right = get("accepted_right");
    l.nearest_right = get("nearest_right");
    l.failed = get("failed");
    if (l.class_right > l.trials || l.accepted > l.trials || l.accepted_right > l.accepted ||
        l.nearest_right > l.trials || l.failed > l.trials) {
      throw DataError(name, at_line(line) + "a count exceeds its total");
    }
    rows.push_back(l);
  }
  return rows;
}

std::vector<FamilyMethodRow> parse_family_methods(const std::string& text, const std::string& name) {
  const Table m = read_table(text, name);
  std::map<std::string, std::size_t> col =
      header_columns(m, name,
                     {"method", "class", "cover", "noise", "trials", "class_right", "nearest_right", "failed",
                      "timed", "seconds_mean"});
  std::vector<FamilyMethodRow> rows;
  for (std::size_t r = 1; r < m.rows.size(); ++r) {
    const auto& row = m.rows[r];
    const int line = m.lines[r];
    check_width(m, r, name);
    FamilyMethodRow x;
    x.method = row[col["method"]];
    x.vehicle_class = row[col["class"]];
    x.cover = row[col["cover"]];
    x.noise = row[col["noise"]];
    auto get = [&](const char* column) { return count(row[col[column]], name, line, column); };
    x.trials = get("trials");
    x.class_right = get("class_right");
    x.nearest_right = get("nearest_right");
    x.failed = get("failed");
    x.timed = get("timed");
    if (x.method.empty() || x.class_right > x.trials || x.nearest_right > x.trials || x.failed > x.trials ||
        x.timed > x.trials) {
      throw DataError(name, at_line(line) + "no method, or a count exceeds its total");
    }
    const std::string& sec = row[col["seconds_mean"]];
    if (x.timed > 0) {
      std::size_t used = 0;
      try {
        x.seconds_mean = std::stod(sec, &used);
      } catch (const std::exception&) { used = 0; }
      if (sec.empty() || used != sec.size() || !std::isfinite(x.seconds_mean) || x.seconds_mean < 0) {
        throw DataError(name, at_line(line) + "seconds_mean '" + sec + "' is not a time in seconds");
      }
    } else if (!sec.empty()) {
      throw DataError(name, at_line(line) + "a mean time without timed trials");
    }
    rows.push_back(x);
  }
  return rows;
}

}  // namespace canopy::documents
