#include "report/disk_section.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <sstream>
#include <utility>

#include "canopy/common/error.h"
#include "report/report.h"

namespace canopy::report {
namespace {

namespace fs = std::filesystem;

// The sorted entries of a directory (directory_iterator's order is the file system's). A
// directory gone meanwhile (a stage's temporary one renamed) has none.
std::vector<fs::path> sorted_entries(const fs::path& dir) {
  std::vector<fs::path> v;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) v.push_back(it->path());
  if (ec == std::errc::no_such_file_or_directory) return {};
  if (ec) throw common::DataError(dir.string(), "cannot be read: " + ec.message());
  std::sort(v.begin(), v.end());
  return v;
}

using Seen = std::set<std::pair<dev_t, ino_t>>;

// Adds `p` (a regular file, or everything under a directory) to `part`.
void add(const fs::path& p, DiskPart& part, Seen& seen) {
  struct stat st {};
  if (lstat(p.c_str(), &st) != 0) return;  // gone meanwhile
  if (S_ISDIR(st.st_mode)) {
    for (const auto& e : sorted_entries(p)) add(e, part, seen);
  } else if (S_ISREG(st.st_mode) && seen.emplace(st.st_dev, st.st_ino).second) {
    part.bytes += static_cast<std::uint64_t>(st.st_size);
    ++part.files;
  }
}

}  // namespace

std::vector<DiskPart> disk_parts(const std::string& out, const std::vector<std::string>& thesis_objects) {
  std::error_code ec;
  if (!fs::exists(out, ec)) return {};
  Seen seen;
  DiskPart thesis{"thesis trials"}, other{"other files"};
  std::vector<DiskPart> named;
  for (const auto& e : sorted_entries(out)) {
    const std::string name = e.filename().string();
    if (fs::is_directory(fs::symlink_status(e, ec))) {
      if (std::find(thesis_objects.begin(), thesis_objects.end(), name) != thesis_objects.end()) {
        add(e, thesis, seen);
      } else {
        DiskPart d{name};
        add(e, d, seen);
        named.push_back(d);
      }
    } else {
      add(e, other, seen);
    }
  }
  std::vector<DiskPart> parts;
  if (thesis.files) parts.push_back(thesis);
  for (const auto& d : named)
    if (d.files) parts.push_back(d);
  if (other.files) parts.push_back(other);
  return parts;
}

std::string disk_markdown(const std::vector<DiskPart>& parts, const std::string& out) {
  std::ostringstream md;
  md << "\n## Disk\n\n"
        "What `"
     << out
     << "` holds when the report is written, per part of the experiment (regular files, each counted once "
        "however many names it has; the thesis trials' scans are deleted right after the report unless "
        "KEEP=1, the scene and family scans after their last reader). Sizes vary a little between runs "
        "(logs and times).\n\n| part | files | MB |\n|---|---:|---:|\n";
  std::uint64_t bytes = 0, files = 0;
  for (const auto& p : parts) {
    md << "| " << p.name << " | " << p.files << " | " << format_number("%.1f", p.bytes / 1e6) << " |\n";
    bytes += p.bytes;
    files += p.files;
  }
  md << "| **all** | " << files << " | **" << format_number("%.1f", bytes / 1e6) << "** |\n";
  return md.str();
}

}  // namespace canopy::report
