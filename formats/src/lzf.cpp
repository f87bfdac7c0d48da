#include "lzf.h"

#include <cstring>

namespace canopy::formats::detail {

bool lzf_decompress(const unsigned char* in, std::size_t in_size, unsigned char* out,
                    std::size_t out_size) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {  // literal run of ctrl + 1 bytes
      const std::size_t len = ctrl + 1;
      if (ip + len > in_size || op + len > out_size) return false;
      std::memcpy(out + op, in + ip, len);
      ip += len;
      op += len;
    } else {  // back reference
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_size) return false;
        len += in[ip++];
      }
      len += 2;
      if (ip >= in_size) return false;
      const std::size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
      if (back > op || op + len > out_size) return false;
      for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
    }
  }
  return op == out_size;
}

}  // namespace canopy::formats::detail
