#include "lzf.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace canopy::formats::detail {

bool lzf_decompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_size) {
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
      if (back >= len) {  // no overlap: one copy
        std::memcpy(out + op, out + op - back, len);
        op += len;
      } else {
        for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
      }
    }
  }
  return op == out_size;
}

}  // namespace canopy::formats::detail

namespace canopy::formats::detail {

// Greedy LZF: a hash of the next 3 bytes finds the last position with the same hash within
// the 8 KiB window; matches of 3..264 bytes become back-references, the rest literal runs of
// at most 32 bytes.
std::size_t lzf_compress(const unsigned char* in, std::size_t in_size, unsigned char* out) {
  constexpr std::size_t kHashBits = 14;
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  constexpr std::size_t kMaxOff = 1 << 13;
  constexpr std::size_t kMaxLen = 264;
  std::vector<std::size_t> table(std::size_t{1} << kHashBits, kNone);
  // op: the next byte to write; lit_at: the control byte of the current literal run.
  std::size_t op = 0, lit_at = 0, lit = 0;
  out[op++] = 0;
  auto literal = [&](unsigned char c) {
    out[op++] = c;
    if (++lit == 32) {
      out[lit_at] = 31;
      lit = 0;
      lit_at = op;
      out[op++] = 0;
    }
  };
  std::size_t ip = 0;
  while (ip + 2 < in_size) {
    const std::uint32_t v = (std::uint32_t{in[ip]} << 16) | (std::uint32_t{in[ip + 1]} << 8) | in[ip + 2];
    const std::size_t hslot = ((v * 2654435761u) >> (32 - kHashBits)) & ((std::size_t{1} << kHashBits) - 1);
    const std::size_t ref = table[hslot];
    table[hslot] = ip;
    if (ref != kNone && ip - ref - 1 < kMaxOff && in[ref] == in[ip] && in[ref + 1] == in[ip + 1] &&
        in[ref + 2] == in[ip + 2]) {
      const std::size_t max_len = std::min(kMaxLen, in_size - ip);
      std::size_t len = 3;
      while (len < max_len && in[ref + len] == in[ip + len]) ++len;
      const std::size_t off = ip - ref - 1;
      if (lit == 0)
        --op;  // the empty run's control byte
      else
        out[lit_at] = static_cast<unsigned char>(lit - 1);
      const std::size_t enc = len - 2;
      if (enc < 7) {
        out[op++] = static_cast<unsigned char>((off >> 8) + (enc << 5));
      } else {
        out[op++] = static_cast<unsigned char>((off >> 8) + (7 << 5));
        out[op++] = static_cast<unsigned char>(enc - 7);
      }
      out[op++] = static_cast<unsigned char>(off & 0xff);
      ip += len;
      lit = 0;
      lit_at = op;
      out[op++] = 0;
    } else {
      literal(in[ip++]);
    }
  }
  while (ip < in_size) literal(in[ip++]);
  if (lit == 0)
    --op;
  else
    out[lit_at] = static_cast<unsigned char>(lit - 1);
  return op;
}

}  // namespace canopy::formats::detail
