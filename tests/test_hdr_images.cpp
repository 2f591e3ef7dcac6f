// The HDR image readers on files written by the reference libraries: OpenEXR 3.1 (every
// compression the reader supports, HALF/FLOAT/UINT, R/G/B(/A) and Y, a data window off the
// origin, tiles with and without mipmaps) and stb_image_write (Radiance RGBE, run-length and
// flat scan lines). tests/textures/make_hdr_test_images.cpp writes them (the command is in
// its first lines). Each compression must give the uncompressed file's values bit for bit;
// every truncated or corrupted file must give an ImageDecodeError, never a crash (the
// AddressSanitizer build runs these too).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>

#include "io/image_decoders.h"
#include "texture_files.h"

namespace spt {
namespace {

using test::read_test_file;
using test::expect_decode_error;

constexpr int kW = 37, kH = 21;  // make_hdr_test_images.cpp's image size

/// The changes made to single bytes of a good file: the lowest bit, the highest, all.
constexpr unsigned kFlips[3] = {0x01, 0x80, 0xff};

/// Decodes `bytes` if it can: an ImageDecodeError is fine, any other exception fails.
void decode_or_error(const std::string& bytes) {
    try {
        decode_image(bytes);
    } catch (const ImageDecodeError&) {
    }
}

bool same_bits(const DecodedImage& a, const DecodedImage& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels &&
           std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)) == 0;
}

/// The generator's pattern (make_hdr_test_images.cpp: value()).
double pattern(int x, int y, int c) {
    if (x < 10 && y < 8) return 0.25 * (1 << c);
    if (x == 30 && y == 3) return 1000 + c;
    if (x == 2 && y == 15) return 0;
    return std::round((1.2 + std::sin(x * 0.31 + c) * std::cos(y * 0.23)) * std::ldexp(1.0, (x + y + c) % 7 - 3) * 4096) / 4096;
}

/// Replaces the compression attribute's value.
std::string with_compression(std::string file, char compression) {
    const std::string key("compression\0compression\0", 24);
    const std::size_t at = file.find(key);
    EXPECT_NE(at, std::string::npos);
    file[at + key.size() + 4] = compression;
    return file;
}

TEST(ExrDecoder, EveryCompressionGivesTheUncompressedValues) {
    for (const std::string kind : {"rgb_half", "rgba_float"}) {
        SCOPED_TRACE(kind);
        const DecodedImage none = decode_image(read_test_file("exr_" + kind + "_none.exr"));
        ASSERT_EQ(none.width, kW);
        ASSERT_EQ(none.height, kH);
        ASSERT_EQ(none.channels, kind == "rgb_half" ? 3 : 4);
        EXPECT_FALSE(none.integer_codes);
        // The uncompressed file holds the pattern (HALF: rounded to 11 significant bits).
        const double tolerance = kind == "rgb_half" ? 1.0 / 2048 : 1e-6;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                for (int c = 0; c < 3; ++c) {
                    ASSERT_NEAR(none.at(x, y, c), pattern(x, y, c), tolerance * pattern(x, y, c) + 1e-6) << x << "," << y;
                }
                if (none.channels == 4) {
                    ASSERT_EQ(none.at(x, y, 3), 0.5f + 0.01f * float(x));
                }
            }
        for (const std::string compression : {"rle", "zips", "zip", "piz"}) {
            SCOPED_TRACE(compression);
            const std::string file = read_test_file("exr_" + kind + "_" + compression + ".exr");
            EXPECT_TRUE(same_bits(decode_image(file), none));
        }
    }
}

TEST(ExrDecoder, TilesOfOneLevelAndTheFirstMipmapLevel) {
    const DecodedImage none = decode_image(read_test_file("exr_rgb_half_none.exr"));
    for (const char* name : {"exr_tiled_zip.exr", "exr_tiled_mipmap_piz.exr"}) {
        SCOPED_TRACE(name);
        EXPECT_TRUE(same_bits(decode_image(read_test_file(name)), none));
    }
}

TEST(ExrDecoder, PizWithMoreThan2To14DistinctValuesUsesTheSixteenBitWavelet) {
    const DecodedImage img = decode_image(read_test_file("exr_ramp_piz.exr"));
    ASSERT_EQ(img.width, 544);
    ASSERT_EQ(img.height, 40);
    ASSERT_EQ(img.channels, 1);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 544; ++x) {
            // Positive halves: bits 1 .. 17408, subnormal below 1024.
            const unsigned bits = 1 + unsigned(y % 32) * 544 + unsigned(x), e = bits >> 10, m = bits & 1023;
            const float expected = e == 0 ? std::ldexp(float(m), -24) : std::ldexp(float(1024 + m), int(e) - 25);
            ASSERT_EQ(img.at(x, y, 0), expected) << x << "," << y;
        }
}

TEST(ExrDecoder, UintLuminance) {
    const DecodedImage img = decode_image(read_test_file("exr_y_uint_zip.exr"));
    ASSERT_EQ(img.channels, 1);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) ASSERT_EQ(img.at(x, y, 0), float((x * 37 + y * 71) * 997 % 100003)) << x << "," << y;
}

TEST(ExrDecoder, ChunksThatWouldNotShrinkAreStoredUncompressed) {
    // OpenEXR stores a chunk as it is when compressing would not make it smaller: an
    // uncompressed file relabelled RLE or ZIPS (one scan line per chunk, as NONE) is a valid
    // file with the same values.
    const std::string none = read_test_file("exr_rgb_half_none.exr");
    const DecodedImage reference = decode_image(none);
    for (const char compression : {'\x01', '\x02'}) EXPECT_TRUE(same_bits(decode_image(with_compression(none, compression)), reference));
    // ZIP and PIZ group 16 and 32 scan lines per chunk: ZIP's second chunk is scan line 1,
    // not 16; PIZ's one chunk is too short to be stored as it is, and not PIZ data.
    expect_decode_error(with_compression(none, '\x03'), "starts at scan line");
    expect_decode_error(with_compression(none, '\x04'), "OpenEXR PIZ chunk");
}

TEST(ExrDecoder, UnsupportedFeaturesAreNamed) {
    expect_decode_error(read_test_file("exr_rgb_half_pxr24.exr"),
                        "OpenEXR compression PXR24 is not supported; expected NONE, RLE, ZIPS, ZIP or PIZ");
    std::string deep = read_test_file("exr_rgb_half_none.exr");
    deep[5] |= 0x08;  // version flag 11: deep data
    expect_decode_error(deep, "deep OpenEXR data is not supported");
    std::string multi = read_test_file("exr_rgb_half_none.exr");
    multi[5] |= 0x10;  // version flag 12: multi-part
    expect_decode_error(multi, "multi-part OpenEXR is not supported");
}

TEST(ExrDecoder, TruncatedAndCorruptFilesAreErrorsNotCrashes) {
    for (const char* name : {"exr_rgb_half_rle.exr", "exr_rgb_half_zips.exr", "exr_rgb_half_zip.exr", "exr_rgb_half_piz.exr",
                             "exr_rgba_float_piz.exr", "exr_tiled_zip.exr", "exr_tiled_mipmap_piz.exr"}) {
        SCOPED_TRACE(name);
        const std::string good = read_test_file(name);
        // Every truncation inside the header and offset table, then every 13th byte. (The
        // mipmap file's smaller levels come last and are not read: cutting them is no error.)
        const bool mipmap = std::string(name).find("mipmap") != std::string::npos;
        for (std::size_t n = 0; n < good.size(); n += n < 600 ? 1 : 13) {
            if (mipmap && n >= 600) decode_or_error(good.substr(0, n));
            else EXPECT_THROW(decode_image(good.substr(0, n)), ImageDecodeError) << n;
        }
        // Every single-byte change (EXR has no checksums: some decode to other values).
        for (std::size_t i = 0; i < good.size(); ++i) {
            std::string bad = good;
            bad[i] = static_cast<char>(bad[i] ^ kFlips[i % 3]);
            decode_or_error(bad);
        }
    }
    // Named header and chunk faults.
    const std::string zip = read_test_file("exr_rgb_half_zip.exr");
    const std::string window("dataWindow\0box2i\0", 17);
    std::string huge = zip;
    const std::size_t w = huge.find(window) + window.size() + 4;
    huge[w + 8] = '\xff', huge[w + 9] = '\xff', huge[w + 10] = '\x00', huge[w + 11] = '\x00';  // x max 65535
    huge[w + 12] = '\xff', huge[w + 13] = '\xff', huge[w + 14] = '\x00', huge[w + 15] = '\x00';
    expect_decode_error(huge, "is too large");
}

TEST(ExrDecoder, ChunkSizesAndOffsetsAreChecked) {
    // The first chunk's offset is the first 8 bytes after the header's closing 0.
    const std::string zip = read_test_file("exr_rgb_half_zip.exr");
    std::size_t table = 8;
    while (zip[table] != '\0') {
        table = zip.find('\0', table) + 1;      // name
        table = zip.find('\0', table) + 1;      // type
        std::uint32_t size = 0;
        std::memcpy(&size, zip.data() + table, 4);
        table += 4 + size;
    }
    ++table;
    std::uint64_t first = 0;
    std::memcpy(&first, zip.data() + table, 8);
    std::string past = zip;
    past[table + 7] = '\x01';  // offset + 2^56
    expect_decode_error(past, "is past the end of the file");
    std::string longer = zip;
    longer[first + 7] = '\x7f';  // chunk size far past the file
    expect_decode_error(longer, "truncated file");
    std::string wrong_line = zip;
    wrong_line[first] = static_cast<char>(wrong_line[first] + 1);
    expect_decode_error(wrong_line, "starts at scan line");
    std::string broken = zip;
    broken[first + 8] = '\x00';  // the zlib header
    expect_decode_error(broken, "OpenEXR ZIP chunk");
}

/// stb_image_write's RGBE encoding of one texel (its float arithmetic).
std::array<unsigned char, 4> stb_rgbe(const float* rgb) {
    const float maxcomp = std::max(rgb[0], std::max(rgb[1], rgb[2]));
    if (maxcomp < 1e-32f) return {0, 0, 0, 0};
    int exponent;
    const float normalize = static_cast<float>(std::frexp(maxcomp, &exponent)) * 256.0f / maxcomp;
    return {static_cast<unsigned char>(rgb[0] * normalize), static_cast<unsigned char>(rgb[1] * normalize),
            static_cast<unsigned char>(rgb[2] * normalize), static_cast<unsigned char>(exponent + 128)};
}

TEST(RgbeDecoder, ReadsRunLengthAndFlatFilesExactly) {
    // The generator wrote the pattern's floats, which the FLOAT EXR holds exactly.
    const DecodedImage floats = decode_image(read_test_file("exr_rgba_float_none.exr"));
    for (const auto& [name, w, h] : {std::tuple{"rgbe_rle.hdr", kW, kH}, std::tuple{"rgbe_flat.hdr", 5, 4}}) {
        SCOPED_TRACE(name);
        const DecodedImage img = decode_image(read_test_file(name));
        ASSERT_EQ(img.width, w);
        ASSERT_EQ(img.height, h);
        ASSERT_EQ(img.channels, 3);
        EXPECT_FALSE(img.integer_codes);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float rgb[3] = {floats.at(x, y, 0), floats.at(x, y, 1), floats.at(x, y, 2)};
                const auto e = stb_rgbe(rgb);
                for (int c = 0; c < 3; ++c) {
                    const float expected = e[3] == 0 ? 0.f : std::ldexp(float(e[static_cast<std::size_t>(c)]), int(e[3]) - 136);
                    ASSERT_EQ(img.at(x, y, c), expected) << x << "," << y << "," << c;
                    // RGBE keeps 8 bits relative to the largest component.
                    const float largest = std::max(rgb[0], std::max(rgb[1], rgb[2]));
                    ASSERT_NEAR(img.at(x, y, c), rgb[c], largest / 128) << x << "," << y << "," << c;
                }
            }
    }
}

std::string px(unsigned r, unsigned g, unsigned b, unsigned e) {
    return {static_cast<char>(r), static_cast<char>(g), static_cast<char>(b), static_cast<char>(e)};
}

TEST(RgbeDecoder, OldStyleRepeatsExactValuesAndIgnoredExposure) {
    const std::string header = "#?RADIANCE\n# hand-made\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=2.0\n\n-Y 2 +X 300\n";
    // Row 0: one pixel, a repeat of 43, then a repeat of 1 << 8 (consecutive repeats shift by
    // 8 bits): 1 + 43 + 256 = 300. Row 1: flat pixels with exponent 0 (black) and 255.
    std::string rows = px(128, 64, 1, 129) + px(1, 1, 1, 43) + px(1, 1, 1, 1);
    rows += px(255, 0, 10, 100) + px(7, 7, 7, 0);
    for (int x = 2; x < 300; ++x) rows += px(3, 2, 1, 255);
    const DecodedImage img = decode_image(header + rows);
    ASSERT_EQ(img.width, 300);
    ASSERT_EQ(img.height, 2);
    for (int x = 0; x < 300; ++x) {
        EXPECT_EQ(img.at(x, 0, 0), 1.f);  // 128 · 2^(129 − 136), EXPOSURE not applied
        EXPECT_EQ(img.at(x, 0, 1), 0.5f);
        EXPECT_EQ(img.at(x, 0, 2), 0.0078125f);
    }
    EXPECT_EQ(img.at(0, 1, 0), std::ldexp(255.f, -36));
    EXPECT_EQ(img.at(0, 1, 1), 0.f);
    EXPECT_EQ(img.at(0, 1, 2), std::ldexp(10.f, -36));
    for (int c = 0; c < 3; ++c) EXPECT_EQ(img.at(1, 1, c), 0.f);
    EXPECT_EQ(img.at(299, 1, 0), std::ldexp(3.f, 119));
    // A repeat longer than the line, or with nothing before it.
    expect_decode_error(header + px(1, 1, 1, 2) + rows, "starts with a repeat");
    expect_decode_error(header + px(9, 9, 9, 9) + px(1, 1, 1, 255) + px(1, 1, 1, 255), "longer than the line");
}

TEST(RgbeDecoder, BadHeadersAndScanLinesAreNamed) {
    const std::string good = read_test_file("rgbe_rle.hdr");
    for (std::size_t n = 0; n < good.size(); ++n) EXPECT_THROW(decode_image(good.substr(0, n)), ImageDecodeError) << n;
    for (std::size_t i = 0; i < good.size(); ++i) {
        std::string bad = good;
        bad[i] = static_cast<char>(bad[i] ^ kFlips[i % 3]);
        decode_or_error(bad);
    }
    const std::string pixels = px(1, 2, 3, 128);
    expect_decode_error("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n" + pixels,
                        "format \"32-bit_rle_xyze\" is not supported; expected 32-bit_rle_rgbe");
    expect_decode_error("#?RADIANCE\n\n+Y 1 +X 1\n" + pixels, "resolution line \"+Y 1 +X 1\" stores the image in an orientation");
    expect_decode_error("#?RADIANCE\n\n-Y 1 +X\n" + pixels, "resolution line \"-Y 1 +X\" is not understood");
    expect_decode_error("#?RADIANCE\n\n-Y 100000 +X 100000\n" + pixels, "is too large");
    expect_decode_error("#?RGBE\n\n-Y 1 +X 1\n", "truncated");
    // New-style scan lines: a stated width that differs, a zero-length literal run, a run past the line.
    const std::string h8 = "#?RADIANCE\n\n-Y 1 +X 8\n";
    expect_decode_error(h8 + std::string("\x02\x02\x00\x09", 4), "says it is 9 texels wide; expected 8");
    expect_decode_error(h8 + std::string("\x02\x02\x00\x08\x00", 5), "literal run of length 0");
    expect_decode_error(h8 + std::string("\x02\x02\x00\x08\x89\x05", 6), "longer than the line");
    // Detection by the first bytes.
    expect_decode_error("#?SOMETHING\n", "unknown first bytes");
}

TEST(ImageSize, EnvironmentMapSizesAreAccepted) {
    EXPECT_NO_THROW(check_image_size(8192, 4096));
    EXPECT_NO_THROW(check_image_size(16384, 8192));
    EXPECT_THROW(check_image_size(16385, 8192), ImageDecodeError);
    EXPECT_THROW(check_image_size(1ll << 28, 1), ImageDecodeError);
}

}  // namespace
}  // namespace spt
