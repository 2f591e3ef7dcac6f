// Which sampler draws a path sample's random numbers: the names the command line chooses from.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "render/integrator_kind.h"

namespace spt {

/// independent: PCG32 numbers, drawn in sequence (core/rng.h). sobol: Owen-scrambled Sobol
/// points per pixel, each quantity at its dimension (core/sobol_sampler.h,
/// core/sample_dimensions.h); path integrator throughout; bdpt and vcm take their camera
/// sample (pixel position, wavelength, lens, time) from it and the rest from its PCG stream.
enum class SamplerKind { independent, sobol };

/// The command line's default: Sobol for the path integrator on the tiles schedule, the
/// independent sampler elsewhere (the wavefront schedule runs only the independent sampler;
/// bdpt and vcm take only their camera sample from Sobol, unmeasured). With the plane
/// light's sampler on (the default since), Sobol's overhead per path is a small share: on
/// cornell (128², 64 spp, seeds 1–4, reference 4096 spp) relMSE 0.0077 against 0.0123
/// (1.61× lower) at 1.13× the time (256², 64 spp, 1 thread, min of 5 interleaved; shared
/// machine): 1.42× the efficiency. cornell-point: 1.38–1.62× lower relMSE
/// (validation/results/sampler_convergence.md). cornell-sphere with the caustic sampler:
/// equal within the noise.
constexpr SamplerKind default_sampler(IntegratorKind integrator, bool wavefront) {
    return integrator == IntegratorKind::path && !wavefront ? SamplerKind::sobol : SamplerKind::independent;
}

constexpr const char* sampler_name(SamplerKind kind) {
    return kind == SamplerKind::sobol ? "sobol" : "independent";
}

inline constexpr SamplerKind kSamplerKinds[] = {SamplerKind::independent, SamplerKind::sobol};

inline std::optional<SamplerKind> sampler_from_name(std::string_view name) {
    return name_lookup(kSamplerKinds, sampler_name, name);
}
inline std::vector<std::string> sampler_names() { return names_of(kSamplerKinds, sampler_name); }

}  // namespace spt
