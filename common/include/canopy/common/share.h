// Where canopy's data (share/: POV-Ray models, scenes, stage parameters, thesis tables) is.
#pragma once

#include <string>

namespace canopy::common {

// The share directory, first of:
//   1. $CANOPY_SHARE, when set and not empty (used as given; it must exist);
//   2. <directory of the executable>/../share/canopy (as configured by CMAKE_INSTALL_BINDIR
//      and CMAKE_INSTALL_DATADIR), when it exists: an installed canopy, wherever its prefix
//      has been moved;
//   3. the source tree's share/ the binary was built from (a build-tree run).
// Throws Error when none exists, naming what was tried.
std::string share_dir();

}  // namespace canopy::common
