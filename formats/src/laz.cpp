// LAZ container: the LASzip VLR, the chunk table, the chunks -> an uncompressed LAS file that
// las.cpp parses like any other. Layout from the LASzip specification (laszip.org) and
// Isenburg (2013): the point data starts with the 64-bit offset of the chunk table (or -1:
// then it is in the file's last 8 bytes); the table is {u32 version 0, u32 chunk count}
// followed by the range-coded (laz_coder.h) per-chunk point counts (variable chunks only)
// and byte sizes, each predicted from the previous chunk's.
#include "canopy/formats/laz.h"

#include <cstdint>
#include <cstring>
#include <vector>

#include "canopy/common/error.h"
#include "las_header.h"
#include "laz_coder.h"
#include "laz_items.h"

namespace canopy::formats {
namespace {

using common::DataError;
using las::get;
using las::kHeader12;
using las::kVlrHeader;
using laz::Item;

constexpr std::size_t kLaszipFixed = 34;
constexpr std::uint32_t kVariableChunks = 0xFFFFFFFFu;

template <typename T>
void set(std::string* s, std::size_t at, T v) {
  std::memcpy(&(*s)[at], &v, sizeof v);
}

bool is_laszip_vlr(const std::uint8_t* v) {
  static const char id[16] = "laszip encoded";
  return std::memcmp(v + 2, id, 15) == 0 && get<std::uint16_t>(v + 18) == 22204;
}

// The header fields the container needs (las::read_header_fields, las::point_count) and the
// EVLRs' place (LAS 1.4); each checked against the file size.
struct Header : las::LasHeader {
  std::uint64_t evlr_start = 0;
  std::uint32_t evlr_count = 0;
};

Header read_header(const std::uint8_t* b, std::size_t size, const std::string& name) {
  if (size < kHeader12) {
    throw DataError(name, "LAS header truncated: file has " + std::to_string(size) +
                              " bytes, a header needs " + std::to_string(kHeader12));
  }
  Header h;
  static_cast<las::LasHeader&>(h) = las::read_header_fields(b, size, name);
  h.n = las::point_count(b, h.minor, name);
  if (h.minor >= 4) {
    h.evlr_start = get<std::uint64_t>(b + 235);
    h.evlr_count = get<std::uint32_t>(b + 243);
    if (h.evlr_count > 0 && (h.evlr_start < h.data_offset || h.evlr_start > size)) {
      throw DataError(name, "EVLR start " + std::to_string(h.evlr_start) +
                                " is not between the point data and the end of the file (" +
                                std::to_string(size) + " bytes)");
    }
  }
  return h;
}

// The LASzip VLR's payload (LASzip specification, "laszip encoded" 22204).
struct Laszip {
  std::uint16_t compressor = 0, coder = 0;
  std::uint32_t chunk_size = 0;
  std::vector<Item> items;
};

Laszip read_laszip(const std::uint8_t* p, std::size_t len, const std::string& name) {
  if (len < kLaszipFixed || (len - kLaszipFixed) % 6 != 0) {
    throw DataError(
        name, "LASzip VLR of " + std::to_string(len) + " bytes is malformed (34 + 6 per item expected)");
  }
  Laszip z;
  z.compressor = get<std::uint16_t>(p);
  z.coder = get<std::uint16_t>(p + 2);
  z.chunk_size = get<std::uint32_t>(p + 12);
  const std::size_t items = get<std::uint16_t>(p + 32);
  if (items == 0 || items != (len - kLaszipFixed) / 6) {
    throw DataError(name, "LASzip VLR lists " + std::to_string(items) + " items in " + std::to_string(len) +
                              " bytes (malformed)");
  }
  for (std::size_t i = 0; i < items; ++i) {
    const std::uint8_t* q = p + kLaszipFixed + 6 * i;
    z.items.push_back({get<std::uint16_t>(q), get<std::uint16_t>(q + 2), get<std::uint16_t>(q + 4)});
  }
  if (z.coder != 0)
    throw DataError(name, "LASzip coder " + std::to_string(z.coder) + " is unknown (0 exists)");
  if (z.compressor > 3) {
    throw DataError(name, "LASzip compressor " + std::to_string(z.compressor) + " is unknown (0-3 exist)");
  }
  return z;
}

// One chunk: where its bytes are and how many points it holds.
struct Chunk {
  std::size_t begin = 0, size = 0;
  std::uint64_t count = 0;
};

// The chunk table of compressors 2 and 3 -> the chunks holding the file's n points.
std::vector<Chunk> read_chunk_table(const std::uint8_t* b, std::size_t size, const Header& h,
                                    std::uint32_t chunk_size, const std::string& name) {
  const std::size_t first = h.data_offset + 8;
  if (first > size) throw DataError(name, "LAZ point data truncated: no chunk table offset");
  std::int64_t at = get<std::int64_t>(b + h.data_offset);
  if (at == -1 && size >= first + 8) at = get<std::int64_t>(b + size - 8);  // written at the end
  if (at < static_cast<std::int64_t>(first) || static_cast<std::uint64_t>(at) > size - 8 || size < 8) {
    throw DataError(name, "LAZ chunk table offset " + std::to_string(at) +
                              " is not between the point data (byte " + std::to_string(first) +
                              ") and the end of the file (" + std::to_string(size) +
                              " bytes; a truncated file or an interrupted compressor)");
  }
  const auto table = static_cast<std::size_t>(at);
  const std::uint32_t version = get<std::uint32_t>(b + table);
  const std::uint32_t count = get<std::uint32_t>(b + table + 4);
  if (version != 0)
    throw DataError(name, "LAZ chunk table version " + std::to_string(version) + " is unknown (0)");
  const std::size_t area = table - first;  // every chunk takes at least one byte of it
  if (count > area || (count == 0 && h.n > 0)) {
    throw DataError(name, "LAZ chunk table lists " + std::to_string(count) + " chunks for " +
                              std::to_string(area) + " bytes of compressed points (corrupt table)");
  }
  std::vector<Chunk> chunks(count);
  bool overrun = false;
  laz::RangeDecoder d;
  d.start(b + table + 8, b + size, &overrun);
  laz::IntegerDecoder ic(32, 2);
  std::int32_t last_count = 0, last_size = 0;
  std::size_t pos = first;
  std::uint64_t points = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    Chunk& c = chunks[i];
    try {
      if (chunk_size == kVariableChunks) last_count = ic.decode(d, last_count, 0);
      last_size = ic.decode(d, last_size, 1);
    } catch (const laz::Corrupt&) { overrun = true; }
    if (overrun)
      throw DataError(name, "LAZ chunk table truncated or corrupt (entry " + std::to_string(i + 1) + ")");
    if (last_size <= 0 || static_cast<std::size_t>(last_size) > table - pos) {
      throw DataError(name, "LAZ chunk " + std::to_string(i + 1) + " of " + std::to_string(count) + " has " +
                                std::to_string(last_size) + " bytes, beyond the " + std::to_string(table - pos) +
                                " bytes left before the chunk table (corrupt table)");
    }
    c.begin = pos;
    c.size = static_cast<std::size_t>(last_size);
    pos += c.size;
    if (chunk_size == kVariableChunks) {
      if (last_count <= 0) {
        throw DataError(name, "LAZ chunk " + std::to_string(i + 1) + " holds " + std::to_string(last_count) +
                                  " points (corrupt table)");
      }
      c.count = static_cast<std::uint64_t>(last_count);
    } else {
      c.count = chunk_size;
    }
    // The last chunks may hold fewer points (fixed size) or more than the header counts.
    c.count = std::min<std::uint64_t>(c.count, h.n - points);
    points += c.count;
  }
  if (points < h.n) {
    throw DataError(
        name, "LAZ chunks hold " + std::to_string(points) + " points, the header says " + std::to_string(h.n));
  }
  while (!chunks.empty() && chunks.back().count == 0) chunks.pop_back();
  return chunks;
}

}  // namespace

bool laszip_compressed(const std::string& bytes) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const std::size_t size = bytes.size();
  if (size < 105 || bytes.compare(0, 4, "LASF") != 0) return false;
  if ((b[104] & 0xC0) != 0) return true;
  if (size < kHeader12) return false;
  const std::size_t data = std::min<std::size_t>(get<std::uint32_t>(b + 96), size);
  std::size_t pos = get<std::uint16_t>(b + 94);
  const std::uint32_t vlrs = get<std::uint32_t>(b + 100);
  for (std::uint32_t i = 0; i < vlrs && pos + kVlrHeader <= data; ++i) {
    if (is_laszip_vlr(b + pos)) return true;
    pos += kVlrHeader + get<std::uint16_t>(b + pos + 20);
  }
  return false;
}

std::string laz_to_las(const std::string& bytes, const std::string& name) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const std::size_t size = bytes.size();
  const Header h = read_header(b, size, name);

  // VLRs: all kept but LASzip's.
  std::string vlrs;
  std::uint32_t kept = 0;
  const std::uint8_t* laszip_at = nullptr;
  std::size_t laszip_len = 0, pos = h.header_size;
  las::for_each_vlr(b, h.data_offset, h, name, [&](const std::uint8_t* v, std::size_t len) {
    if (is_laszip_vlr(v)) {
      if (laszip_at == nullptr) laszip_at = v + kVlrHeader, laszip_len = len;
    } else {
      vlrs.append(bytes, pos, kVlrHeader + len);
      ++kept;
    }
    pos += kVlrHeader + len;
  });
  vlrs.append(bytes, pos, h.data_offset - pos);  // bytes after the VLRs, if any
  if (laszip_at == nullptr) {
    throw DataError(name,
                    "the point format byte says LAZ (compression bit set) but the file has no LASzip VLR "
                    "('laszip encoded' 22204): not a LAZ file canopy can decode");
  }
  const Laszip z = read_laszip(laszip_at, laszip_len, name);
  std::size_t item_bytes = 0;
  for (const Item& it : z.items) item_bytes += it.size;
  // h.record >= the point format's minimum (20 bytes or more): read_header_fields checked it.
  if (item_bytes != h.record) {
    throw DataError(name, "LASzip items add up to " + std::to_string(item_bytes) +
                              " bytes, the point record has " + std::to_string(h.record));
  }

  // The compressed point data ends at the EVLRs (LAS 1.4) or the end of the file.
  const std::size_t data_end = h.evlr_count > 0 ? static_cast<std::size_t>(h.evlr_start) : size;
  std::vector<Chunk> chunks;
  if (h.n > 0) {
    if (z.compressor == 0 || z.compressor == 1) {  // raw, or one stream without chunks
      chunks.push_back({h.data_offset, data_end - h.data_offset, h.n});
    } else {
      if (z.chunk_size == 0) throw DataError(name, "LASzip chunk size is 0");
      chunks = read_chunk_table(b, size, h, z.chunk_size, name);
    }
  }
  // Memory is bounded by the file: no chunk may expand beyond kLazMaxExpansion.
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    const Chunk& c = chunks[i];
    const bool raw = z.compressor == 0;
    if (c.count > (raw ? 1 : kLazMaxExpansion) * static_cast<std::uint64_t>(c.size) / h.record) {
      throw DataError(name, (raw ? std::string("point data truncated: header says ")
                                 : "LAZ chunk " + std::to_string(i + 1) + " of " +
                                       std::to_string(chunks.size()) + " claims ") +
                                std::to_string(c.count) + " points of " + std::to_string(h.record) +
                                " bytes in " + std::to_string(c.size) + " bytes" +
                                (raw ? std::string() : " (more than LASzip can compress into that; corrupt)"));
    }
  }

  std::unique_ptr<laz::ChunkDecoder> decoder;
  if (z.compressor != 0 && h.n > 0) {
    std::string why;
    decoder = z.compressor == 3 ? laz::make_layered_decoder(z.items, &why)
                                : laz::make_pointwise_decoder(z.items, &why);
    if (!decoder) throw DataError(name, why);
  }

  // The LAS file: header, VLRs, records, EVLRs.
  const std::size_t evlr_bytes = h.evlr_count > 0 ? size - data_end : 0;
  const std::size_t offset = h.header_size + vlrs.size();
  std::string out;
  out.reserve(offset + static_cast<std::size_t>(h.n) * h.record + evlr_bytes);
  out.append(bytes, 0, h.header_size);
  out[104] = static_cast<char>(b[104] & 0x3F);
  set<std::uint32_t>(&out, 96, static_cast<std::uint32_t>(offset));
  set<std::uint32_t>(&out, 100, kept);
  if (h.evlr_count > 0) set<std::uint64_t>(&out, 235, offset + h.n * h.record);
  out += vlrs;
  out.resize(offset + static_cast<std::size_t>(h.n) * h.record);
  auto* records = reinterpret_cast<std::uint8_t*>(&out[offset]);
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    const Chunk& c = chunks[i];
    if (z.compressor == 0) {
      std::memcpy(records, b + c.begin, static_cast<std::size_t>(c.count) * h.record);
      break;
    }
    try {
      decoder->decode(b + c.begin, b + c.begin + c.size, c.count, records);
    } catch (const laz::Corrupt& e) {
      throw DataError(name, "LAZ chunk " + std::to_string(i + 1) + " of " + std::to_string(chunks.size()) +
                                " (bytes " + std::to_string(c.begin) + "-" +
                                std::to_string(c.begin + c.size) + ") is corrupt: " + e.what());
    }
    records += static_cast<std::size_t>(c.count) * h.record;
  }
  out.append(bytes, data_end, evlr_bytes);
  return out;
}

}  // namespace canopy::formats
