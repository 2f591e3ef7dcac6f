// RLE and ZIP chunks of OpenEXR files. Both compressors first split the bytes into the even-
// and odd-indexed halves and store each byte as its difference from the previous one plus 128
// (small differences in smooth images become runs near 128); decoding undoes both after the
// run-length or zlib stage.
#include "io/exr_compression.h"

#include <cstring>
#include <string>

#include "io/image_decoders.h"
#include "io/inflate.h"

namespace spt {

namespace {

/// Undoes the predictor in `t`, then writes the interleaved bytes to `out`.
void undo_predictor_and_split(std::vector<std::uint8_t>& t, std::vector<std::uint8_t>& out) {
    const std::size_t n = t.size();
    for (std::size_t i = 1; i < n; ++i) t[i] = static_cast<std::uint8_t>(t[i - 1] + t[i] - 128);
    out.resize(n);
    const std::size_t half = (n + 1) / 2;
    for (std::size_t k = 0; k < n / 2; ++k) {
        out[2 * k] = t[k];
        out[2 * k + 1] = t[half + k];
    }
    if (n % 2) out[n - 1] = t[half - 1];
}

}  // namespace

void exr_uncompress_rle(std::string_view packed, std::vector<std::uint8_t>& out, std::size_t raw_size) {
    std::vector<std::uint8_t> t;
    t.reserve(raw_size);
    std::size_t at = 0;
    while (at < packed.size()) {
        const auto count = static_cast<std::int8_t>(packed[at++]);
        if (count < 0) {
            const auto n = static_cast<std::size_t>(-count);
            if (packed.size() - at < n) throw ImageDecodeError("OpenEXR RLE chunk ends inside a literal run (corrupt chunk)");
            if (raw_size - t.size() < n) throw ImageDecodeError("OpenEXR RLE chunk decodes to more bytes than its pixels need");
            t.insert(t.end(), packed.begin() + static_cast<std::ptrdiff_t>(at), packed.begin() + static_cast<std::ptrdiff_t>(at + n));
            at += n;
        } else {
            const auto n = static_cast<std::size_t>(count) + 1;
            if (at >= packed.size()) throw ImageDecodeError("OpenEXR RLE chunk ends inside a repeat run (corrupt chunk)");
            if (raw_size - t.size() < n) throw ImageDecodeError("OpenEXR RLE chunk decodes to more bytes than its pixels need");
            t.insert(t.end(), n, static_cast<std::uint8_t>(packed[at++]));
        }
    }
    if (t.size() != raw_size)
        throw ImageDecodeError("OpenEXR RLE chunk decodes to " + std::to_string(t.size()) + " bytes; its pixels need " +
                               std::to_string(raw_size));
    undo_predictor_and_split(t, out);
}

void exr_uncompress_zip(std::string_view packed, std::vector<std::uint8_t>& out, std::size_t raw_size) {
    std::vector<std::uint8_t> t;
    try {
        t = zlib_decompress(packed, raw_size);
    } catch (const InflateError& e) {
        throw ImageDecodeError(std::string("OpenEXR ZIP chunk: ") + e.what());
    }
    undo_predictor_and_split(t, out);
}

}  // namespace spt
