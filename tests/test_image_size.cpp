// The image-size rule (src/cli/image_size.h): one side given keeps the scene's aspect ratio,
// --scale multiplies the scene's size. The command-line test is in test_cli.cpp.
#include <gtest/gtest.h>

#include "cli/image_size.h"
#include "cli/options.h"

namespace spt {
namespace {

void expect_size(ImageSize s, int width, int height) {
    EXPECT_EQ(s.width, width);
    EXPECT_EQ(s.height, height);
}

TEST(ImageSize, DefaultsAndBothSidesAreTakenAsGiven) {
    expect_size(resolve_image_size(240, 160, {}, {}, {}), 240, 160);
    expect_size(resolve_image_size(240, 160, 100, 100, {}), 100, 100);
}

TEST(ImageSize, OneSideKeepsTheAspectRatio) {
    expect_size(resolve_image_size(240, 160, 48, {}, {}), 48, 32);
    expect_size(resolve_image_size(240, 160, {}, 8, {}), 12, 8);
    expect_size(resolve_image_size(512, 384, 100, {}, {}), 100, 75);
    // Rounded to nearest: 3·160/240 = 2; 5·160/240 = 3.33 → 3; 7·384/512 = 5.25 → 5;
    // 10·384/512 = 7.5 → 8 (halves away from zero).
    expect_size(resolve_image_size(240, 160, 3, {}, {}), 3, 2);
    expect_size(resolve_image_size(240, 160, 5, {}, {}), 5, 3);
    expect_size(resolve_image_size(512, 384, 7, {}, {}), 7, 5);
    expect_size(resolve_image_size(512, 384, 10, {}, {}), 10, 8);
    // Never below one pixel.
    expect_size(resolve_image_size(1000, 10, 1, {}, {}), 1, 1);
    expect_size(resolve_image_size(10, 1000, {}, 1, {}), 1, 1);
}

TEST(ImageSize, ScaleMultipliesTheScenesSize) {
    expect_size(resolve_image_size(240, 160, {}, {}, 0.5), 120, 80);
    expect_size(resolve_image_size(240, 160, {}, {}, 0.1), 24, 16);
    expect_size(resolve_image_size(512, 384, {}, {}, 2.0), 1024, 768);
    expect_size(resolve_image_size(512, 384, {}, {}, 0.001), 1, 1);
}

TEST(ImageSize, TooLargeDerivedSideIsAUsageErrorNamingTheFlag) {
    try {
        resolve_image_size(1, 1000, 65536, {}, {});
        FAIL() << "no exception";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("--width"), std::string::npos) << e.what();
    }
    EXPECT_THROW(resolve_image_size(1000, 1, {}, 65536, {}), UsageError);
    EXPECT_THROW(resolve_image_size(1024, 1024, {}, {}, 100.0), UsageError);
    expect_size(resolve_image_size(1024, 1024, {}, {}, 64.0), 65536, 65536);
}

TEST(ImageSize, ScaleWithWidthOrHeightIsRejectedByTheParser) {
    EXPECT_THROW(parse_options({"--scale", "2", "--width", "10"}), UsageError);
    EXPECT_THROW(parse_options({"--height", "10", "--scale", "2"}), UsageError);
    EXPECT_EQ(parse_options({"--scale", "0.25"}).scale, 0.25);
}

}  // namespace
}  // namespace spt
