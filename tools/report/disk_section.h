// The disk an experiment's output directory holds, per part (issue 31: "report the disk per
// experiment part"): the report's "Disk" section.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace canopy::report {

struct DiskPart {
  std::string name;         // "thesis trials", or the top-level directory's name, or "other files"
  std::uint64_t bytes = 0;  // regular files' sizes, each file (inode) counted once
  std::uint64_t files = 0;
};

// Walks `out` (symbolic links are not followed) and sums the regular files per part: the
// top-level directories named in `thesis_objects` together as "thesis trials", every other
// top-level directory by its name, files directly in `out` as "other files". A file with
// several names (the 0 mm scans are hard links to their render) is counted once, in the first
// part met in name order. Parts in name order, "thesis trials" first, "other files" last;
// empty parts left out. A missing `out` gives no parts; an unreadable one is a DataError.
std::vector<DiskPart> disk_parts(const std::string& out, const std::vector<std::string>& thesis_objects);

// The Markdown section: one row per part in MB (10^6 bytes) with its file count, and the total.
std::string disk_markdown(const std::vector<DiskPart>& parts, const std::string& out);

}  // namespace canopy::report
