// Private to common/: a whole write to a file descriptor.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstddef>

namespace canopy::common::detail {

// Writes all of [data, data + size) to fd; returns 0 or the errno of the failure.
inline int write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return EIO;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return 0;
}

}  // namespace canopy::common::detail
