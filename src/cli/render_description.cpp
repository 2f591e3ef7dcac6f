#include "cli/render_description.h"

#include <cstring>
#include <fstream>
#include <vector>

#include "io/checksums.h"

namespace spt {

namespace {

/// FNV-1a over the 64-bit words of `block` (then its last bytes one by one), continuing `h`.
std::uint64_t fnv1a64_words(const char* block, std::size_t n, std::uint64_t h) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t word;
        std::memcpy(&word, block + i, 8);
        h = (h ^ word) * 0x100000001b3ull;
    }
    for (; i < n; ++i) h = (h ^ static_cast<unsigned char>(block[i])) * 0x100000001b3ull;
    return h;
}

}  // namespace

std::uint64_t program_build_id() {
    static const std::uint64_t id = [] {
        // The executable is read at every render (tens of megabytes in a debug or sanitizer
        // build): in blocks, a word at a time, not byte by byte through a stream iterator,
        // which took 0.2 s of a 58 MB debug build's start.
        std::ifstream in("/proc/self/exe", std::ios::binary);
        std::vector<char> block(std::size_t(1) << 20);  // a multiple of 8: only the last block has a tail
        std::uint64_t h = 0xcbf29ce484222325ull;
        std::size_t total = 0;
        while (in) {
            in.read(block.data(), static_cast<std::streamsize>(block.size()));
            const std::size_t n = static_cast<std::size_t>(in.gcount());
            h = fnv1a64_words(block.data(), n, h);
            total += n;
        }
        // Without /proc, the version string is the best the program can say about itself.
        return total > 0 ? h : fnv1a64(SPT_VERSION);
    }();
    return id;
}

RenderDescription describe_render(const Options& o, const RenderSettings& rs, const InputFiles& scene_files,
                                  const Observer* sensor) {
    RenderDescription r;
    r.scene = o.scene;
    r.width = rs.width;
    r.height = rs.height;
    r.spp = rs.spp;
    r.spectral_bins = o.spectral.bins;
    r.max_depth = rs.integrator.max_depth;
    r.seed = rs.seed;
    r.integrator = rs.integrator.kind;
    r.light_sampling = rs.integrator.light_sampling;
    r.sampler = rs.sampler;
    r.wavelengths_per_path = o.wavelengths_per_path;
    r.caustic_nee = rs.integrator.caustic_nee;
    r.plane_nee = rs.integrator.sample_planes;
    r.light_selection = rs.integrator.light_selection;
    r.guiding = rs.guiding;
    r.dispersion = o.dispersion;
    r.merge_radius = rs.integrator.kind == IntegratorKind::vcm ? rs.integrator.merge_radius : 0.f;
    r.program = program_build_id();
    r.inputs = scene_files;
    if (sensor) r.inputs.emplace_back(o.sensor, sensor->fingerprint());
    return r;
}

RenderSettings settings_of(const RenderDescription& r) {
    RenderSettings rs;
    rs.width = r.width;
    rs.height = r.height;
    rs.spp = r.spp;
    rs.seed = r.seed;
    rs.sampler = r.sampler;
    rs.integrator.kind = r.integrator;
    rs.integrator.max_depth = r.max_depth;
    rs.integrator.light_sampling = r.light_sampling;
    rs.integrator.wavelengths_per_path = r.wavelengths_per_path;
    rs.integrator.caustic_nee = r.caustic_nee;
    rs.integrator.sample_planes = r.plane_nee;
    rs.integrator.light_selection = r.light_selection;
    rs.guiding = r.guiding;
    rs.integrator.merge_radius = r.merge_radius;
    return rs;
}

}  // namespace spt
