// Writes the OpenEXR and Radiance HDR test images of tests/test_hdr_images.cpp with the
// reference libraries (not part of the build; the renderer reads them with its own code):
//   g++ -std=c++17 -O1 tests/textures/make_hdr_test_images.cpp -I/usr/include/OpenEXR \
//       -I/usr/include/Imath -I<pbrt-v4>/src/ext/stb -lOpenEXR-3_1 -lImath-3_1 -o /tmp/make_hdr
//   /tmp/make_hdr tests/textures
// (OpenEXR 3.1 from Debian's libopenexr-dev; stb_image_write.h v1.16 from pbrt-v4's src/ext/stb.)
// The pixel values are the formulas below; test_hdr_images.cpp recomputes what it needs.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTiledOutputFile.h>
#include <half.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include "stb_image_write.h"

namespace {

constexpr int kW = 37, kH = 21, kX0 = -3, kY0 = 5;  // data window (-3, 5) – (33, 25)

/// Channel c of texel (x, y) (data-window relative): a flat corner (runs), a smooth HDR
/// pattern over several octaves, one bright "sun" texel and one zero, quantised to 1/4096.
float value(int x, int y, int c) {
    if (x < 10 && y < 8) return 0.25f * float(1 << c);
    if (x == 30 && y == 3) return 1000.f + float(c);
    if (x == 2 && y == 15) return 0.f;
    const double v = (1.2 + std::sin(x * 0.31 + c) * std::cos(y * 0.23)) * std::ldexp(1.0, (x + y + c) % 7 - 3);
    return float(std::round(v * 4096) / 4096);
}

const char* kNames[4] = {"R", "G", "B", "A"};

void write_scanline(const std::string& path, Imf::Compression compression, Imf::PixelType type, int channels, bool offset) {
    const int x0 = offset ? kX0 : 0, y0 = offset ? kY0 : 0;
    Imf::Header header(Imath::Box2i({0, 0}, {39, 29}), Imath::Box2i({x0, y0}, {x0 + kW - 1, y0 + kH - 1}));
    header.compression() = compression;
    for (int c = 0; c < channels; ++c) header.channels().insert(kNames[c], Imf::Channel(type));
    std::vector<half> halves(std::size_t(kW) * kH * 4);
    std::vector<float> floats(halves.size());
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            for (int c = 0; c < 4; ++c) {
                const float v = c == 3 ? 0.5f + 0.01f * float(x) : value(x, y, c);
                floats[(std::size_t(y) * kW + x) * 4 + c] = v;
                halves[(std::size_t(y) * kW + x) * 4 + c] = half(v);
            }
    Imf::FrameBuffer fb;
    const std::size_t xs = 4 * (type == Imf::HALF ? 2 : 4), ys = xs * kW;
    for (int c = 0; c < channels; ++c) {
        char* base = type == Imf::HALF ? reinterpret_cast<char*>(halves.data() + c) : reinterpret_cast<char*>(floats.data() + c);
        fb.insert(kNames[c], Imf::Slice(type, base - std::ptrdiff_t(x0) * std::ptrdiff_t(xs) - std::ptrdiff_t(y0) * std::ptrdiff_t(ys), xs, ys));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(kH);
}

/// RGB HALF tiles; every level holds the level-0 pattern subsampled.
void write_tiled(const std::string& path, Imf::Compression compression, int tw, int th, Imf::LevelMode mode) {
    Imf::Header header(Imath::Box2i({0, 0}, {39, 29}), Imath::Box2i({kX0, kY0}, {kX0 + kW - 1, kY0 + kH - 1}));
    header.compression() = compression;
    header.setTileDescription(Imf::TileDescription(tw, th, mode, Imf::ROUND_DOWN));
    for (int c = 0; c < 3; ++c) header.channels().insert(kNames[c], Imf::Channel(Imf::HALF));
    Imf::TiledOutputFile file(path.c_str(), header);
    for (int level = 0; level < file.numLevels(); ++level) {
        const int lw = file.levelWidth(level), lh = file.levelHeight(level), step = 1 << level;
        std::vector<half> pixels(std::size_t(lw) * lh * 3);
        for (int y = 0; y < lh; ++y)
            for (int x = 0; x < lw; ++x)
                for (int c = 0; c < 3; ++c) pixels[(std::size_t(y) * lw + x) * 3 + c] = half(value(x * step, y * step, c));
        Imf::FrameBuffer fb;
        const std::size_t xs = 6, ys = xs * lw;
        for (int c = 0; c < 3; ++c)
            fb.insert(kNames[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(pixels.data() + c) - std::ptrdiff_t(kX0) * 6 -
                                                           std::ptrdiff_t(kY0) * std::ptrdiff_t(ys), xs, ys));
        file.setFrameBuffer(fb);
        file.writeTiles(0, file.numXTiles(level) - 1, 0, file.numYTiles(level) - 1, level);
    }
}

/// Y HALF, 544 × 40: texel (x, y) holds the half whose bits are 1 + (y mod 32)·544 + x, so
/// the first 32-line PIZ chunk has 17408 distinct values (past 2^14: the 16-bit wavelet).
void write_ramp(const std::string& path, Imf::Compression compression) {
    constexpr int w = 544, h = 40;
    Imf::Header header(w, h);
    header.compression() = compression;
    header.channels().insert("Y", Imf::Channel(Imf::HALF));
    std::vector<half> pixels(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) pixels[std::size_t(y) * w + x].setBits(std::uint16_t(1 + (y % 32) * w + x));
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(pixels.data()), 2, 2 * w));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
}

/// Y UINT: (x·37 + y·71)·997 mod 100003.
void write_uint(const std::string& path, Imf::Compression compression) {
    Imf::Header header(kW, kH);
    header.compression() = compression;
    header.channels().insert("Y", Imf::Channel(Imf::UINT));
    std::vector<unsigned> pixels(std::size_t(kW) * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) pixels[std::size_t(y) * kW + x] = unsigned((x * 37 + y * 71) * 997 % 100003);
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(pixels.data()), 4, 4 * kW));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(kH);
}

void write_hdr(const std::string& path, int w, int h) {
    std::vector<float> rgb(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) rgb[(std::size_t(y) * w + x) * 3 + c] = value(x, y, c);
    stbi_write_hdr(path.c_str(), w, h, 3, rgb.data());
}

/// A stand-in for a photographed 8192 × 4096 environment: a sky gradient, a sun, and 2 % of
/// hashed noise per texel (real maps are noisy: ZIP and PIZ shrink them to about half).
void write_big(const std::string& dir) {
    constexpr int w = 8192, h = 4096;
    std::vector<float> rgb(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint32_t n = std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u;
            n = (n ^ (n >> 13)) * 0x5bd1e995u;
            const float noise = 1.f + 0.02f * (float(n >> 8 & 0xffff) / 65535.f - 0.5f);
            const float sky = 0.2f + 0.8f * float(h - y) / float(h);
            const float d2 = float((x - 2000) * (x - 2000) + (y - 1000) * (y - 1000));
            const float sun = d2 < 400.f ? 5e4f : 0.f;
            for (int c = 0; c < 3; ++c) rgb[(std::size_t(y) * w + x) * 3 + c] = (sky * (0.6f + 0.2f * float(c)) + sun) * noise;
        }
    std::vector<half> halves(rgb.begin(), rgb.end());
    for (const auto& [name, compression] : {std::pair{"zip", Imf::ZIP_COMPRESSION}, std::pair{"piz", Imf::PIZ_COMPRESSION}}) {
        Imf::Header header(w, h);
        header.compression() = compression;
        Imf::FrameBuffer fb;
        for (int c = 0; c < 3; ++c) {
            header.channels().insert(kNames[c], Imf::Channel(Imf::HALF));
            fb.insert(kNames[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.data() + c), 6, 6 * std::size_t(w)));
        }
        Imf::OutputFile file((dir + "/envmap_8k_" + name + ".exr").c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(h);
    }
    stbi_write_hdr((dir + "/envmap_8k.hdr").c_str(), w, h, 3, rgb.data());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc > 2 && std::string(argv[1]) == "--big") {  // the decode-time measurement's inputs
        write_big(argv[2]);
        return 0;
    }
    const std::string dir = argc > 1 ? argv[1] : ".";
    const std::pair<const char*, Imf::Compression> compressions[] = {
        {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION}, {"zips", Imf::ZIPS_COMPRESSION},
        {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION}};
    for (const auto& [name, compression] : compressions) {
        write_scanline(dir + "/exr_rgb_half_" + name + ".exr", compression, Imf::HALF, 3, true);
        write_scanline(dir + "/exr_rgba_float_" + name + ".exr", compression, Imf::FLOAT, 4, false);
    }
    write_scanline(dir + "/exr_rgb_half_pxr24.exr", Imf::PXR24_COMPRESSION, Imf::HALF, 3, true);
    write_tiled(dir + "/exr_tiled_zip.exr", Imf::ZIP_COMPRESSION, 16, 8, Imf::ONE_LEVEL);
    write_tiled(dir + "/exr_tiled_mipmap_piz.exr", Imf::PIZ_COMPRESSION, 8, 8, Imf::MIPMAP_LEVELS);
    write_ramp(dir + "/exr_ramp_piz.exr", Imf::PIZ_COMPRESSION);
    write_uint(dir + "/exr_y_uint_zip.exr", Imf::ZIP_COMPRESSION);
    write_hdr(dir + "/rgbe_rle.hdr", kW, kH);  // stb writes run-length scan lines from width 8 on
    write_hdr(dir + "/rgbe_flat.hdr", 5, 4);   // and flat ones below
    return 0;
}
