// PIZ chunks of OpenEXR files. The stored chunk is:
//   - the range [min, max] of a bitmap over the 65536 16-bit values (which values occur; bit
//     0 is implied), and those bitmap bytes: the values are replaced by their rank among the
//     present ones, so the wavelet works on small numbers;
//   - a Huffman stream of the ranks after a 2-D Haar wavelet of each channel (and, for
//     32-bit channels, of each 16-bit half separately), with a run-length pseudo-symbol.
// Decoding runs that in reverse: Huffman, inverse wavelet, rank → value, and the per-channel
// planes back into scan lines.
#include <algorithm>
#include <array>
#include <string>

#include "io/exr_compression.h"
#include "io/image_decoders.h"

namespace spt {

namespace {

[[noreturn]] void fail(const std::string& what) { throw ImageDecodeError("OpenEXR PIZ chunk: " + what); }

constexpr int kSymbols = 65537;  // every 16-bit value and the run-length pseudo-symbol
constexpr int kMaxCodeLength = 58;
constexpr int kTableBits = 12;   // codes up to this long are decoded by one table lookup

/// Bits, most significant first.
class MsbBits {
public:
    MsbBits(std::string_view data, std::uint64_t nbits) : m_data(data), m_nbits(nbits) {}
    std::uint64_t left() const { return m_nbits - m_pos; }
    unsigned bit() {
        if (m_pos >= m_nbits) fail("the Huffman data ends early (corrupt chunk)");
        const unsigned b = (static_cast<unsigned char>(m_data[m_pos >> 3]) >> (7 - (m_pos & 7))) & 1u;
        ++m_pos;
        return b;
    }
    unsigned bits(int n) {
        unsigned v = 0;
        for (int i = 0; i < n; ++i) v = v << 1 | bit();
        return v;
    }
    /// The next `n` ≤ 24 bits without consuming them (past the end of the data: zeros; past
    /// the stated bit count: whatever follows, which a caller must not use).
    unsigned peek(int n) const {
        const std::size_t first = static_cast<std::size_t>(m_pos >> 3);
        std::uint32_t w = 0;
        for (std::size_t i = 0; i < 4; ++i)
            w = w << 8 | (first + i < m_data.size() ? static_cast<unsigned char>(m_data[first + i]) : 0u);
        return (w << (m_pos & 7)) >> (32 - n);
    }
    void skip(int n) { m_pos += static_cast<std::uint64_t>(n); }

private:
    std::string_view m_data;
    std::uint64_t m_nbits, m_pos = 0;
};

std::uint32_t le32(std::string_view s, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
    return v;
}

/// The canonical code of the OpenEXR Huffman coder: code lengths are assigned values from
/// the longest length down, and within a length in increasing symbol order.
class PizHuffman {
public:
    /// Reads the code lengths of symbols [lo, hi] (6 bits each; 59–62: a short run of unused
    /// symbols, 63 and 8 more bits: a long run).
    PizHuffman(MsbBits& table, unsigned lo, unsigned hi) : m_length(kSymbols, 0) {
        for (unsigned i = lo; i <= hi;) {
            const unsigned l = table.bits(6);
            if (l >= 59) {
                const unsigned run = l == 63 ? table.bits(8) + 6 : l - 59 + 2;
                if (i + run > hi + 1) fail("the code-length table runs past its last symbol");
                i += run;
            } else {
                m_length[i++] = static_cast<std::uint8_t>(l);
            }
        }
        std::array<std::uint64_t, kMaxCodeLength + 2> count{};
        for (int s = 0; s < kSymbols; ++s) ++count[m_length[static_cast<std::size_t>(s)]];
        std::uint64_t c = 0;
        for (int l = kMaxCodeLength; l > 0; --l) {
            m_first[static_cast<std::size_t>(l)] = c;
            c = (c + count[static_cast<std::size_t>(l)]) >> 1;
        }
        // Symbols sorted by length then value: code (first[l] + k) of length l is m_sorted[m_offset[l] + k].
        std::size_t offset = 0;
        for (int l = 1; l <= kMaxCodeLength; ++l) {
            m_offset[static_cast<std::size_t>(l)] = offset;
            m_count[static_cast<std::size_t>(l)] = count[static_cast<std::size_t>(l)];
            offset += count[static_cast<std::size_t>(l)];
        }
        m_sorted.resize(offset);
        std::array<std::size_t, kMaxCodeLength + 1> next{};
        for (int l = 1; l <= kMaxCodeLength; ++l) next[static_cast<std::size_t>(l)] = m_offset[static_cast<std::size_t>(l)];
        m_table.assign(std::size_t(1) << kTableBits, 0);
        for (int s = 0; s < kSymbols; ++s) {
            const unsigned l = m_length[static_cast<std::size_t>(s)];
            if (l == 0) continue;
            const std::size_t rank = next[l]++ - m_offset[l];
            m_sorted[m_offset[l] + rank] = static_cast<std::uint32_t>(s);
            const std::uint64_t code = m_first[l] + rank;
            if (l <= kTableBits && code < (std::uint64_t(1) << l)) {
                const std::size_t from = static_cast<std::size_t>(code << (kTableBits - l));
                const std::size_t to = static_cast<std::size_t>((code + 1) << (kTableBits - l));
                for (std::size_t e = from; e < to; ++e) m_table[e] = static_cast<std::uint32_t>(s) << 6 | l;
            }
        }
    }

    unsigned decode(MsbBits& in) const {
        const std::uint32_t e = m_table[in.peek(kTableBits)];
        if (e != 0 && (e & 63u) <= in.left()) {
            in.skip(static_cast<int>(e & 63u));
            return e >> 6;
        }
        std::uint64_t code = 0;
        for (std::size_t l = 1; l <= kMaxCodeLength; ++l) {
            code = code << 1 | in.bit();
            if (code >= m_first[l] && code - m_first[l] < m_count[l])
                return m_sorted[m_offset[l] + static_cast<std::size_t>(code - m_first[l])];
        }
        fail("invalid Huffman code");
    }

private:
    std::vector<std::uint8_t> m_length;
    std::array<std::uint64_t, kMaxCodeLength + 1> m_first{}, m_count{};
    std::array<std::size_t, kMaxCodeLength + 1> m_offset{};
    std::vector<std::uint32_t> m_sorted;
    std::vector<std::uint32_t> m_table;  ///< symbol << 6 | length; 0: not a short code
};

void huffman_decode(std::string_view s, std::vector<std::uint16_t>& out) {
    if (s.size() < 20) fail("the Huffman header is truncated");
    const std::uint32_t lo = le32(s, 0), hi = le32(s, 4), nbits = le32(s, 12);
    if (lo >= kSymbols || hi >= kSymbols || lo > hi) fail("the Huffman symbol range is invalid");
    std::string_view rest = s.substr(20);
    MsbBits table(rest, std::uint64_t(rest.size()) * 8);
    const PizHuffman code(table, lo, hi);
    const std::size_t table_bytes = static_cast<std::size_t>((std::uint64_t(rest.size()) * 8 - table.left() + 7) / 8);
    rest = rest.substr(table_bytes);
    if ((std::uint64_t(nbits) + 7) / 8 > rest.size()) fail("the Huffman data is longer than the chunk (truncated)");
    MsbBits in(rest, nbits);
    const unsigned run_symbol = hi;
    std::size_t n = 0;
    while (in.left() > 0) {
        const unsigned sym = code.decode(in);
        if (sym == run_symbol) {
            const unsigned repeat = in.bits(8);
            if (n == 0) fail("a run has no value before it");
            if (out.size() - n < repeat) fail("the Huffman data decodes to more values than the pixels need");
            std::fill_n(out.begin() + static_cast<std::ptrdiff_t>(n), repeat, out[n - 1]);
            n += repeat;
        } else {
            if (n >= out.size()) fail("the Huffman data decodes to more values than the pixels need");
            out[n++] = static_cast<std::uint16_t>(sym);
        }
    }
    if (n != out.size())
        fail("the Huffman data decodes to " + std::to_string(n) + " values; the pixels need " + std::to_string(out.size()));
}

/// The inverse of one Haar step on a pair (l, h) → (a, b). Values below 2^14 use the exact
/// signed form; larger ones the modular 16-bit form.
inline void haar_inverse14(std::uint16_t l, std::uint16_t h, std::uint16_t& a, std::uint16_t& b) {
    const int ls = static_cast<std::int16_t>(l), hs = static_cast<std::int16_t>(h);
    const int ai = ls + (hs & 1) + (hs >> 1);
    a = static_cast<std::uint16_t>(static_cast<std::int16_t>(ai));
    b = static_cast<std::uint16_t>(static_cast<std::int16_t>(ai - hs));
}
inline void haar_inverse16(std::uint16_t l, std::uint16_t h, std::uint16_t& a, std::uint16_t& b) {
    const int m = l, d = h;
    const int bb = (m - (d >> 1)) & 0xffff;
    a = static_cast<std::uint16_t>((d + bb - 0x8000) & 0xffff);
    b = static_cast<std::uint16_t>(bb);
}

/// The inverse 2-D wavelet of an nx × ny plane whose samples are `ox` apart along x and `oy`
/// along y, from the coarsest level to the finest.
void wavelet_decode(std::uint16_t* v, int nx, int ox, int ny, int oy, std::uint16_t max_value) {
    const bool small = max_value < (1 << 14);
    const auto pair = [small](std::uint16_t l, std::uint16_t h, std::uint16_t& a, std::uint16_t& b) {
        if (small) haar_inverse14(l, h, a, b);
        else haar_inverse16(l, h, a, b);
    };
    const int n = std::min(nx, ny);
    int top = 1;
    while (top <= n) top <<= 1;
    int step2 = top >> 1;  // the block size of the coarsest level
    for (int p = step2 >> 1; p >= 1; step2 = p, p >>= 1) {
        const auto at = [&](int x, int y) -> std::uint16_t& {
            return v[static_cast<std::ptrdiff_t>(y) * oy + static_cast<std::ptrdiff_t>(x) * ox];
        };
        int y = 0;
        for (; y <= ny - step2; y += step2) {
            int x = 0;
            for (; x <= nx - step2; x += step2) {
                std::uint16_t i00, i01, i10, i11;
                pair(at(x, y), at(x, y + p), i00, i10);
                pair(at(x + p, y), at(x + p, y + p), i01, i11);
                pair(i00, i01, at(x, y), at(x + p, y));
                pair(i10, i11, at(x, y + p), at(x + p, y + p));
            }
            if (nx & p) {  // a last column at this level: a vertical pair only
                std::uint16_t a;
                pair(at(x, y), at(x, y + p), a, at(x, y + p));
                at(x, y) = a;
            }
        }
        if (ny & p) {  // a last row at this level: horizontal pairs only
            for (int x = 0; x <= nx - step2; x += step2) {
                std::uint16_t a;
                pair(at(x, y), at(x + p, y), a, at(x + p, y));
                at(x, y) = a;
            }
        }
    }
}

}  // namespace

void exr_uncompress_piz(std::string_view s, std::vector<std::uint8_t>& out, std::size_t raw_size,
                        const std::vector<PizChannel>& channels) {
    std::size_t words = 0;
    for (const PizChannel& c : channels)
        words += static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.lines) * static_cast<std::size_t>(c.words);
    if (words * 2 != raw_size) fail("the channels do not add up to the chunk's size");
    if (s.size() < 4) fail("the bitmap range is truncated");
    const unsigned lo = static_cast<unsigned char>(s[0]) | static_cast<unsigned char>(s[1]) << 8;
    const unsigned hi = static_cast<unsigned char>(s[2]) | static_cast<unsigned char>(s[3]) << 8;
    std::array<std::uint8_t, 8192> bitmap{};
    std::size_t at = 4;
    if (lo <= hi) {
        if (hi >= bitmap.size()) fail("the bitmap range " + std::to_string(hi) + " is past 8191");
        if (s.size() - at < hi - lo + 1) fail("the bitmap is truncated");
        for (unsigned i = lo; i <= hi; ++i) bitmap[i] = static_cast<std::uint8_t>(s[at++]);
    }
    // Rank → value: value 0 always has rank 0.
    std::vector<std::uint16_t> value(65536, 0);
    unsigned ranks = 0;
    for (unsigned i = 0; i < 65536; ++i)
        if (i == 0 || (bitmap[i >> 3] >> (i & 7) & 1)) value[ranks++] = static_cast<std::uint16_t>(i);
    const auto max_rank = static_cast<std::uint16_t>(ranks - 1);
    if (s.size() - at < 4) fail("the Huffman data length is truncated");
    const std::uint32_t length = le32(s, at);
    at += 4;
    if (length > s.size() - at) fail("the Huffman data is longer than the chunk (truncated)");
    std::vector<std::uint16_t> plane(words);
    huffman_decode(s.substr(at, length), plane);
    // The planes: channel after channel, each width × lines samples of `words` words.
    std::size_t start = 0;
    for (const PizChannel& c : channels) {
        for (int w = 0; w < c.words; ++w)
            wavelet_decode(plane.data() + start + static_cast<std::size_t>(w), c.width, c.words, c.lines, c.width * c.words,
                           max_rank);
        start += static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.lines) * static_cast<std::size_t>(c.words);
    }
    for (std::uint16_t& v : plane) v = value[v];
    // Scan line after scan line, channel after channel, little-endian words.
    out.resize(raw_size);
    std::vector<std::size_t> next(channels.size());
    start = 0;
    for (std::size_t k = 0; k < channels.size(); ++k) {
        next[k] = start;
        start += static_cast<std::size_t>(channels[k].width) * static_cast<std::size_t>(channels[k].lines) *
                 static_cast<std::size_t>(channels[k].words);
    }
    std::size_t o = 0;
    const int lines = channels.empty() ? 0 : channels[0].lines;
    for (int y = 0; y < lines; ++y)
        for (std::size_t k = 0; k < channels.size(); ++k) {
            const std::size_t n = static_cast<std::size_t>(channels[k].width) * static_cast<std::size_t>(channels[k].words);
            for (std::size_t i = 0; i < n; ++i) {
                const std::uint16_t v = plane[next[k] + i];
                out[o++] = static_cast<std::uint8_t>(v & 0xff);
                out[o++] = static_cast<std::uint8_t>(v >> 8);
            }
            next[k] += n;
        }
}

}  // namespace spt
