#include "canopy/common/error.h"

namespace canopy::common {

DataError::DataError(const std::string& file, const std::string& cause)
    : Error(display_name(file) + ": " + cause), file_(file), cause_(cause) {}

std::string display_name(const std::string& path, bool output) {
  if (path == "-") return output ? "<stdout>" : "<stdin>";
  return path;
}

}  // namespace canopy::common
