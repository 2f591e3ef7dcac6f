// The image readers (src/io/image_decoders.h) on small files of every kind: PNG of every
// colour type, bit depth and scanline filter (validation/make_texture_files.py writes them
// by hand; each texel's code is code() below), PPM P3/P6 8/16-bit and the renderer's HDR P3,
// PFM and EXR as the renderer's own writers make them; and malformed files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/image_decoders.h"
#include "io/image_encoders.h"
#include "io/image_writer.h"
#include "texture_files.h"

namespace spt {
namespace {

using test::read_test_file;
using test::expect_decode_error;

constexpr int kW = 5, kH = 6;  // the test images' size (make_texture_files.py)

/// The code of channel c of texel (x, y) in the test PNGs (the script's formula).
unsigned code(int x, int y, int c, int depth) { return unsigned(x * 37 + y * 71 + c * 113 + 11) % (1u << depth); }

std::array<unsigned, 3> palette_entry(unsigned i) {
    return {(i * 53 + 7) % 256, (i * 101 + 3) % 256, (i * 29 + 200) % 256};
}

TEST(PngDecoder, EveryColourTypeAndBitDepth) {
    struct Case {
        const char* file;
        int channels, depth;
    };
    const Case cases[] = {{"grey1.png", 1, 1},      {"grey2.png", 1, 2},       {"grey4.png", 1, 4},
                          {"grey8.png", 1, 8},      {"grey16.png", 1, 16},     {"greyalpha8.png", 2, 8},
                          {"greyalpha16.png", 2, 16}, {"rgb8.png", 3, 8},      {"rgb16.png", 3, 16},
                          {"rgba8.png", 4, 8},      {"rgba16.png", 4, 16},     {"rgb8_level0.png", 3, 8},
                          {"rgb8_fixed.png", 3, 8}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        const DecodedImage img = decode_png(read_test_file(c.file));
        ASSERT_EQ(img.width, kW);
        ASSERT_EQ(img.height, kH);
        ASSERT_EQ(img.channels, c.channels);
        EXPECT_TRUE(img.integer_codes);
        const float max_code = float((1u << c.depth) - 1);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (int ch = 0; ch < c.channels; ++ch)
                    ASSERT_EQ(img.at(x, y, ch), float(code(x, y, ch, c.depth)) / max_code) << x << "," << y << "," << ch;
    }
}

TEST(PngDecoder, PalettesAndTheirAlpha) {
    for (int depth : {1, 2, 4, 8}) {
        SCOPED_TRACE(depth);
        const DecodedImage img = decode_png(read_test_file("palette" + std::to_string(depth) + ".png"));
        ASSERT_EQ(img.channels, 3);  // no tRNS: RGB
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const auto e = palette_entry(code(x, y, 0, depth));
                for (int c = 0; c < 3; ++c) ASSERT_EQ(img.at(x, y, c), float(e[c]) / 255.f);
            }
    }
    const DecodedImage img = decode_png(read_test_file("palette8_trns.png"));
    ASSERT_EQ(img.channels, 4);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) ASSERT_EQ(img.at(x, y, 3), float((code(x, y, 0, 8) * 3) % 256) / 255.f);
}

TEST(PngDecoder, InterlacedTruncatedAndCorruptFilesAreClearErrors) {
    expect_decode_error(read_test_file("interlaced.png"), "interlaced (Adam7) PNG is not supported");
    const std::string good = read_test_file("rgb8.png");
    // Every truncation is an error, never a crash.
    for (std::size_t n = 0; n < good.size(); ++n) EXPECT_THROW(decode_image(good.substr(0, n)), ImageDecodeError) << n;
    // Every single-byte change: chunk CRCs catch it (or the signature check).
    for (std::size_t i = 0; i < good.size(); ++i) {
        std::string bad = good;
        bad[i] ^= 0x10;
        EXPECT_THROW(decode_image(bad), ImageDecodeError) << "byte " << i;
    }
    expect_decode_error("GIF89a", "unknown first bytes");
}

TEST(PpmDecoder, BinaryAsciiAndTheRenderersHdrForm) {
    // P6, 8-bit: 2 x 1 pixels.
    DecodedImage a = decode_image(std::string("P6\n# comment\n2 1\n255\n") + std::string("\x00\x80\xff\x10\x20\x30", 6));
    ASSERT_EQ(a.width, 2);
    EXPECT_TRUE(a.integer_codes);
    EXPECT_EQ(a.at(0, 0, 1), 128.f / 255.f);
    EXPECT_EQ(a.at(1, 0, 2), 48.f / 255.f);
    // P6, 16-bit big-endian.
    DecodedImage b = decode_image(std::string("P6 1 1 65535\n") + std::string("\x12\x34\xff\xff\x00\x01", 6));
    EXPECT_EQ(b.at(0, 0, 0), float(0x1234) / 65535.f);
    EXPECT_EQ(b.at(0, 0, 2), 1.f / 65535.f);
    // P3.
    DecodedImage c = decode_image("P3\n1 2\n1000\n0 500 1000\n1 2 3\n");
    EXPECT_EQ(c.at(0, 1, 2), 3.f / 1000.f);
    // The renderer's HDR P3: linear values back (within its 2^25 levels of the maximum).
    Image img;
    img.width = 2, img.height = 2;
    img.rgb = {0.f, 0.5f, 1.f, 2.f, 4.f, 8.f, 0.25f, 0.125f, 3.f, 7.f, 6.f, 5.f};
    ImageWriteOptions options;
    const DecodedImage d = decode_image(encode_ppm(img, options));
    EXPECT_FALSE(d.integer_codes);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(d.at(x, y, k), img.pixel(x, y)[k], 8.f / (1 << 25));
    expect_decode_error("P6\n2 2\n255\n\x01\x02", "truncated");
    expect_decode_error("P3\n1 1\n255\n1 2 300\n", "exceeds maxval");
    expect_decode_error("P6\n0 4\n255\n", "empty");
    expect_decode_error("P6\n100000 100000\n255\n", "too large");
}

TEST(PfmAndExrDecoders, ReadTheRenderersOwnFilesExactly) {
    Image img;
    img.width = 3, img.height = 2;
    img.rgb = {0.1f, 0.2f, 0.3f, 1e-3f, 5.f, 1e4f, 0.f, 0.5f, 1.f, 2.f, 3.f, 4.f, 7.f, 8.f, 9.f, 0.25f, 0.75f, 1.5f};
    const ImageWriteOptions options;
    for (const std::string& bytes : {encode_pfm(img, options), encode_exr(img, options)}) {
        const DecodedImage d = decode_image(bytes);
        EXPECT_FALSE(d.integer_codes);
        ASSERT_EQ(d.width, 3);
        ASSERT_EQ(d.height, 2);
        ASSERT_EQ(d.channels, 3);
        // Row 0 is the top in both (PFM stores rows bottom-up: the reader turns them).
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x)
                for (int k = 0; k < 3; ++k) EXPECT_EQ(d.at(x, y, k), img.pixel(x, y)[k]) << x << "," << y;
        for (std::size_t n = 0; n < bytes.size(); n += 7) EXPECT_THROW(decode_image(bytes.substr(0, n)), ImageDecodeError);
    }
    // Big-endian grey PFM (positive scale).
    const DecodedImage g = decode_image(std::string("Pf\n1 1\n1.0\n") + std::string("\x3f\x80\x00\x00", 4));
    EXPECT_EQ(g.channels, 1);
    EXPECT_EQ(g.at(0, 0, 0), 1.f);
}

}  // namespace
}  // namespace spt
