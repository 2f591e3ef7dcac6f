// The OpenEXR pixel-data compressions the reader decodes: RLE, ZIPS/ZIP (zlib) and PIZ
// (wavelet + Huffman). Each turns one chunk's stored bytes into the chunk's uncompressed
// pixel data (per scan line, per channel in the header's order, little-endian samples),
// exactly `raw_size` bytes; any malformed chunk is an ImageDecodeError, never a read or
// write out of bounds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace spt {

/// RLE: signed count bytes (negative: that many literal bytes follow; otherwise count + 1
/// copies of the next byte), then the byte predictor and interleave that ZIP uses too.
void exr_uncompress_rle(std::string_view packed, std::vector<std::uint8_t>& out, std::size_t raw_size);

/// ZIPS and ZIP: a zlib stream, then the predictor and interleave.
void exr_uncompress_zip(std::string_view packed, std::vector<std::uint8_t>& out, std::size_t raw_size);

/// One channel of a PIZ chunk: `width` × `lines` samples of `words` 16-bit words each
/// (1 for HALF, 2 for FLOAT and UINT).
struct PizChannel {
    int width, lines, words;
};

/// PIZ: a bitmap of the 16-bit values present, a Huffman-coded stream of their indices, and
/// a Haar wavelet per channel and word to undo (src/io/exr_piz.cpp).
void exr_uncompress_piz(std::string_view packed, std::vector<std::uint8_t>& out, std::size_t raw_size,
                        const std::vector<PizChannel>& channels);

}  // namespace spt
