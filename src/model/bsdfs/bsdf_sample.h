// What every BSDF type answers with: its flags, the transport mode, and a sampled direction.
// The contract itself is written once, in bsdf.h.
#pragma once
#include <cstdint>

#include "core/vec3.h"
#include "spectral/sampled.h"

namespace spt {

/// Which quantity a path carries: radiance (camera paths) or importance (light paths).
/// They differ where the BSDF is not symmetric: refraction scales radiance by (η_i/η_t)²
/// but not importance (Veach 1997, §5.2).
enum class TransportMode : unsigned char { radiance, importance };

/// Properties of a BSDF as a whole (BsdfFlags of a type) or of one sampled lobe
/// (BsdfSample::flags).
struct BsdfFlags {
    enum : std::uint8_t {
        reflection = 1,    ///< scatters to the side light came from
        transmission = 2,  ///< scatters through the surface
        non_delta = 4,     ///< has a lobe with a density (diffuse, glossy): light sampling,
                           ///< connections and merging can use it
        delta = 8,         ///< has a specular lobe (a Dirac in direction)
        dispersive = 16,   ///< its directions depend on the wavelength (the hero set splits)
    };
    std::uint8_t bits = 0;

    bool has(std::uint8_t f) const { return (bits & f) != 0; }
    /// No lobe at all: a surface that only absorbs (or only emits).
    bool is_black() const { return (bits & (non_delta | delta)) == 0; }
};

struct BsdfSample {
    Vec3 wi;                 ///< unit, pointing away from the surface
    SampledSpectrum weight;  ///< f·|cos θi| / (density of the sample) per wavelength
    /// Solid-angle density of wi for MIS (BSDF::pdf's value); 0 for a delta lobe.
    float pdf = 0.f;
    BsdfFlags flags;         ///< the sampled lobe: reflection or transmission, delta or not
    float eta_scale = 1.f;   ///< (η_t/η_i)² on refraction, 1 otherwise: undoes the radiance
                             ///< scaling for roulette
    bool is_delta() const { return flags.has(BsdfFlags::delta); }
};

}  // namespace spt
