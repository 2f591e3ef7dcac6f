// libFuzzer entry points for the scene readers (built with -DSPT_FUZZ=ON and clang, under
// AddressSanitizer and UndefinedBehaviorSanitizer; see tests/fuzz/README.md).
//   fuzz_scene: bytes → JSON reader → scene loader (a mesh named "a.ply" resolves to a small
//               valid PLY, any other file name fails to open).
//   fuzz_ply:   bytes → PLY reader.
//   fuzz_png:   bytes → image readers: PNG (with our inflate), OpenEXR, Radiance HDR, PFM, PPM.
// The only exception allowed to escape is LocatedError (the clean "file:line:column" error;
// for fuzz_png ImageDecodeError, the reader's own); anything else, and any crash, leak or
// undefined behaviour, is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/checksums.h"
#include "io/image_decoders.h"
#include "io/located_error.h"
#include "io/ply_reader.h"
#include "scene/scene_loader.h"

#if !defined(SPT_FUZZ_PLY) && !defined(SPT_FUZZ_PNG)
namespace {

const char* kPly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

}  // namespace
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
#if defined(SPT_FUZZ_PLY)
        spt::parse_ply(bytes, "fuzz.ply");
#elif defined(SPT_FUZZ_PNG)
        // Other formats (OpenEXR, Radiance HDR, PFM, PPM) go to decode_image as they are.
        if (!bytes.starts_with("\x89PNG")) {
            spt::decode_image(bytes);
            return 0;
        }
        // Mutations would nearly all break a chunk CRC and stop there: give every chunk its
        // right CRC, so the chunks' contents (header, palette, compressed data) get fuzzed.
        std::string png(bytes);
        for (std::size_t at = 8; at + 12 <= png.size();) {
            std::uint32_t length = 0;
            for (int i = 0; i < 4; ++i) length = length << 8 | static_cast<unsigned char>(png[at + static_cast<std::size_t>(i)]);
            if (length > png.size() - at - 12) break;
            const std::uint32_t crc = spt::crc32(std::string_view(png).substr(at + 4, 4 + length));
            for (int i = 0; i < 4; ++i) png[at + 8 + length + static_cast<std::size_t>(i)] = static_cast<char>(crc >> (24 - 8 * i));
            at += 12 + length;
        }
        spt::decode_png(png);
#else
        const spt::RelativeFileReader reader = [](const std::string& rel, std::string& contents,
                                                  std::string& display, std::string& why) {
            display = rel;
            if (rel != "a.ply") {
                why = "no such file";
                return false;
            }
            contents = kPly;
            return true;
        };
        // Few bins keep each run fast; the checks do not depend on the resolution.
        spt::load_scene_text(bytes, "fuzz.json", "fuzz", spt::SpectralResolution{4}, reader);
#endif
    } catch (const spt::LocatedError&) {
    } catch (const spt::ImageDecodeError&) {
    }
    return 0;
}
