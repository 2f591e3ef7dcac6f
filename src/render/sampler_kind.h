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
/// bdpt and vcm take only their camera sample from Sobol, unmeasured): for the path
/// integrator it gives a lower error at a small cost per path, a higher efficiency
/// (validation/results/sampler_convergence.md).
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
