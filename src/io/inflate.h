// zlib (RFC 1950) and DEFLATE (RFC 1951) decompression, our own: stored, fixed-Huffman and
// dynamic-Huffman blocks, with the Adler-32 checksum of the zlib trailer checked. Used by
// the PNG reader; every malformed stream is an InflateError, never a read out of bounds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace spt {

/// A stream that is not valid zlib/DEFLATE data (the message says what is wrong).
struct InflateError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Decompresses a zlib stream (2-byte header, DEFLATE blocks, Adler-32 trailer). The output
/// must be exactly `expected_size` bytes (a PNG knows its size from its header): a longer
/// stream stops with an error as soon as it would exceed it, so a small file cannot make
/// the reader allocate or write more than the caller asked for.
std::vector<std::uint8_t> zlib_decompress(std::string_view stream, std::size_t expected_size);

}  // namespace spt
