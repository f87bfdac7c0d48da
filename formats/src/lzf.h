// LZF (liblzf format, as used by PCD binary_compressed). Private to formats/.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace canopy::formats::detail {

// Decompresses `in` into exactly `out_size` bytes. Returns false on corrupt input.
bool lzf_decompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_size);

// The most bytes lzf_compress writes for `in_size` input bytes (a literal run of 32 bytes
// takes 33; a back-reference never more than the bytes it stands for).
inline std::size_t lzf_bound(std::size_t in_size) { return in_size + in_size / 32 + 16; }

// Compresses `in` (liblzf's format; PCL's lzfDecompress and ours read it) into `out`, which
// holds lzf_bound(in_size) bytes; returns the compressed size. Deterministic.
std::size_t lzf_compress(const unsigned char* in, std::size_t in_size, unsigned char* out);

}  // namespace canopy::formats::detail
