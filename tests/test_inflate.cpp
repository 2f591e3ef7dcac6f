// Our inflate (src/io/inflate.h) against streams made by Python's zlib
// (validation/make_texture_files.py): stored, fixed-Huffman and dynamic-Huffman blocks, and
// against hand-made defects, each of which must be an InflateError.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/checksums.h"
#include "io/inflate.h"
#include "texture_files.h"

namespace spt {
namespace {

using test::read_test_file;

/// The payload the script compressed (its formula, repeated here).
std::vector<std::uint8_t> payload() {
    std::vector<std::uint8_t> p;
    for (int i = 0; i < 3000; ++i) p.push_back(static_cast<std::uint8_t>((i * 7 + i / 13) % 251));
    return p;
}

TEST(Inflate, DecodesStoredFixedAndDynamicStreams) {
    // Block types checked by the script's author: level 0 stored (BTYPE 0), Z_FIXED fixed
    // (1), levels 1 and 9 dynamic (2); the first byte after the header says so.
    const std::pair<const char*, int> files[] = {
        {"zlib_level0.bin", 0}, {"zlib_fixed.bin", 1}, {"zlib_level1.bin", 2}, {"zlib_level9.bin", 2}};
    for (const auto& [name, btype] : files) {
        SCOPED_TRACE(name);
        const std::string z = read_test_file(name);
        ASSERT_GT(z.size(), 6u);
        EXPECT_EQ((static_cast<unsigned char>(z[2]) >> 1) & 3, btype);
        EXPECT_EQ(zlib_decompress(z, 3000), payload());
    }
}

TEST(Inflate, StoredBlocksAcrossTheirSizeLimit) {
    const std::string z = read_test_file("zlib_stored_two_blocks.bin");
    const std::vector<std::uint8_t> out = zlib_decompress(z, 70000);
    ASSERT_EQ(out.size(), 70000u);
    for (std::size_t i = 0; i < out.size(); i += 997) ASSERT_EQ(out[i], (i / 100) % 256) << i;
}

TEST(Inflate, Adler32OfKnownStrings) {
    EXPECT_EQ(adler32(""), 1u);
    EXPECT_EQ(adler32("Wikipedia"), 0x11E60398u);  // the example of the Adler-32 article
    // Long input: the modulo must be taken before the sums overflow (zlib's NMAX).
    const std::string ff(100000, '\xff');
    std::uint64_t a = 1, b = 0;
    for (unsigned char c : ff) a = (a + c) % 65521, b = (b + a) % 65521;
    EXPECT_EQ(adler32(ff), static_cast<std::uint32_t>(b << 16 | a));
}

/// A zlib stream of one hand-made stored block.
std::string stored_stream(const std::string& data, bool good_nlen = true) {
    std::string z = "\x78\x01";
    z += '\x01';  // BFINAL = 1, BTYPE = 00
    const unsigned len = static_cast<unsigned>(data.size()), nlen = good_nlen ? ~len & 0xffffu : len;
    z += static_cast<char>(len & 0xff), z += static_cast<char>(len >> 8);
    z += static_cast<char>(nlen & 0xff), z += static_cast<char>(nlen >> 8);
    z += data;
    const std::uint32_t a = adler32(data);
    for (int s = 24; s >= 0; s -= 8) z += static_cast<char>(a >> s & 0xff);
    return z;
}

TEST(Inflate, HandMadeStoredBlock) {
    const std::vector<std::uint8_t> out = zlib_decompress(stored_stream("hello"), 5);
    EXPECT_EQ(std::string(out.begin(), out.end()), "hello");
}

TEST(Inflate, DefectsAreErrorsNeverCrashes) {
    auto fails = [](const std::string& z, std::size_t size, const std::string& expected) {
        try {
            zlib_decompress(z, size);
            ADD_FAILURE() << "no error; expected one containing: " << expected;
        } catch (const InflateError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    };
    fails(stored_stream("hello", false), 5, "complement");
    std::string bad_sum = stored_stream("hello");
    bad_sum.back() ^= 1;
    fails(bad_sum, 5, "Adler-32");
    fails(stored_stream("hello"), 4, "longer than");
    fails(stored_stream("hello"), 6, "expected 6");
    const std::string dynamic = read_test_file("zlib_level9.bin");
    fails(dynamic.substr(0, dynamic.size() / 2), 3000, "truncated");
    fails(dynamic.substr(0, dynamic.size() - 2), 3000, "Adler-32");
    std::string header = dynamic;
    header[1] ^= 1;
    fails(header, 3000, "header check");
    fails(std::string("\x78\x01\x07\x00\x00\x00\x00", 7), 1, "block type 3");
    // Every single-byte corruption of the dynamic stream: an error or (rarely) the same
    // length of other bytes caught by the checksum, but never a crash.
    for (std::size_t i = 2; i < dynamic.size(); ++i) {
        std::string z = dynamic;
        z[i] ^= 0x21;
        EXPECT_THROW(zlib_decompress(z, 3000), InflateError) << "byte " << i;
    }
}

// A gzip file with a file name field (Python's gzip module, mtime 0): three lines of a scene.
const std::string kGzipScene(
    "\x1f\x8b\x08\x08\x00\x00\x00\x00\x02\xff\x73\x70\x68\x65\x72\x65\x2e\x70\x62\x72\x74\x00\x0b\xce\x48\x2c\x48"
    "\x55\x50\x2a\x2e\xc8\x48\x2d\x4a\x55\x52\x50\x4a\xcb\xc9\x4f\x2c\x51\x28\x4a\x4c\xc9\x2c\x2d\x56\x52\x30\xe2"
    "\x0a\xa6\x50\x1e\x00\x0d\x66\xe9\x55\x60\x00\x00\x00",
    67);

TEST(Gzip, DecompressesAFileWithOptionalHeaderFields) {
    ASSERT_TRUE(is_gzip(kGzipScene));
    std::string expected;
    for (int i = 0; i < 3; ++i) expected += "Shape \"sphere\" \"float radius\" 2\n";
    EXPECT_EQ(gzip_decompress(kGzipScene), expected);
}

TEST(Gzip, CorruptOrTruncatedFilesAreErrors) {
    std::string bad_crc = kGzipScene;
    bad_crc[bad_crc.size() - 6] ^= 1;
    EXPECT_THROW(gzip_decompress(bad_crc), InflateError);
    std::string bad_size = kGzipScene;
    bad_size[bad_size.size() - 4] ^= 1;
    EXPECT_THROW(gzip_decompress(bad_size), InflateError);
    EXPECT_THROW(gzip_decompress(kGzipScene.substr(0, 40)), InflateError);
    EXPECT_THROW(gzip_decompress(kGzipScene + kGzipScene), InflateError);  // two members
    EXPECT_THROW(gzip_decompress("plain text, not gzip at all"), InflateError);
    // Every single-byte corruption: an error, or (in the unchecked header bytes: time, name)
    // the same text; never other text and never a crash.
    const std::string expected = gzip_decompress(kGzipScene);
    for (std::size_t i = 0; i < kGzipScene.size(); ++i) {
        std::string z = kGzipScene;
        z[i] ^= 0x21;
        try {
            EXPECT_EQ(gzip_decompress(z), expected) << "byte " << i;
        } catch (const InflateError&) {
        }
    }
}

}  // namespace
}  // namespace spt
