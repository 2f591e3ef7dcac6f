// The start of a path sample (random numbers, wavelengths, film position, lens point, time),
// shared by the tile renderer and the wavefront renderer so both draw identical numbers.
#pragma once
#include <cstdint>

#include "core/rng.h"
#include "core/sample_dimensions.h"
#include "core/sobol_sampler.h"
#include "model/camera.h"
#include "render/renderer.h"
#include "spectral/sampled.h"

namespace spt {

/// The start of every path sample, shared by both integrators so they draw identical numbers:
/// Rng(seed, pixel, sample), then the wavelengths, then the jitter inside the pixel, then
/// (thin lens only) the lens point, then (motion blur only) the shutter time: scenes without
/// an effect draw nothing for it. Sampler: Rng, or SobolSampler, which takes each of these
/// from its dimension (core/sample_dimensions.h; the seeks are no-ops for Rng).
/// The camera ray is left to the caller (ray() as the integrator's argument): built in place
/// there, it is not copied through memory in pieces, which stalls the first intersection.
template <class Sampler>
struct PixelSample {
    Sampler rng;
    SampledWavelengths lambda;
    float px, py;                      ///< film position of the sample
    float lens_u = 0.f, lens_v = 0.f;  ///< thin lens: the lens point's uniform numbers
    float time = 0.f;                  ///< shutter time of the whole sample
    Ray ray(const Camera& camera) const {
        return camera.thin_lens() ? camera.generate_ray(px, py, lens_u, lens_v) : camera.generate_ray(px, py);
    }
};

/// The lens point and the shutter time of a sample, for the scenes that have either. Out of
/// line: inlined, the lens sampling grows the render loop past what GCC inlines whole, which
/// slows the pinhole path.
template <class Sampler>
[[gnu::noinline]] PixelSample<Sampler> start_lens_and_time(Sampler rng, const SampledWavelengths& lambda, float px,
                                                           float py, const Camera& camera) {
    PixelSample<Sampler> ps{rng, lambda, px, py};
    ps.time = camera.shutter_open();
    if (camera.thin_lens()) {
        seek_dimension(ps.rng, dims::kLensU);
        ps.lens_u = ps.rng.uniform();
        ps.lens_v = ps.rng.uniform();
    }
    if (camera.motion_blur()) {
        seek_dimension(ps.rng, dims::kTime);
        ps.time = camera.shutter_time(ps.rng.uniform());
    }
    return ps;
}

inline RngStream pixel_stream(const RenderSettings& settings, int x, int y) {
    return RngStream(settings.seed, std::uint64_t(y) * settings.width + x);
}

/// Always inlined: as a call (GCC's choice once the path loop grew) the sample came back
/// through memory, a stall at the start of every path.
template <class Sampler>
[[gnu::always_inline]] inline PixelSample<Sampler> start_pixel_sample(const RngStream& stream, int x, int y, int s,
                                               const RenderSettings& settings, const Camera& camera) {
    Sampler rng(stream, static_cast<std::uint64_t>(s));
    seek_dimension(rng, dims::kWavelength);
    const float u = rng.uniform();
    SampledWavelengths lambda = settings.wide_wavelengths ? settings.wide_wavelengths->sample(u)
                                                          : SampledWavelengths::sample(u);
    if (settings.integrator.wavelengths_per_path == 1) lambda.terminate_secondary();
    seek_dimension(rng, dims::kPixelX);
    const float px = static_cast<float>(x) + rng.uniform();
    const float py = static_cast<float>(y) + rng.uniform();
    if (!camera.thin_lens() && !camera.motion_blur()) return {rng, lambda, px, py, 0.f, 0.f, camera.shutter_open()};
    return start_lens_and_time(rng, lambda, px, py, camera);
}

}  // namespace spt
