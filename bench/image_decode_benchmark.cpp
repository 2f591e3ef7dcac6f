// Image decode time (not part of the tests): reads each file named on the command line,
// decodes it with decode_image (the reader textures and environment maps use) and prints
// its size, the decode time (best of --repeat runs, file already in memory) and the
// process's peak resident memory so far.
//   image_decode_benchmark [--repeat N] FILE...
// The large inputs come from tests/textures/make_hdr_test_images.cpp --big DIR.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "io/image_decoders.h"

int main(int argc, char** argv) {
    int repeat = 1, first = 1;
    if (argc > 2 && std::string(argv[1]) == "--repeat") repeat = std::max(1, std::atoi(argv[2])), first = 3;
    for (int a = first; a < argc; ++a) {
        std::ifstream in(argv[a], std::ios::binary);
        if (!in) {
            std::fprintf(stderr, "%s: cannot open\n", argv[a]);
            return 1;
        }
        const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        double best = 1e30;
        int w = 0, h = 0, c = 0;
        for (int r = 0; r < repeat; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            try {
                const spt::DecodedImage img = spt::decode_image(bytes);
                w = img.width, h = img.height, c = img.channels;
            } catch (const spt::ImageDecodeError& e) {
                std::fprintf(stderr, "%s: %s\n", argv[a], e.what());
                return 1;
            }
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        std::printf("%s: %dx%d, %d channels, %.1f MB file: decoded in %.2f s; peak RSS %.0f MB\n", argv[a], w, h, c,
                    double(bytes.size()) / 1e6, best, double(usage.ru_maxrss) / 1024.0);
    }
    return 0;
}
