// zlib (RFC 1950), gzip (RFC 1952) and DEFLATE (RFC 1951) decompression, our own: stored,
// fixed-Huffman and dynamic-Huffman blocks, with the trailers' checksums checked. Used by the
// PNG reader and for compressed scene files (.pbrt.gz, .ply.gz); every malformed stream is an InflateError, never a read out of bounds.
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

/// Whether `data` starts with the gzip magic bytes (RFC 1952).
bool is_gzip(std::string_view data);

/// Decompresses a gzip file of one member (RFC 1952: header with its optional fields, DEFLATE
/// blocks, CRC-32 and size trailer, both checked); the size the trailer states bounds the output.
std::string gzip_decompress(std::string_view file);

}  // namespace spt
