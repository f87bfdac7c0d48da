// LZF (liblzf format, as used by PCD binary_compressed). Private to formats/.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace canopy::formats::detail {

// Decompresses `in` into exactly `out_size` bytes. Returns false on corrupt input.
bool lzf_decompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_size);

// Compresses `in` (liblzf's format; PCL's lzfDecompress and ours read it). Deterministic.
std::vector<unsigned char> lzf_compress(const unsigned char* in, std::size_t in_size);

}  // namespace canopy::formats::detail
