#include "cli/render_description.h"

#include <fstream>
#include <iterator>

#include "io/checksums.h"

namespace spt {

std::uint64_t program_build_id() {
    static const std::uint64_t id = [] {
        std::ifstream in("/proc/self/exe", std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        // Without /proc, the version string is the best the program can say about itself.
        return fnv1a64(bytes.empty() ? std::string(SPT_VERSION) : bytes);
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
