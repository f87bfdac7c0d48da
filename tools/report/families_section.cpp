#include "report/families_section.h"

#include <cstdio>
#include <map>
#include <sstream>

#include "canopy/common/error.h"

namespace canopy::report {
namespace {

std::string pct(int k, int n) {
  if (n == 0) return "–";
  char b[32];
  std::snprintf(b, sizeof b, "%.1f%%", 100.0 * k / n);
  return b;
}

std::string rate(int k, int n) {
  return pct(k, n) + " (" + std::to_string(k) + "/" + std::to_string(n) + ")";
}

// The non-empty lines of a CSV table, split at commas, with their line numbers.
struct Table {
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
};

Table read_table(const std::string& text, const std::string& name) {
  Table t;
  std::istringstream in(text);
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (line.back() == ',') cells.emplace_back();
    t.rows.push_back(std::move(cells));
    t.lines.push_back(no);
  }
  if (t.rows.empty()) throw common::DataError(name, "empty table (no header)");
  return t;
}

int count(const std::string& s, const std::string& name, int line, const std::string& column) {
  std::size_t used = 0;
  long v = -1;
  try {
    v = std::stol(s, &used);
  } catch (const std::exception&) { used = 0; }
  if (s.empty() || used != s.size() || v < 0 || v > 1000000000) {
    throw common::DataError(name, "line " + std::to_string(line) + ": " + column + " '" + s +
                                      "' is not a count (a whole number >= 0)");
  }
  return static_cast<int>(v);
}

}  // namespace

FamilySummary summarize_families(const std::string& confusion, const std::string& confusion_name,
                                 const std::string& accuracy, const std::string& accuracy_name) {
  FamilySummary s;
  const Table c = read_table(confusion, confusion_name);
  const auto& head = c.rows.front();
  if (head.size() < 2 || head[0] != "true_class") {
    throw common::DataError(confusion_name, "line " + std::to_string(c.lines[0]) +
                                                ": expected the header true_class,<answered classes...>");
  }
  s.answers.assign(head.begin() + 1, head.end());
  for (std::size_t r = 1; r < c.rows.size(); ++r) {
    const auto& row = c.rows[r];
    const int line = c.lines[r];
    if (row.size() != head.size()) {
      throw common::DataError(confusion_name, "line " + std::to_string(line) + ": " +
                                                  std::to_string(row.size()) + " columns, the header has " +
                                                  std::to_string(head.size()));
    }
    FamilyClass fc;
    fc.name = row[0];
    for (std::size_t k = 1; k < row.size(); ++k) {
      const int n = count(row[k], confusion_name, line, head[k]);
      fc.answered.push_back(n);
      fc.trials += n;
      if (head[k] == fc.name) fc.right = n;
    }
    s.trials += fc.trials;
    s.right += fc.right;
    s.classes.push_back(std::move(fc));
  }

  const Table a = read_table(accuracy, accuracy_name);
  std::map<std::string, std::size_t> col;
  for (std::size_t k = 0; k < a.rows.front().size(); ++k) col[a.rows.front()[k]] = k;
  for (const char* needed :
       {"cover", "noise", "trials", "class_right", "accepted", "accepted_right", "nearest_right", "failed"}) {
    if (!col.count(needed)) {
      throw common::DataError(
          accuracy_name, "line " + std::to_string(a.lines[0]) + ": no column '" + needed + "' in the header");
    }
  }
  bool have_all = false;
  for (std::size_t r = 1; r < a.rows.size(); ++r) {
    const auto& row = a.rows[r];
    const int line = a.lines[r];
    if (row.size() != a.rows.front().size()) {
      throw common::DataError(accuracy_name, "line " + std::to_string(line) + ": " +
                                                 std::to_string(row.size()) + " columns, the header has " +
                                                 std::to_string(a.rows.front().size()));
    }
    FamilyLevel l;
    l.cover = row[col["cover"]];
    l.noise = row[col["noise"]];
    auto get = [&](const char* name) { return count(row[col[name]], accuracy_name, line, name); };
    l.trials = get("trials");
    l.class_right = get("class_right");
    l.accepted = get("accepted");
    l.accepted_right = get("accepted_right");
    l.nearest_right = get("nearest_right");
    l.failed = get("failed");
    if (l.class_right > l.trials || l.accepted > l.trials || l.accepted_right > l.accepted ||
        l.nearest_right > l.trials || l.failed > l.trials) {
      throw common::DataError(accuracy_name, "line " + std::to_string(line) + ": a count exceeds its total");
    }
    if (l.cover == "all" && l.noise == "all") {
      s.all = l;
      have_all = true;
    } else {
      s.levels.push_back(l);
    }
  }
  if (!have_all) throw common::DataError(accuracy_name, "no 'all,all' row (the totals)");
  if (s.all.trials != s.trials || s.all.class_right != s.right) {
    throw common::DataError(
        accuracy_name, "its totals (" + std::to_string(s.all.class_right) + " of " +
                           std::to_string(s.all.trials) + " classes right) disagree with " + confusion_name +
                           " (" + std::to_string(s.right) + " of " + std::to_string(s.trials) + ")");
  }
  return s;
}

std::string families_markdown(const FamilySummary& s) {
  std::ostringstream md;
  md << "\n## Vehicle families (issue 17)\n\n"
     << "The class-level protocol (`make -f Makefile.experiments families`, mk/families.mk, "
        "docs/decisions/families.md): procedural vehicles of "
     << s.classes.size()
     << " classes, tested on instances that are not in the modelbase. The answered class is the class of "
        "verify's best-scoring hypothesis (accepted or not); `none` = no class answered or a stage failed. "
        "From `families/confusion.csv` and `families/accuracy.csv` (famscore).\n\n"
     << "**Class accuracy: " << rate(s.right, s.trials)
     << "**; nearest instance (the modelbase entry of the "
        "true class nearest in size): "
     << rate(s.all.nearest_right, s.all.trials) << "; verify accepted " << s.all.accepted << " answers, "
     << s.all.accepted_right << " of them of the right class; " << s.all.failed << " failed trials.\n\n";
  md << "| class | trials | class accuracy |\n|---|---:|---:|\n";
  for (const auto& c : s.classes)
    md << "| " << c.name << " | " << c.trials << " | " << rate(c.right, c.trials) << " |\n";
  md << "| **all** | " << s.trials << " | **" << rate(s.right, s.trials) << "** |\n\n";
  md << "| cover | noise (mm) | trials | class accuracy | verify accepted (right class) | nearest instance | "
        "failed |\n|---|---:|---:|---:|---:|---:|---:|\n";
  auto level = [&](const FamilyLevel& l, bool total) {
    md << "| " << (total ? "**all**" : l.cover) << " | " << (total ? "" : l.noise) << " | " << l.trials
       << " | " << rate(l.class_right, l.trials) << " | " << l.accepted << " (" << l.accepted_right << ") | "
       << rate(l.nearest_right, l.trials) << " | " << l.failed << " |\n";
  };
  for (const auto& l : s.levels) level(l, false);
  level(s.all, true);
  md << "\nConfusion matrix: rows the true class, columns the answered class (right answers in bold).\n\n"
     << "| true \\ answered |";
  for (const auto& a : s.answers) md << " " << a << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < s.answers.size(); ++k) md << "---:|";
  md << "\n";
  for (const auto& c : s.classes) {
    md << "| " << c.name << " |";
    for (std::size_t k = 0; k < s.answers.size(); ++k) {
      const std::string n = std::to_string(c.answered[k]);
      md << " " << (s.answers[k] == c.name && c.answered[k] > 0 ? "**" + n + "**" : n) << " |";
    }
    md << "\n";
  }
  return md.str();
}

}  // namespace canopy::report
