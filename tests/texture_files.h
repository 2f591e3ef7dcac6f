// The image files under tests/textures/ (made by validation/make_texture_files.py and
// tests/textures/make_hdr_test_images.cpp), and the check that a decoder refuses bytes.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/image_decoders.h"

namespace spt::test {

/// The bytes of tests/textures/NAME (a failed expectation if it cannot be opened).
inline std::string read_test_file(const std::string& name) {
    std::ifstream in(std::filesystem::path(SPT_TEST_DIR) / "textures" / name, std::ios::binary);
    EXPECT_TRUE(in) << name;
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// decode_image(bytes) must throw an ImageDecodeError whose message contains `expected`.
inline void expect_decode_error(const std::string& bytes, const std::string& expected) {
    try {
        decode_image(bytes);
        ADD_FAILURE() << "no error; expected one containing: " << expected;
    } catch (const ImageDecodeError& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
}

}  // namespace spt::test
