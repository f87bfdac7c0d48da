// The LAS header and VLR walk shared by the LAS reader (las.cpp) and the LAZ container
// (laz.cpp), which reads the same uncompressed header and VLRs. Private to formats/.
// Layout: ASPRS LAS 1.4 R15; every failure is a common::DataError naming the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "canopy/common/error.h"

namespace canopy::formats::las {

// Minimum point record length of point data formats 0..10 (LAS 1.4 R15, Table 7 ff.).
constexpr std::size_t kMinRecord[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
// Public header size by minor version (1.0-1.2, 1.3, 1.4).
constexpr std::size_t kHeader12 = 227, kHeader13 = 235, kHeader14 = 375;
constexpr std::size_t kVlrHeader = 54;

template <typename T>
inline T get(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// File text (user ids, names) made safe for a message: stops at NUL, escapes the rest.
std::string printable(const unsigned char* p, std::size_t n);

// What the LAS header says, checked against the file's size.
struct LasHeader {
  int minor = 0, format = 0;
  std::size_t header_size = 0, data_offset = 0, record = 0;
  std::uint32_t vlr_count = 0;
  double scale[3] = {1, 1, 1}, offset[3] = {0, 0, 0};
  std::uint64_t n = 0;  // point records
};

// The header's fields (not the point count), checked against the file's size (`size` >=
// kHeader12 bytes at `b`): version 1.0-1.4, header size, point data offset, point format (the
// format byte without LASzip's compression bits) and record length, XYZ scale and offset.
LasHeader read_header_fields(const unsigned char* b, std::size_t size, const std::string& name);

// The point count: the 64-bit count of LAS 1.4 wins when set; a legacy count that disagrees
// with it is a broken header.
std::uint64_t point_count(const unsigned char* b, int minor, const std::string& name);

// Calls visit(v, len) for every VLR (v: its 54-byte header, then `len` bytes of payload) between
// the header and the point data, each of which must fit there; stops quietly at the first one
// that does not end within the `available` bytes of `b` (<= the point data offset).
template <typename Visit>
void for_each_vlr(const unsigned char* b, std::size_t available, const LasHeader& h, const std::string& name,
                  Visit visit) {
  std::size_t pos = h.header_size;
  for (std::uint32_t i = 0; i < h.vlr_count; ++i) {
    if (h.data_offset - pos < kVlrHeader) {
      throw common::DataError(name, "LAS header says " + std::to_string(h.vlr_count) + " VLRs but VLR " +
                                        std::to_string(i + 1) +
                                        " does not fit before the point data at byte " +
                                        std::to_string(h.data_offset) + " (broken VLR count or offset)");
    }
    if (pos > available || available - pos < kVlrHeader) return;
    const unsigned char* v = b + pos;
    const std::size_t len = get<std::uint16_t>(v + 20);
    if (h.data_offset - pos - kVlrHeader < len) {
      throw common::DataError(name, "VLR " + std::to_string(i + 1) + " ('" + printable(v + 2, 16) + "' " +
                                        std::to_string(get<std::uint16_t>(v + 18)) + ") of " +
                                        std::to_string(len) + " bytes runs into the point data at byte " +
                                        std::to_string(h.data_offset));
    }
    if (available - pos - kVlrHeader < len) return;
    visit(v, len);
    pos += kVlrHeader + len;
  }
}

}  // namespace canopy::formats::las
