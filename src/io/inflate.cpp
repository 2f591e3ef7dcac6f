// Canonical-Huffman DEFLATE decoder in the manner of zlib's "puff" reference decoder
// (counts per code length, symbols sorted by code), with a 64-bit bit buffer and a table for
// codes up to 9 bits (nearly every symbol of real streams), so that a compressed 8k × 4k
// environment map inflates in about a second; each step checks its bounds.
#include "io/inflate.h"

#include "io/checksums.h"

#include <algorithm>
#include <array>
#include <string>

namespace spt {

namespace {

constexpr int kMaxBits = 15;  // longest DEFLATE code

/// Bits of the stream, least significant first (RFC 1951 §3.1.1), through a 64-bit buffer.
class BitReader {
public:
    explicit BitReader(std::string_view data) : m_data(data) {}

    unsigned bits(int n) {
        if (n == 0) return 0;
        need(n);
        const auto v = static_cast<unsigned>(m_buffer & ((std::uint64_t(1) << n) - 1));
        drop(n);
        return v;
    }
    unsigned bit() { return bits(1); }
    /// The next `n` ≤ 32 bits without consuming them; zeros past the end of the data (the
    /// caller checks with available() before using them).
    unsigned peek(int n) {
        if (m_count < n) refill();
        return static_cast<unsigned>(m_buffer & ((std::uint64_t(1) << n) - 1));
    }
    int available() const { return m_count; }
    void drop(int n) { m_buffer >>= n, m_count -= n; }
    /// Skips to the next byte boundary (stored blocks start there).
    void align() { drop(m_count % 8); }
    std::uint8_t byte() { return static_cast<std::uint8_t>(bits(8)); }
    /// Bytes consumed so far (after align()).
    std::size_t position() const { return m_pos - static_cast<std::size_t>(m_count / 8); }

private:
    std::string_view m_data;
    std::size_t m_pos = 0;  ///< the next byte to load into the buffer
    std::uint64_t m_buffer = 0;
    int m_count = 0;  ///< bits in the buffer

    void refill() {
        while (m_count <= 56 && m_pos < m_data.size()) {
            m_buffer |= std::uint64_t(static_cast<unsigned char>(m_data[m_pos++])) << m_count;
            m_count += 8;
        }
    }
    void need(int n) {
        if (m_count < n) refill();
        if (m_count < n) throw InflateError("the compressed data ends early (truncated stream)");
    }
};

/// A canonical Huffman code: how many codes of each length, and the symbols in code order;
/// codes up to kFastBits long are also in a table indexed by the stream's next bits.
struct Huffman {
    static constexpr int kFastBits = 9;
    std::array<std::uint16_t, kMaxBits + 1> count{};
    std::vector<std::uint16_t> symbol;
    std::array<std::uint16_t, 1u << kFastBits> fast{};  ///< symbol << 4 | length; 0: a longer code

    /// Builds the code from each symbol's length (0: unused). Over-subscribed sets are an
    /// error; incomplete ones are allowed (RFC 1951 permits a single distance code).
    Huffman(const std::uint8_t* lengths, int n, const char* what) : symbol(static_cast<std::size_t>(n)) {
        for (int s = 0; s < n; ++s) ++count[lengths[s]];
        int left = 1;
        for (int len = 1; len <= kMaxBits; ++len) {
            left = left * 2 - count[len];
            if (left < 0) throw InflateError(std::string("invalid ") + what + " code (over-subscribed lengths)");
        }
        std::array<std::uint16_t, kMaxBits + 2> offset{};
        for (int len = 1; len <= kMaxBits; ++len) offset[len + 1] = offset[len] + count[len];
        for (int s = 0; s < n; ++s)
            if (lengths[s] != 0) symbol[offset[lengths[s]]++] = static_cast<std::uint16_t>(s);
        // The codes in order (RFC 1951 §3.2.2), bit-reversed: the stream sends them first bit first.
        std::array<unsigned, kMaxBits + 1> next{};
        unsigned code = 0;
        for (int len = 1; len <= kMaxBits; ++len) {
            code = (code + (len == 1 ? 0u : count[len - 1])) << 1;
            next[len] = code;
        }
        for (int s = 0; s < n; ++s) {
            const int len = lengths[s];
            if (len == 0) continue;
            const unsigned c = next[len]++;
            if (len > kFastBits) continue;
            unsigned reversed = 0;
            for (int i = 0; i < len; ++i) reversed |= ((c >> i) & 1u) << (len - 1 - i);
            for (unsigned e = reversed; e < (1u << kFastBits); e += 1u << len)
                fast[e] = static_cast<std::uint16_t>(s << 4 | len);
        }
    }

    int decode(BitReader& in) const {
        const std::uint16_t e = fast[in.peek(kFastBits)];
        if (e != 0 && (e & 15) <= in.available()) {
            in.drop(e & 15);
            return e >> 4;
        }
        int code = 0, first = 0, index = 0;
        for (int len = 1; len <= kMaxBits; ++len) {
            code |= static_cast<int>(in.bit());
            const int c = count[len];
            if (code - c < first) return symbol[static_cast<std::size_t>(index + (code - first))];
            index += c, first += c;
            first <<= 1, code <<= 1;
        }
        throw InflateError("invalid Huffman code in the compressed data");
    }
};

constexpr std::uint16_t kLengthBase[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                           31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::uint8_t kLengthExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                           2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr std::uint16_t kDistBase[30] = {1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
                                         193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr std::uint8_t kDistExtra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6,
                                         6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

class Inflater {
public:
    Inflater(std::string_view data, std::size_t expected) : m_in(data), m_expected(expected) {
        // DEFLATE expands at most 1032:1, so a small stream cannot reserve much.
        m_out.reserve(std::min(expected, data.size() * 1032 + 64));
    }

    std::vector<std::uint8_t> run() {
        bool last = false;
        while (!last) {
            last = m_in.bit() != 0;
            switch (m_in.bits(2)) {
                case 0: stored(); break;
                case 1: fixed(); break;
                case 2: dynamic(); break;
                default: throw InflateError("invalid block type 3 in the compressed data");
            }
        }
        return std::move(m_out);
    }
    std::size_t consumed() {
        m_in.align();
        return m_in.position();
    }

private:
    BitReader m_in;
    std::size_t m_expected;
    std::vector<std::uint8_t> m_out;

    void put(std::uint8_t b) {
        if (m_out.size() >= m_expected) throw InflateError("the decompressed data is longer than the image needs");
        m_out.push_back(b);
    }

    void stored() {
        m_in.align();
        const unsigned len = m_in.byte() | m_in.byte() << 8;
        const unsigned nlen = m_in.byte() | m_in.byte() << 8;
        if ((len ^ 0xffffu) != nlen) throw InflateError("a stored block's length does not match its complement");
        for (unsigned i = 0; i < len; ++i) put(m_in.byte());
    }

    void fixed() {
        static const auto codes = [] {
            std::array<std::uint8_t, 288 + 30> l{};
            for (int s = 0; s < 144; ++s) l[s] = 8;
            for (int s = 144; s < 256; ++s) l[s] = 9;
            for (int s = 256; s < 280; ++s) l[s] = 7;
            for (int s = 280; s < 288; ++s) l[s] = 8;
            for (int s = 0; s < 30; ++s) l[288 + s] = 5;
            return std::pair<Huffman, Huffman>{Huffman(l.data(), 288, "literal/length"),
                                               Huffman(l.data() + 288, 30, "distance")};
        }();
        codes_block(codes.first, codes.second);
    }

    void dynamic() {
        const int nlen = static_cast<int>(m_in.bits(5)) + 257, ndist = static_cast<int>(m_in.bits(5)) + 1;
        const int ncode = static_cast<int>(m_in.bits(4)) + 4;
        if (nlen > 286 || ndist > 30) throw InflateError("a dynamic block declares too many codes");
        static constexpr int kOrder[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
        std::uint8_t lengths[286 + 30] = {};
        for (int i = 0; i < ncode; ++i) lengths[kOrder[i]] = static_cast<std::uint8_t>(m_in.bits(3));
        const Huffman lencode(lengths, 19, "code-length");
        int index = 0;
        while (index < nlen + ndist) {
            int sym = lencode.decode(m_in);
            if (sym < 16) {
                lengths[index++] = static_cast<std::uint8_t>(sym);
                continue;
            }
            std::uint8_t len = 0;
            int repeat;
            if (sym == 16) {
                if (index == 0) throw InflateError("a length repeat has no previous length");
                len = lengths[index - 1];
                repeat = 3 + static_cast<int>(m_in.bits(2));
            } else if (sym == 17) {
                repeat = 3 + static_cast<int>(m_in.bits(3));
            } else {
                repeat = 11 + static_cast<int>(m_in.bits(7));
            }
            if (index + repeat > nlen + ndist) throw InflateError("code lengths run past their count");
            while (repeat--) lengths[index++] = len;
        }
        if (lengths[256] == 0) throw InflateError("a dynamic block has no end-of-block code");
        codes_block(Huffman(lengths, nlen, "literal/length"), Huffman(lengths + nlen, ndist, "distance"));
    }

    void codes_block(const Huffman& lencode, const Huffman& distcode) {
        for (;;) {
            int sym = lencode.decode(m_in);
            if (sym < 256) {
                put(static_cast<std::uint8_t>(sym));
                continue;
            }
            if (sym == 256) return;
            sym -= 257;
            if (sym >= 29) throw InflateError("invalid length symbol in the compressed data");
            const unsigned len = kLengthBase[sym] + m_in.bits(kLengthExtra[sym]);
            const int dsym = distcode.decode(m_in);
            if (dsym >= 30) throw InflateError("invalid distance symbol in the compressed data");
            const std::size_t dist = kDistBase[dsym] + m_in.bits(kDistExtra[dsym]);
            if (dist > m_out.size()) throw InflateError("a back-reference points before the start of the data");
            if (m_expected - m_out.size() < len) throw InflateError("the decompressed data is longer than the image needs");
            for (unsigned i = 0; i < len; ++i) {
                const std::uint8_t b = m_out[m_out.size() - dist];
                m_out.push_back(b);
            }
        }
    }
};

}  // namespace

bool is_gzip(std::string_view data) {
    return data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f && static_cast<unsigned char>(data[1]) == 0x8b;
}

std::string gzip_decompress(std::string_view file) {
    if (!is_gzip(file) || file.size() < 18) throw InflateError("not a gzip file (too short or no gzip magic bytes)");
    const auto byte = [&](std::size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(file[i])); };
    const auto le32 = [&](std::size_t i) {
        return static_cast<std::uint32_t>(byte(i) | byte(i + 1) << 8 | byte(i + 2) << 16 | byte(i + 3) << 24);
    };
    if (byte(2) != 8) throw InflateError("the gzip header does not announce DEFLATE");
    const unsigned flags = byte(3);
    if (flags & 0xe0) throw InflateError("the gzip header has reserved flag bits set");
    std::size_t at = 10;
    const std::size_t body_end = file.size() - 8;
    if (flags & 0x04) {  // FEXTRA: a length and that many bytes
        if (at + 2 > body_end) throw InflateError("the gzip header is truncated");
        at += 2 + (byte(at) | byte(at + 1) << 8);
    }
    for (const unsigned text_field : {0x08u, 0x10u}) {  // FNAME, FCOMMENT: zero-terminated
        if (!(flags & text_field)) continue;
        while (at < body_end && file[at] != 0) ++at;
        ++at;
    }
    if (flags & 0x02) at += 2;  // FHCRC
    if (at >= body_end) throw InflateError("the gzip header is truncated");
    const std::uint32_t size = le32(file.size() - 4);
    Inflater inflater(file.substr(at, body_end - at), size);
    const std::vector<std::uint8_t> out = inflater.run();
    if (at + inflater.consumed() != body_end)
        throw InflateError("the gzip file has data after its first member; expected one member");
    if (out.size() != size)
        throw InflateError("the decompressed data has " + std::to_string(out.size()) + " bytes; the gzip trailer says " +
                           std::to_string(size));
    std::string text(reinterpret_cast<const char*>(out.data()), out.size());
    if (crc32(text) != le32(file.size() - 8)) throw InflateError("the CRC-32 does not match the decompressed data");
    return text;
}

std::vector<std::uint8_t> zlib_decompress(std::string_view stream, std::size_t expected_size) {
    if (stream.size() < 6) throw InflateError("the zlib stream is too short");
    const unsigned cmf = static_cast<unsigned char>(stream[0]), flg = static_cast<unsigned char>(stream[1]);
    if ((cmf & 0x0f) != 8 || (cmf >> 4) > 7) throw InflateError("the zlib header does not announce DEFLATE");
    if ((cmf << 8 | flg) % 31 != 0) throw InflateError("the zlib header check bits are wrong");
    if (flg & 0x20) throw InflateError("the zlib stream asks for a preset dictionary, which PNG forbids");
    Inflater inflater(stream.substr(2), expected_size);
    std::vector<std::uint8_t> out = inflater.run();
    if (out.size() != expected_size)
        throw InflateError("the decompressed data has " + std::to_string(out.size()) + " bytes; expected " +
                           std::to_string(expected_size));
    const std::size_t end = 2 + inflater.consumed();
    if (end + 4 > stream.size()) throw InflateError("the zlib stream has no Adler-32 checksum (truncated)");
    std::uint32_t stored = 0;
    for (int i = 0; i < 4; ++i) stored = stored << 8 | static_cast<unsigned char>(stream[end + i]);
    const std::uint32_t computed =
        adler32(std::string_view(reinterpret_cast<const char*>(out.data()), out.size()));
    if (stored != computed) throw InflateError("the Adler-32 checksum does not match the decompressed data");
    return out;
}

}  // namespace spt
