// Tests for the image writers: each file is parsed back by an independent reader written here
// (PPM, PFM, EXR header + offsets, PNG chunks + a small inflater) and for the atomic file write.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/image.h"
#include "io/image_writer.h"
#include "io/tone_map.h"
#include "exr_reader.h"

namespace spt {
namespace {

using exr_test::le32;
using exr_test::le64;
using exr_test::le_float;
using exr_test::parse_exr_header;
using exr_test::read_cstring;

namespace fs = std::filesystem;

Image make_image(int w, int h, const std::function<float(int, int, int)>& value) {
    Image image{w, h, std::vector<float>(static_cast<std::size_t>(w) * h * 3)};
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = value(x, y, c);
        }
    }
    return image;
}

std::uint32_t be32(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = v << 8 | static_cast<std::uint8_t>(s.at(at + i));
    return v;
}

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A fresh directory per test, removed afterwards.
class TempDir : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               (std::string("spt_io_") + info->test_suite_name() + "_" + info->name() + "_" +
                std::to_string(std::random_device{}()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename());
        return names;
    }
    bool has_temp_file() const {
        for (const std::string& name : entries()) {
            if (name.find(".tmp-") != std::string::npos) return true;
        }
        return false;
    }
    fs::path dir_;
};

// ---- format from path -----------------------------------------------------------------------

TEST(ImageFormatFromPath, ByExtensionCaseInsensitive) {
    EXPECT_EQ(image_format_from_path("x.PNG"), ImageFormat::Png);
    EXPECT_EQ(image_format_from_path(".PNG"), ImageFormat::Png);
    EXPECT_EQ(image_format_from_path("out/render.exr"), ImageFormat::Exr);
    EXPECT_EQ(image_format_from_path("a.b.pfm"), ImageFormat::Pfm);
    EXPECT_EQ(image_format_from_path("a.PpM"), ImageFormat::Ppm);
    EXPECT_EQ(image_format_from_path("noext"), std::nullopt);
    EXPECT_EQ(image_format_from_path("dir.png/noext"), std::nullopt);
    EXPECT_EQ(image_format_from_path("x.bmp"), std::nullopt);
    EXPECT_EQ(image_format_from_path(".bmp"), std::nullopt);
}

// ---- PPM ------------------------------------------------------------------------------------

struct Ppm {
    std::string max_comment;
    int width = 0, height = 0;
    std::uint64_t maxval = 0;
    std::vector<std::uint64_t> values;
};

Ppm parse_ppm(const std::string& text) {
    std::istringstream in(text);
    std::string magic, comment;
    std::getline(in, magic);
    std::getline(in, comment);
    EXPECT_EQ(magic, "P3");
    EXPECT_EQ(comment.rfind("#MAX=", 0), 0u) << comment;
    Ppm ppm;
    ppm.max_comment = comment.substr(5);
    in >> ppm.width >> ppm.height >> ppm.maxval;
    for (std::uint64_t q; in >> q;) ppm.values.push_back(q);
    EXPECT_TRUE(in.eof()) << "non-integer token in PPM body";
    return ppm;
}

TEST(PpmWriter, MaxCommentAndValuesReconstruct) {
    const Image image = make_image(7, 5, [](int x, int y, int c) {
        return 0.001f + 3.7f * std::sin(0.3f * x + 0.7f * y + c) * std::sin(0.3f * x + y + c);
    });
    float true_max = 0.0f;
    for (float v : image.rgb) true_max = std::max(true_max, v);

    const Ppm ppm = parse_ppm(encode_image(image, ImageFormat::Ppm, {}));
    EXPECT_EQ(std::strtof(ppm.max_comment.c_str(), nullptr), true_max);  // round-trips exactly
    EXPECT_EQ(ppm.width, 7);
    EXPECT_EQ(ppm.height, 5);
    EXPECT_EQ(ppm.maxval, 1ull << 25);
    ASSERT_EQ(ppm.values.size(), image.rgb.size());
    const double step = static_cast<double>(true_max) / static_cast<double>(ppm.maxval);
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        const float v = image.rgb[i];
        const double expected = v > 0.0f ? v : 0.0;  // negatives clamp to 0
        EXPECT_NEAR(static_cast<double>(ppm.values[i]) * step, expected, step) << i;
        EXPECT_LE(ppm.values[i], ppm.maxval);
    }
}

TEST(PpmWriter, NegativeAndNonFiniteClampToZero) {
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Image image{2, 1, {-1.0f, nan, inf, 0.5f, 2.0f, -inf}};
    ImageWriteOptions options;
    options.color_resolution = 1000;
    const Ppm ppm = parse_ppm(encode_image(image, ImageFormat::Ppm, options));
    EXPECT_EQ(ppm.max_comment, "2");  // infinity does not count towards the max
    EXPECT_EQ(ppm.maxval, 1000u);
    EXPECT_EQ(ppm.values, (std::vector<std::uint64_t>{0, 0, 0, 250, 1000, 0}));
}

TEST(PpmWriter, AllZeroImage) {
    const Image image{1, 2, std::vector<float>(6, 0.0f)};
    const Ppm ppm = parse_ppm(encode_image(image, ImageFormat::Ppm, {}));
    EXPECT_EQ(ppm.max_comment, "0");
    EXPECT_EQ(ppm.values, std::vector<std::uint64_t>(6, 0));
}

TEST(PpmWriter, RejectsZeroResolution) {
    ImageWriteOptions options;
    options.color_resolution = 0;
    EXPECT_THROW(encode_image(Image{1, 1, {1, 1, 1}}, ImageFormat::Ppm, options),
                 std::invalid_argument);
}

// ---- PFM ------------------------------------------------------------------------------------

TEST(PfmWriter, BitExactBottomToTop) {
    const Image image = make_image(3, 4, [](int x, int y, int c) {
        return y == 0 ? 100.0f + x * 3 + c : 0.1f * (y * 9 + x * 3 + c) - 0.55f;
    });
    const std::string bytes = encode_image(image, ImageFormat::Pfm, {});
    const std::string header = "PF\n3 4\n-1.0\n";
    ASSERT_EQ(bytes.substr(0, header.size()), header);
    ASSERT_EQ(bytes.size(), header.size() + image.rgb.size() * 4);
    for (int y = 0; y < 4; ++y) {
        const std::size_t row_start = header.size() + static_cast<std::size_t>(3 - y) * 3 * 3 * 4;
        for (int i = 0; i < 9; ++i) {
            EXPECT_EQ(std::bit_cast<std::uint32_t>(le_float(bytes, row_start + 4 * i)),
                      std::bit_cast<std::uint32_t>(image.pixel(0, y)[i]))
                << "y=" << y << " i=" << i;
        }
    }
    // The last stored row is the top row (values >= 100), the first stored row is not.
    EXPECT_EQ(le_float(bytes, bytes.size() - 4), 108.0f);
    EXPECT_LT(le_float(bytes, header.size()), 100.0f);
}

// ---- EXR ------------------------------------------------------------------------------------

TEST(ExrWriter, HeaderHasMagicVersionAttributesAndSortedChannels) {
    const Image image = make_image(5, 3, [](int x, int y, int c) { return x + 10.0f * y + c; });
    ImageWriteOptions options;
    options.chromaticities = {{0.7347f, 0.2653f}, {0.0f, 1.0f}, {0.0001f, -0.077f}, {0.32168f,
                                                                                      0.33767f}};
    const std::string s = encode_image(image, ImageFormat::Exr, options);
    EXPECT_EQ(le32(s, 0), 20000630u);
    EXPECT_EQ(le32(s, 4), 2u);  // version 2, no flags (single-part scanline)
    std::size_t at = 0;
    const auto attrs = parse_exr_header(s, at);

    const std::map<std::string, std::string> expected_types = {
        {"channels", "chlist"},         {"compression", "compression"},
        {"dataWindow", "box2i"},        {"displayWindow", "box2i"},
        {"lineOrder", "lineOrder"},     {"pixelAspectRatio", "float"},
        {"screenWindowCenter", "v2f"},  {"screenWindowWidth", "float"},
        {"chromaticities", "chromaticities"}};
    for (const auto& [name, type] : expected_types) {
        ASSERT_TRUE(attrs.count(name)) << name;
        EXPECT_EQ(attrs.at(name).type, type) << name;
    }
    EXPECT_EQ(attrs.at("compression").value, std::string(1, '\0'));
    EXPECT_EQ(attrs.at("lineOrder").value, std::string(1, '\0'));
    for (const char* window : {"dataWindow", "displayWindow"}) {
        const std::string& box = attrs.at(window).value;
        ASSERT_EQ(box.size(), 16u);
        EXPECT_EQ(le32(box, 0), 0u);
        EXPECT_EQ(le32(box, 4), 0u);
        EXPECT_EQ(le32(box, 8), 4u);
        EXPECT_EQ(le32(box, 12), 2u);
    }
    EXPECT_EQ(le_float(attrs.at("pixelAspectRatio").value, 0), 1.0f);
    EXPECT_EQ(le_float(attrs.at("screenWindowWidth").value, 0), 1.0f);

    const std::string& chroma = attrs.at("chromaticities").value;
    ASSERT_EQ(chroma.size(), 32u);
    const Chromaticities& c = options.chromaticities;
    const float expected_chroma[8] = {c.red[0],  c.red[1],  c.green[0], c.green[1],
                                      c.blue[0], c.blue[1], c.white[0], c.white[1]};
    for (int i = 0; i < 8; ++i) EXPECT_EQ(le_float(chroma, 4 * i), expected_chroma[i]) << i;

    // chlist: name, int32 pixel type, pLinear + 3 reserved, int32 x/y sampling; then a null.
    const std::string& chlist = attrs.at("channels").value;
    std::size_t p = 0;
    std::vector<std::string> names;
    while (chlist.at(p) != '\0') {
        names.push_back(read_cstring(chlist, p));
        EXPECT_EQ(le32(chlist, p), 2u) << "pixel type FLOAT";
        EXPECT_EQ(le32(chlist, p + 4), 0u);
        EXPECT_EQ(le32(chlist, p + 8), 1u);
        EXPECT_EQ(le32(chlist, p + 12), 1u);
        p += 16;
    }
    EXPECT_EQ(p + 1, chlist.size());
    EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R"}));
}

TEST(ExrWriter, PixelsReadBackViaOffsetTable) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Image image = make_image(6, 4, [](int x, int y, int c) {
        return std::ldexp(1.0f + 0.125f * c, x - y) * (x % 2 ? -1.0f : 1.0f);
    });
    image.pixel(1, 2)[1] = nan;
    image.pixel(5, 3)[0] = std::numeric_limits<float>::denorm_min();

    const std::string s = encode_image(image, ImageFormat::Exr, {});
    std::size_t at = 0;
    parse_exr_header(s, at);
    const std::size_t data_bytes = 6 * 3 * 4;
    for (int y = 0; y < 4; ++y) {
        const std::uint64_t offset = le64(s, at + 8 * y);
        ASSERT_LE(offset + 8 + data_bytes, s.size());
        EXPECT_EQ(le32(s, offset), static_cast<std::uint32_t>(y));
        EXPECT_EQ(le32(s, offset + 4), data_bytes);
        const int channel_of[3] = {2, 1, 0};  // stored B, G, R
        for (int k = 0; k < 3; ++k) {
            for (int x = 0; x < 6; ++x) {
                const std::size_t pos = offset + 8 + (static_cast<std::size_t>(k) * 6 + x) * 4;
                const float expected = image.pixel(x, y)[channel_of[k]];
                EXPECT_EQ(le32(s, pos), std::bit_cast<std::uint32_t>(expected))
                    << "x=" << x << " y=" << y << " k=" << k;
            }
        }
        if (y == 3) {
            EXPECT_EQ(offset + 8 + data_bytes, s.size());  // nothing trailing
        }
    }
}

// ---- PNG ------------------------------------------------------------------------------------

std::uint32_t reference_crc32(const std::string& bytes) {  // bitwise, unlike the writer's table
    std::uint32_t c = 0xFFFFFFFFu;
    for (char ch : bytes) {
        c ^= static_cast<std::uint8_t>(ch);
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return ~c;
}

struct PngChunk {
    std::string type, data;
};

std::vector<PngChunk> parse_png_chunks(const std::string& s) {
    EXPECT_EQ(s.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    std::vector<PngChunk> chunks;
    for (std::size_t at = 8; at < s.size();) {
        const std::uint32_t length = be32(s, at);
        PngChunk chunk{s.substr(at + 4, 4), s.substr(at + 8, length)};
        EXPECT_EQ(be32(s, at + 8 + length), reference_crc32(chunk.type + chunk.data))
            << "CRC of " << chunk.type;
        chunks.push_back(chunk);
        at += 12 + length;
    }
    return chunks;
}

/// A small inflater (after RFC 1951 and zlib's puff.c): zlib wrapper, stored, fixed and dynamic
/// blocks. Stricter than needed: prefix codes must be complete.
struct Inflated {
    std::vector<std::uint8_t> data;
    int stored_blocks = 0, fixed_blocks = 0, dynamic_blocks = 0;
};

class Inflater {
public:
    explicit Inflater(const std::string& zlib) : in_(zlib) {}

    Inflated run() {
        if (in_.size() < 6) throw std::runtime_error("zlib stream too short");
        const int cmf = byte(0), flg = byte(1);
        if ((cmf & 0x0f) != 8 || (cmf * 256 + flg) % 31 != 0 || (flg & 0x20)) {
            throw std::runtime_error("bad zlib header");
        }
        pos_ = 2;
        Inflated result;
        for (bool final_block = false; !final_block;) {
            final_block = bits(1);
            const int type = static_cast<int>(bits(2));
            if (type == 0) {
                ++result.stored_blocks;
                bit_count_ = 0;  // skip to the byte boundary
                const std::uint32_t len = bits(16), nlen = bits(16);
                if ((len ^ 0xffff) != nlen) throw std::runtime_error("bad stored length");
                for (std::uint32_t i = 0; i < len; ++i) result.data.push_back(next_byte());
            } else if (type == 1) {
                ++result.fixed_blocks;
                std::vector<int> litlen(288, 8);
                std::fill(litlen.begin() + 144, litlen.begin() + 256, 9);
                std::fill(litlen.begin() + 256, litlen.begin() + 280, 7);
                inflate_codes(result.data, Code(litlen), Code(std::vector<int>(32, 5)));
            } else if (type == 2) {
                ++result.dynamic_blocks;
                inflate_dynamic(result.data);
            } else {
                throw std::runtime_error("bad block type 3");
            }
        }
        std::uint32_t a = 1, b = 0;
        for (std::uint8_t v : result.data) a = (a + v) % 65521, b = (b + a) % 65521;
        if (pos_ + 4 != in_.size()) throw std::runtime_error("trailing or missing bytes");
        std::uint32_t adler = 0;
        for (int i = 0; i < 4; ++i) adler = adler << 8 | byte(pos_ + i);
        if (adler != (b << 16 | a)) throw std::runtime_error("Adler-32 mismatch");
        return result;
    }

private:
    /// A canonical prefix code: symbols sorted by code length, and counts per length.
    struct Code {
        explicit Code(const std::vector<int>& lengths) {
            for (int len : lengths) ++count[len];
            int left = 1;
            for (int len = 1; len <= 15; ++len) {
                left = 2 * left - count[len];
                if (left < 0) throw std::runtime_error("over-subscribed code");
            }
            if (left != 0) throw std::runtime_error("incomplete code");
            for (int len = 1; len <= 15; ++len) {
                for (std::size_t s = 0; s < lengths.size(); ++s) {
                    if (lengths[s] == len) symbols.push_back(static_cast<int>(s));
                }
            }
        }
        int count[16] = {};
        std::vector<int> symbols;
    };

    int byte(std::size_t at) const { return static_cast<std::uint8_t>(in_.at(at)); }
    std::uint8_t next_byte() { return static_cast<std::uint8_t>(byte(pos_++)); }
    std::uint32_t bits(int n) {  // least significant bit first
        std::uint32_t v = 0;
        for (int i = 0; i < n; ++i) {
            if (bit_count_ == 0) bit_buffer_ = next_byte(), bit_count_ = 8;
            v |= static_cast<std::uint32_t>(bit_buffer_ & 1) << i;
            bit_buffer_ >>= 1;
            --bit_count_;
        }
        return v;
    }
    int decode(const Code& h) {  // codes are read most significant bit first
        int code = 0, first = 0, index = 0;
        for (int len = 1; len <= 15; ++len) {
            code |= static_cast<int>(bits(1));
            if (code - h.count[len] < first) return h.symbols[index + (code - first)];
            index += h.count[len];
            first = (first + h.count[len]) << 1;
            code <<= 1;
        }
        throw std::runtime_error("bad code");
    }
    void inflate_dynamic(std::vector<std::uint8_t>& out) {
        static const int kOrder[19] = {16, 17, 18, 0,  8, 7,  9, 6,  10, 5,
                                       11, 4,  12, 3, 13, 2, 14, 1, 15};
        const int hlit = static_cast<int>(bits(5)) + 257, hdist = static_cast<int>(bits(5)) + 1;
        const int hclen = static_cast<int>(bits(4)) + 4;
        std::vector<int> cl_lengths(19, 0);
        for (int i = 0; i < hclen; ++i) cl_lengths[kOrder[i]] = static_cast<int>(bits(3));
        const Code cl(cl_lengths);
        std::vector<int> lengths;
        while (static_cast<int>(lengths.size()) < hlit + hdist) {
            const int sym = decode(cl);
            if (sym < 16) {
                lengths.push_back(sym);
                continue;
            }
            if (sym == 16 && lengths.empty()) throw std::runtime_error("repeat with no length");
            const int value = sym == 16 ? lengths.back() : 0;
            const int repeat = sym == 16 ? 3 + static_cast<int>(bits(2))
                               : sym == 17 ? 3 + static_cast<int>(bits(3))
                                           : 11 + static_cast<int>(bits(7));
            lengths.insert(lengths.end(), repeat, value);
        }
        if (static_cast<int>(lengths.size()) != hlit + hdist) throw std::runtime_error("overrun");
        if (lengths[256] == 0) throw std::runtime_error("no end-of-block code");
        inflate_codes(out, Code({lengths.begin(), lengths.begin() + hlit}),
                      Code({lengths.begin() + hlit, lengths.end()}));
    }
    void inflate_codes(std::vector<std::uint8_t>& out, const Code& litlen, const Code& dist) {
        static const int kLenBase[29] = {3,  4,  5,  6,  7,  8,  9,  10,  11,  13,
                                         15, 17, 19, 23, 27, 31, 35, 43,  51,  59,
                                         67, 83, 99, 115, 131, 163, 195, 227, 258};
        static const int kLenExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                          2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
        for (;;) {
            const int sym = decode(litlen);
            if (sym < 256) {
                out.push_back(static_cast<std::uint8_t>(sym));
                continue;
            }
            if (sym == 256) return;
            if (sym > 285) throw std::runtime_error("bad length symbol");
            const int length = kLenBase[sym - 257] + static_cast<int>(bits(kLenExtra[sym - 257]));
            const int d = decode(dist);
            if (d > 29) throw std::runtime_error("bad distance symbol");
            // Distance bases: 1..4, then pairs doubling, with d/2 - 1 extra bits.
            const int extra = d < 4 ? 0 : d / 2 - 1;
            const int base = d < 4 ? d + 1 : (1 << (extra + 1)) + (d % 2) * (1 << extra) + 1;
            const std::size_t distance = base + bits(extra);
            if (distance > out.size() || distance > 32768) throw std::runtime_error("bad distance");
            for (int i = 0; i < length; ++i) out.push_back(out[out.size() - distance]);
        }
    }

    const std::string& in_;
    std::size_t pos_ = 0;
    std::uint8_t bit_buffer_ = 0;
    int bit_count_ = 0;
};

struct DecodedPng {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
    Inflated stream;
    std::size_t file_size = 0;
};

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

DecodedPng decode_png(const std::string& file) {
    const std::vector<PngChunk> chunks = parse_png_chunks(file);
    DecodedPng png;
    png.file_size = file.size();
    EXPECT_GE(chunks.size(), 3u);
    EXPECT_EQ(chunks.front().type, "IHDR");
    EXPECT_EQ(chunks.back().type, "IEND");
    const std::string& ihdr = chunks.front().data;
    EXPECT_EQ(ihdr.size(), 13u);
    png.width = static_cast<int>(be32(ihdr, 0));
    png.height = static_cast<int>(be32(ihdr, 4));
    EXPECT_EQ(ihdr.substr(8), std::string("\x08\x02\x00\x00\x00", 5));  // 8-bit RGB, defaults
    std::string zlib;
    bool seen_srgb = false, seen_idat = false;
    for (const PngChunk& chunk : chunks) {
        if (chunk.type == "sRGB") {
            EXPECT_FALSE(seen_idat) << "sRGB must precede IDAT";
            EXPECT_EQ(chunk.data.size(), 1u);
            seen_srgb = true;
        }
        if (chunk.type == "IDAT") zlib += chunk.data, seen_idat = true;
    }
    EXPECT_TRUE(seen_srgb);
    png.stream = Inflater(zlib).run();

    const std::size_t row_bytes = static_cast<std::size_t>(png.width) * 3;
    EXPECT_EQ(png.stream.data.size(), (row_bytes + 1) * png.height);
    png.rgb.assign(row_bytes * png.height, 0);
    for (int y = 0; y < png.height; ++y) {
        const std::uint8_t* in = &png.stream.data.at((row_bytes + 1) * y);
        std::uint8_t* row = &png.rgb[row_bytes * y];
        const std::uint8_t* above = y > 0 ? row - row_bytes : nullptr;
        for (std::size_t i = 0; i < row_bytes; ++i) {
            const int a = i >= 3 ? row[i - 3] : 0, b = above ? above[i] : 0;
            const int c = i >= 3 && above ? above[i - 3] : 0;
            int predictor = 0;
            switch (in[0]) {
                case 0: predictor = 0; break;
                case 1: predictor = a; break;
                case 2: predictor = b; break;
                case 3: predictor = (a + b) / 2; break;
                case 4: predictor = paeth(a, b, c); break;
                default: ADD_FAILURE() << "bad filter type " << int(in[0]); return png;
            }
            row[i] = static_cast<std::uint8_t>(in[1 + i] + predictor);
        }
    }
    return png;
}

TEST(PngWriter, SignatureChunksAndCrcs) {
    const std::string s = encode_image(Image{2, 1, {0, 0, 0, 1, 1, 1}}, ImageFormat::Png, {});
    const std::vector<PngChunk> chunks = parse_png_chunks(s);
    ASSERT_GE(chunks.size(), 4u);
    EXPECT_EQ(chunks.front().type, "IHDR");
    EXPECT_EQ(chunks.back().type, "IEND");
    EXPECT_TRUE(chunks.back().data.empty());
    // A corrupted byte must be caught by the CRC check (i.e. the check above can fail).
    std::string corrupt = s;
    corrupt[20] ^= 1;  // inside IHDR's data
    EXPECT_NONFATAL_FAILURE(parse_png_chunks(corrupt), "CRC of IHDR");
}

/// The PNG writer with the clip curve: exposure, min(v, 1), the sRGB OETF. These codes are
/// the writer's output from before tone curves existed, so --tonemap clip is unchanged.
ImageWriteOptions clip_options() {
    ImageWriteOptions o;
    o.tone_map = ToneMap::clip;
    return o;
}
const ImageWriteOptions kClip = clip_options();

TEST(PngWriter, SrgbTransferClampAndExposure) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // Expected 8-bit codes computed by hand from IEC 61966-2-1.
    const std::vector<float> linear = {0.0f,  1.0f, 0.5f,  0.18f, 0.002f, 0.0031308f,
                                       -0.5f, nan,  7.0f,  0.01f, 0.25f,  0.8f};
    const std::vector<int> expected = {0, 255, 188, 118, 7, 10, 0, 0, 255, 25, 137, 231};
    const Image image{4, 1, linear};
    const DecodedPng png = decode_png(encode_image(image, ImageFormat::Png, kClip));
    ASSERT_EQ(png.width, 4);
    ASSERT_EQ(png.height, 1);
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(png.rgb[i], expected[i]) << i;

    ImageWriteOptions brighter = kClip;
    brighter.exposure_stops = 1.0;  // 0.25 -> 0.5, 0.5 -> 1.0
    const DecodedPng bright = decode_png(encode_image(image, ImageFormat::Png, brighter));
    EXPECT_EQ(bright.rgb[2], 255);
    EXPECT_EQ(bright.rgb[10], 188);
}

TEST(PngWriter, SmoothGradientCompressesWell) {
    const int n = 256;
    const Image image = make_image(n, n, [](int x, int y, int c) {
        const float t = c == 0 ? x / 255.0f : c == 1 ? y / 255.0f : (x + y) / 510.0f;
        return t * t;
    });
    const DecodedPng png = decode_png(encode_image(image, ImageFormat::Png, kClip));
    ASSERT_EQ(png.width, n);
    ASSERT_EQ(png.height, n);
    const std::size_t raw = static_cast<std::size_t>(n) * n * 3;
    EXPECT_LT(png.file_size, raw / 10);
    // Decoded bytes match an independent 8-bit encoding of the same values.
    for (int y = 0; y < n; y += 17) {
        for (int x = 0; x < n; x += 13) {
            for (int c = 0; c < 3; ++c) {
                const double v = image.pixel(x, y)[c];
                const double s = v < 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
                EXPECT_EQ(png.rgb[(static_cast<std::size_t>(y) * n + x) * 3 + c],
                          std::lround(s * 255));
            }
        }
    }
}

double srgb_to_linear(double s) {
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

TEST(PngWriter, NoisyImageUsesStoredAndDynamicBlocks) {
    // Top: uniformly random 8-bit codes (incompressible: stored blocks). Bottom: a flat image
    // with render-like noise (dynamic Huffman). Large enough for many blocks and for matches
    // reaching back across block boundaries.
    std::mt19937 rng(42);
    std::uniform_int_distribution<int> byte(0, 255);
    std::normal_distribution<float> noise(0.0f, 0.02f);
    std::vector<int> expected;
    const Image image = make_image(160, 240, [&](int x, int y, int c) {
        const int flat = 160 + (x / 40 + c) % 3 * 20;
        const int code = y < 100 ? byte(rng)
                                 : std::clamp(flat + static_cast<int>(255 * noise(rng)), 0, 255);
        expected.push_back(code);
        return static_cast<float>(srgb_to_linear(code / 255.0));
    });
    const DecodedPng png = decode_png(encode_image(image, ImageFormat::Png, kClip));
    EXPECT_GT(png.stream.stored_blocks, 0);
    EXPECT_GT(png.stream.dynamic_blocks, 0);
    ASSERT_EQ(png.rgb.size(), expected.size());
    for (std::size_t i = 0; i < png.rgb.size(); ++i) ASSERT_EQ(png.rgb[i], expected[i]) << i;
}

TEST(PngWriter, SinglePixel) {
    // Too small for a dynamic code table to pay off: a fixed-Huffman block.
    const DecodedPng png =
        decode_png(encode_image(Image{1, 1, {1, 0, 0.5f}}, ImageFormat::Png, kClip));
    EXPECT_EQ(png.rgb, (std::vector<std::uint8_t>{255, 0, 188}));
    EXPECT_EQ(png.stream.fixed_blocks, 1);
}

TEST(PngWriter, DefaultCurveIsAppliedToWholePixelsAfterExposure) {
    // A saturated orange above the knee: the PBR Neutral shoulder acts on the pixel (its
    // peak), not per channel, and after the exposure scale; clip would give 255, 188, 59.
    const Image image{1, 1, {1.0f, 0.25f, 0.0225f}};
    ImageWriteOptions options;
    options.exposure_stops = 1.0;
    EXPECT_EQ(options.tone_map, kDefaultToneMap);
    const DecodedPng png = decode_png(encode_image(image, ImageFormat::Png, options));
    const std::array<double, 3> display = tone_map(kDefaultToneMap, {2.0, 0.5, 0.045});
    for (int c = 0; c < 3; ++c) {
        const double v = display[c];
        const double s = v < 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
        EXPECT_EQ(png.rgb[c], std::lround(s * 255)) << c;
    }
    EXPECT_LT(png.rgb[0], 255);
    EXPECT_LT(png.rgb[1], 188);  // scaled down with the peak (hue kept), not clipped alone
}

// ---- invalid images and atomic writes -------------------------------------------------------

TEST(ImageWriter, RejectsInconsistentImage) {
    EXPECT_THROW(encode_image(Image{2, 2, std::vector<float>(11)}, ImageFormat::Pfm, {}),
                 std::invalid_argument);
    EXPECT_THROW(encode_image(Image{0, 0, {}}, ImageFormat::Png, {}), std::invalid_argument);
}

using AtomicWrite = TempDir;

TEST_F(AtomicWrite, ReplacesExistingFile) {
    const std::string path = dir_ / "out.txt";
    write_file_atomically(path, "old contents that are longer than the new ones");
    write_file_atomically(path, "new");
    EXPECT_EQ(read_file(path), "new");
    EXPECT_EQ(entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicWrite, MissingDirectoryThrowsWithPathAndOsError) {
    const std::string path = dir_ / "no_such_dir" / "x.png";
    try {
        write_file_atomically(path, "data");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "cannot write '" + path + "': No such file or directory");
    }
    EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicWrite, FailedRenameLeavesNoTempFile) {
    // The target is a directory: the temporary file is written, then rename() fails.
    const fs::path target = dir_ / "target.pfm";
    fs::create_directory(target);
    try {
        write_file_atomically(target, "data");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
    EXPECT_FALSE(has_temp_file());
    EXPECT_TRUE(fs::is_directory(target));
}

using WriteImage = TempDir;

TEST_F(WriteImage, WritesEncodedBytes) {
    const Image image{2, 1, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f}};
    for (const char* name : {"a.png", "a.EXR", "a.pfm", "a.ppm"}) {
        const std::string path = dir_ / name;
        write_image(path, image, {});
        EXPECT_EQ(read_file(path), encode_image(image, *image_format_from_path(path), {})) << name;
    }
    EXPECT_FALSE(has_temp_file());
}

TEST_F(WriteImage, UnsupportedExtensionNamesFile) {
    const Image image{1, 1, {0, 0, 0}};
    try {
        write_image("x.bmp", image, {});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "unsupported image extension '.bmp' for 'x.bmp' "
                  "(expected .png, .exr, .pfm, .ppm)");
    }
    try {
        write_image("noext", image, {});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("'noext'"), std::string::npos) << e.what();
    }
}

TEST_F(WriteImage, SeveralFilesReplaceNoneWhenOneFails) {
    const std::string good = dir_ / "a.pfm";
    write_file_atomically(good, "old");
    const std::string missing = dir_ / "missing" / "a.exr";
    EXPECT_THROW(write_images({good, missing}, Image{1, 1, {1, 2, 3}}, {}), std::runtime_error);
    EXPECT_EQ(read_file(good), "old");
    EXPECT_FALSE(has_temp_file());

    write_images({good, dir_ / "a.png"}, Image{1, 1, {1, 2, 3}}, {});
    EXPECT_EQ(read_file(good), encode_image(Image{1, 1, {1, 2, 3}}, ImageFormat::Pfm, {}));
    EXPECT_EQ(entries().size(), 2u);
}

TEST_F(WriteImage, ErrorsNameTheFile) {
    const std::string missing = dir_ / "missing" / "x.png";
    try {
        write_image(missing, Image{1, 1, {0, 0, 0}}, {});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "cannot write '" + missing + "': No such file or directory");
    }
    const std::string bad = dir_ / "bad.exr";
    try {
        write_image(bad, Image{2, 2, {}}, {});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
    EXPECT_TRUE(entries().empty());
}

}  // namespace
}  // namespace spt
