// User text in messages (defined in error.cpp, beside display_name).
#pragma once

#include <string>

namespace canopy::common {

// Text from a user file (a name, a token) for a message: control bytes as \xNN, so no message
// echoes them raw.
std::string printable(const std::string& text);

}  // namespace canopy::common
