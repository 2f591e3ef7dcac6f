// 8-bit sRGB PNG (exposure, tone curve, sRGB OETF) with our own zlib stream: hashed LZ77, then
// per block the smallest of stored, fixed-Huffman and dynamic-Huffman deflate; per-row adaptive
// filtering; CRC32 and Adler-32.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <queue>
#include <utility>
#include <vector>

#include "io/checksums.h"
#include "io/image_encoders.h"
#include "io/tone_map.h"

namespace spt {
namespace {

// ---- deflate (RFC 1951) ---------------------------------------------------------------------

class BitWriter {
public:
    explicit BitWriter(std::string& out) : out_(out) {}
    /// Appends the low `count` bits of `bits`, least significant first (deflate's bit order).
    void put(std::uint32_t bits, int count) {
        acc_ |= static_cast<std::uint64_t>(bits) << used_;
        used_ += count;
        for (; used_ >= 8; used_ -= 8, acc_ >>= 8) out_.push_back(static_cast<char>(acc_ & 0xff));
    }
    /// Huffman codes are defined most significant bit first, so they go in reversed.
    void put_code(std::uint32_t code, int length) {
        std::uint32_t reversed = 0;
        for (int i = 0; i < length; ++i) reversed |= ((code >> i) & 1) << (length - 1 - i);
        put(reversed, length);
    }
    void align() {
        if (used_ > 0) put(0, 8 - used_);
    }
    int pending_bits() const { return used_; }

private:
    std::string& out_;
    std::uint64_t acc_ = 0;
    int used_ = 0;
};

constexpr std::array<int, 29> kLengthBase = {3,  4,  5,  6,  7,  8,  9,  10,  11,  13,
                                             15, 17, 19, 23, 27, 31, 35, 43,  51,  59,
                                             67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::array<int, 29> kLengthExtra = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                              2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr std::array<int, 30> kDistBase = {1,    2,    3,    4,    5,    7,     9,     13,
                                           17,   25,   33,   49,   65,   97,    129,   193,
                                           257,  385,  513,  769,  1025, 1537,  2049,  3073,
                                           4097, 6145, 8193, 12289, 16385, 24577};
constexpr std::array<int, 30> kDistExtra = {0, 0, 0, 0, 1, 1, 2, 2,  3,  3,  4,  4,  5,  5,  6,
                                            6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

/// Index of the last base <= value.
template <std::size_t N>
int code_index(const std::array<int, N>& base, int value) {
    return static_cast<int>(std::upper_bound(base.begin(), base.end(), value) - base.begin()) - 1;
}

/// A canonical prefix code (RFC 1951, 3.2.2), given by its code lengths.
struct PrefixCode {
    std::vector<int> lengths;
    std::vector<std::uint32_t> codes;
};

PrefixCode canonical_code(std::vector<int> lengths) {
    std::array<std::uint32_t, 17> count{}, next{};
    for (int len : lengths) count[len] += len > 0;
    for (int bits = 1; bits <= 16; ++bits) next[bits] = (next[bits - 1] + count[bits - 1]) << 1;
    std::vector<std::uint32_t> codes(lengths.size());
    for (std::size_t i = 0; i < lengths.size(); ++i) {
        if (lengths[i] > 0) codes[i] = next[lengths[i]]++;
    }
    return {std::move(lengths), std::move(codes)};
}

/// Huffman code lengths of at most `limit` bits (needs freq.size() <= 2^limit). At least two
/// symbols get a code so that the code is complete (strict inflaters reject incomplete codes).
/// Too deep trees are rebuilt from flattened frequencies: simple, and rarely needed.
std::vector<int> huffman_lengths(std::vector<std::uint64_t> freq, int limit) {
    const int n = static_cast<int>(freq.size());
    for (int i = 0, used = static_cast<int>(std::count_if(freq.begin(), freq.end(),
                                                            [](auto f) { return f > 0; }));
         used < 2; ++i) {
        if (freq[i] == 0) freq[i] = 1, ++used;
    }
    for (;;) {
        using Node = std::pair<std::uint64_t, int>;  // weight, node (ties broken by node id)
        std::priority_queue<Node, std::vector<Node>, std::greater<>> heap;
        std::vector<int> parent(2 * n, -1);
        for (int i = 0; i < n; ++i) {
            if (freq[i] > 0) heap.push({freq[i], i});
        }
        for (int next = n; heap.size() > 1; ++next) {
            const Node a = heap.top();
            heap.pop();
            const Node b = heap.top();
            heap.pop();
            parent[a.second] = parent[b.second] = next;
            heap.push({a.first + b.first, next});
        }
        std::vector<int> lengths(n, 0);
        int deepest = 0;
        for (int i = 0; i < n; ++i) {
            for (int node = i; freq[i] > 0 && parent[node] >= 0; node = parent[node]) ++lengths[i];
            deepest = std::max(deepest, lengths[i]);
        }
        if (deepest <= limit) return lengths;
        for (auto& f : freq) f = (f + 1) / 2;  // keeps used symbols used
    }
}

struct Token {
    int length;  ///< 0 for a literal
    int value;   ///< the literal byte, or the match distance
};

int litlen_symbol(const Token& t) {
    return t.length == 0 ? t.value : 257 + code_index(kLengthBase, t.length);
}

/// The literal/length and distance codes of one block.
struct BlockCodes {
    PrefixCode litlen, dist;
};

BlockCodes fixed_codes() {  // RFC 1951, 3.2.6
    std::vector<int> litlen(288, 8);
    std::fill(litlen.begin() + 144, litlen.begin() + 256, 9);
    std::fill(litlen.begin() + 256, litlen.begin() + 280, 7);
    return {canonical_code(litlen), canonical_code(std::vector<int>(30, 5))};
}

long token_bits(const BlockCodes& c, const std::vector<Token>& tokens) {
    long bits = c.litlen.lengths[256];  // end of block
    for (const Token& t : tokens) {
        bits += c.litlen.lengths[litlen_symbol(t)];
        if (t.length > 0) {
            const int l = code_index(kLengthBase, t.length), d = code_index(kDistBase, t.value);
            bits += kLengthExtra[l] + c.dist.lengths[d] + kDistExtra[d];
        }
    }
    return bits;
}

void put_symbol(BitWriter& bits, const PrefixCode& code, int symbol) {
    bits.put_code(code.codes[symbol], code.lengths[symbol]);
}

void put_tokens(BitWriter& bits, const BlockCodes& c, const std::vector<Token>& tokens) {
    for (const Token& t : tokens) {
        put_symbol(bits, c.litlen, litlen_symbol(t));
        if (t.length > 0) {
            const int l = code_index(kLengthBase, t.length), d = code_index(kDistBase, t.value);
            bits.put(static_cast<std::uint32_t>(t.length - kLengthBase[l]), kLengthExtra[l]);
            put_symbol(bits, c.dist, d);
            bits.put(static_cast<std::uint32_t>(t.value - kDistBase[d]), kDistExtra[d]);
        }
    }
    put_symbol(bits, c.litlen, 256);
}

/// A dynamic-Huffman block header (RFC 1951, 3.2.7): the code lengths, run-length encoded
/// with symbols 16 (repeat previous), 17 and 18 (runs of zeros), themselves Huffman coded.
class DynamicHeader {
public:
    explicit DynamicHeader(const BlockCodes& c) {
        hlit_ = trimmed_size(c.litlen.lengths, 257);
        hdist_ = trimmed_size(c.dist.lengths, 1);
        std::vector<int> all(c.litlen.lengths.begin(), c.litlen.lengths.begin() + hlit_);
        all.insert(all.end(), c.dist.lengths.begin(), c.dist.lengths.begin() + hdist_);
        run_length_encode(all);
        std::vector<std::uint64_t> freq(19, 0);
        for (const Run& r : runs_) ++freq[r.symbol];
        code_ = canonical_code(huffman_lengths(freq, 7));
        hclen_ = 19;
        while (hclen_ > 4 && code_.lengths[kOrder[hclen_ - 1]] == 0) --hclen_;
    }
    long bits() const {
        long n = 5 + 5 + 4 + 3L * hclen_;
        for (const Run& r : runs_) n += code_.lengths[r.symbol] + r.extra_bits;
        return n;
    }
    void put(BitWriter& out) const {
        out.put(static_cast<std::uint32_t>(hlit_ - 257), 5);
        out.put(static_cast<std::uint32_t>(hdist_ - 1), 5);
        out.put(static_cast<std::uint32_t>(hclen_ - 4), 4);
        for (int i = 0; i < hclen_; ++i) {
            out.put(static_cast<std::uint32_t>(code_.lengths[kOrder[i]]), 3);
        }
        for (const Run& r : runs_) {
            put_symbol(out, code_, r.symbol);
            out.put(static_cast<std::uint32_t>(r.extra), r.extra_bits);
        }
    }

private:
    static constexpr std::array<int, 19> kOrder = {16, 17, 18, 0, 8,  7, 9,  6, 10, 5,
                                                   11, 4,  12, 3, 13, 2, 14, 1, 15};
    struct Run {
        int symbol, extra = 0, extra_bits = 0;
    };

    static int trimmed_size(const std::vector<int>& lengths, int minimum) {
        int n = static_cast<int>(lengths.size());
        while (n > minimum && lengths[n - 1] == 0) --n;
        return n;
    }
    void run_length_encode(const std::vector<int>& lengths) {
        const int n = static_cast<int>(lengths.size());
        for (int i = 0; i < n;) {
            int run = 1;
            while (i + run < n && lengths[i + run] == lengths[i]) ++run;
            if (lengths[i] == 0 && run >= 3) {
                const int r = std::min(run, 138);
                runs_.push_back(r >= 11 ? Run{18, r - 11, 7} : Run{17, r - 3, 3});
                i += r;
                continue;
            }
            runs_.push_back({lengths[i]});
            ++i, --run;
            for (; lengths[i - 1] != 0 && run >= 3; run -= std::min(run, 6)) {
                runs_.push_back({16, std::min(run, 6) - 3, 2});
                i += std::min(run, 6);
            }
        }
    }

    int hlit_ = 0, hdist_ = 0, hclen_ = 0;
    std::vector<Run> runs_;
    PrefixCode code_;
};

/// Greedy LZ77 over hash chains of 3-byte prefixes; matches stay inside [begin, end) but may
/// reach back into earlier blocks (the 32 KiB window spans blocks).
class Matcher {
public:
    explicit Matcher(const std::vector<std::uint8_t>& data)
        : data_(data), head_(1 << kHashBits, -1), prev_(kWindow, -1) {}

    std::vector<Token> tokenize(int begin, int end) {
        std::vector<Token> tokens;
        int pos = begin;
        while (pos < end) {
            const Token t = longest_match(pos, end);
            const int advance = t.length == 0 ? 1 : t.length;
            for (int i = 0; i < advance; ++i) insert(pos + i);
            tokens.push_back(t);
            pos += advance;
        }
        return tokens;
    }

private:
    static constexpr int kWindow = 32768, kHashBits = 15, kMaxChain = 48;
    static constexpr int kMinMatch = 3, kMaxMatch = 258;

    int hash(int pos) const {
        const std::uint32_t key = data_[pos] | data_[pos + 1] << 8 | data_[pos + 2] << 16;
        return static_cast<int>((key * 2654435761u) >> (32 - kHashBits));
    }
    void insert(int pos) {
        if (pos + kMinMatch > static_cast<int>(data_.size())) return;
        const int h = hash(pos);
        prev_[pos & (kWindow - 1)] = head_[h];
        head_[h] = pos;
    }
    Token longest_match(int pos, int end) const {
        Token best{0, data_[pos]};
        const int max_length = std::min(kMaxMatch, end - pos);
        if (max_length < kMinMatch) return best;
        int candidate = head_[hash(pos)];
        // A position's prev_ slot is reused only when the position kWindow later is inserted,
        // so the links are valid as long as the distance check holds.
        for (int steps = 0; candidate >= 0 && pos - candidate <= kWindow && steps < kMaxChain;
             ++steps, candidate = prev_[candidate & (kWindow - 1)]) {
            const int floor = std::max(best.length, kMinMatch - 1);
            if (data_[candidate + floor] != data_[pos + floor]) continue;  // cannot beat best
            int length = 0;
            while (length < max_length && data_[candidate + length] == data_[pos + length]) {
                ++length;
            }
            if (length > best.length && length >= kMinMatch) {
                best = {length, pos - candidate};
                if (length == max_length) break;
            }
        }
        return best;
    }

    const std::vector<std::uint8_t>& data_;
    std::vector<int> head_, prev_;
};

/// A zlib stream (RFC 1950) holding `data`. Each block is written stored, fixed-Huffman or
/// dynamic-Huffman, whichever takes fewest bits.
std::string zlib_compress(const std::vector<std::uint8_t>& data) {
    // Stored blocks hold at most 65535 bytes; smaller blocks also let the codes adapt.
    constexpr int kBlockSize = 1 << 15;
    std::string out = {0x78, 0x5E};  // deflate, 32 KiB window, "fast" level; header % 31 == 0
    BitWriter bits(out);
    Matcher matcher(data);
    const BlockCodes fixed = fixed_codes();
    const int size = static_cast<int>(data.size());
    int begin = 0;
    do {
        const int end = std::min(size, begin + kBlockSize);
        const std::uint32_t final_block = end == size ? 1 : 0;
        const std::vector<Token> tokens = matcher.tokenize(begin, end);

        std::vector<std::uint64_t> litlen_freq(286, 0), dist_freq(30, 0);
        litlen_freq[256] = 1;
        for (const Token& t : tokens) {
            ++litlen_freq[litlen_symbol(t)];
            if (t.length > 0) ++dist_freq[code_index(kDistBase, t.value)];
        }
        const BlockCodes dynamic = {canonical_code(huffman_lengths(litlen_freq, 15)),
                                    canonical_code(huffman_lengths(dist_freq, 15))};
        const DynamicHeader header(dynamic);
        const long fixed_bits = token_bits(fixed, tokens);
        const long dynamic_bits = header.bits() + token_bits(dynamic, tokens);
        const long stored_bits = (8 - (bits.pending_bits() + 3) % 8) % 8 + 32 + 8L * (end - begin);

        if (stored_bits < std::min(fixed_bits, dynamic_bits)) {
            bits.put(final_block, 3);  // BTYPE 00
            bits.align();
            const auto length = static_cast<std::uint32_t>(end - begin);
            bits.put(length, 16);
            bits.put(~length & 0xffff, 16);
            out.append(reinterpret_cast<const char*>(data.data()) + begin, end - begin);
        } else if (fixed_bits <= dynamic_bits) {
            bits.put(final_block | 1u << 1, 3);  // BTYPE 01
            put_tokens(bits, fixed, tokens);
        } else {
            bits.put(final_block | 2u << 1, 3);  // BTYPE 10
            header.put(bits);
            put_tokens(bits, dynamic, tokens);
        }
        begin = end;
    } while (begin < size);
    bits.align();
    const std::uint32_t check = adler32(std::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>(check >> shift));
    return out;
}

// ---- PNG (ISO/IEC 15948) --------------------------------------------------------------------

void append_be32(std::string& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>(v >> shift));
}

void append_chunk(std::string& out, const char* type, const std::string& data) {
    append_be32(out, static_cast<std::uint32_t>(data.size()));
    const std::size_t start = out.size();
    out += type;
    out += data;
    append_be32(out, crc32(std::string_view(out).substr(start)));  // CRC covers type and data
}

/// 8-bit sRGB code of a display-linear value in [0, 1] (IEC 61966-2-1 OETF).
std::uint8_t to_srgb8(double v) {
    const double s = v < 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return static_cast<std::uint8_t>(std::lround(s * 255.0));
}

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

/// Filter-type byte + filtered row, choosing the filter with the smallest sum of |signed byte|
/// (the usual heuristic: small residuals compress best).
void append_filtered_row(std::vector<std::uint8_t>& out, const std::uint8_t* row,
                         const std::uint8_t* above, int row_bytes) {
    constexpr int kBpp = 3;
    std::array<std::vector<std::uint8_t>, 5> candidates;
    long best_cost = -1;
    int best = 0;
    for (int type = 0; type < 5; ++type) {
        std::vector<std::uint8_t>& f = candidates[type];
        f.resize(row_bytes);
        long cost = 0;
        for (int i = 0; i < row_bytes; ++i) {
            const int a = i >= kBpp ? row[i - kBpp] : 0, b = above ? above[i] : 0;
            const int c = i >= kBpp && above ? above[i - kBpp] : 0;
            const int predictor = type == 0 ? 0
                                  : type == 1 ? a
                                  : type == 2 ? b
                                  : type == 3 ? (a + b) / 2
                                              : paeth(a, b, c);
            f[i] = static_cast<std::uint8_t>(row[i] - predictor);
            cost += std::abs(static_cast<std::int8_t>(f[i]));
        }
        if (best_cost < 0 || cost < best_cost) best_cost = cost, best = type;
    }
    out.push_back(static_cast<std::uint8_t>(best));
    out.insert(out.end(), candidates[best].begin(), candidates[best].end());
}

}  // namespace

std::string encode_png(const Image& image, const ImageWriteOptions& options) {
    const int w = image.width, h = image.height, row_bytes = w * 3;
    const double scale = std::exp2(options.exposure_stops);
    std::vector<std::uint8_t> pixels(image.rgb.size());
    for (std::size_t i = 0; i < pixels.size(); i += 3) {
        const float* in = &image.rgb[i];
        const std::array<double, 3> display =
            tone_map(options.tone_map, {in[0] * scale, in[1] * scale, in[2] * scale});
        for (int c = 0; c < 3; ++c) pixels[i + c] = to_srgb8(display[c]);
    }

    std::vector<std::uint8_t> filtered;
    filtered.reserve(static_cast<std::size_t>(row_bytes + 1) * h);
    for (int y = 0; y < h; ++y) {
        const std::uint8_t* row = &pixels[static_cast<std::size_t>(y) * row_bytes];
        append_filtered_row(filtered, row, y > 0 ? row - row_bytes : nullptr, row_bytes);
    }

    std::string out = "\x89PNG\r\n\x1a\n";
    std::string header;
    append_be32(header, static_cast<std::uint32_t>(w));
    append_be32(header, static_cast<std::uint32_t>(h));
    header += {8, 2, 0, 0, 0};  // 8-bit, truecolour RGB, deflate, adaptive filter, no interlace
    append_chunk(out, "IHDR", header);
    append_chunk(out, "sRGB", std::string(1, '\0'));  // rendering intent: perceptual
    std::string gamma;
    append_be32(gamma, 45455);  // 1/2.2, for readers that ignore sRGB (as the spec recommends)
    append_chunk(out, "gAMA", gamma);
    // Several IDAT chunks of bounded size, as streaming readers prefer.
    constexpr std::size_t kIdatSize = 1 << 16;
    const std::string stream = zlib_compress(filtered);
    for (std::size_t at = 0; at < stream.size(); at += kIdatSize) {
        append_chunk(out, "IDAT", stream.substr(at, kIdatSize));
    }
    append_chunk(out, "IEND", "");
    return out;
}

}  // namespace spt
