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

/// The default: Sobol has the lower error at equal samples on cornell and cornell-point (1.35x
/// to 1.62x at 16, 64 and 256 spp; validation/results/sampler_convergence.md) but not at every
/// count on cornell-sphere, and on cornell it takes 1.21x the time per path (256x256x128,
/// 1 thread, min of 5 interleaved): 1.17x the efficiency there, below 1 on cornell-sphere.
inline constexpr SamplerKind kDefaultSampler = SamplerKind::independent;

constexpr const char* sampler_name(SamplerKind kind) {
    return kind == SamplerKind::sobol ? "sobol" : "independent";
}

inline constexpr SamplerKind kSamplerKinds[] = {SamplerKind::independent, SamplerKind::sobol};

inline std::optional<SamplerKind> sampler_from_name(std::string_view name) {
    return name_lookup(kSamplerKinds, sampler_name, name);
}
inline std::vector<std::string> sampler_names() { return names_of(kSamplerKinds, sampler_name); }

}  // namespace spt
