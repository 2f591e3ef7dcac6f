// Participating media: the closed set of density fields and what every medium has in
// common. A medium at p has absorption σa(λ)·d(p) and scattering σs(λ)·d(p) per unit
// length (scene units), d the density field (dimensionless), and a Henyey–Greenstein
// phase function.
//
///  density(p)       d(p) ≥ 0
///  max_density(ray, t0, t1)  an upper bound of d over the ray's segment [t0, t1] (the
///                   majorant's factor: the tighter, the fewer null collisions)
///  clip(ray, t0, t1) narrows [t0, t1] to where d may be non-zero; false: nowhere
///  kUniform         d ≡ 1: transmittance in closed form, no null collisions
#pragma once
#include <string>
#include <variant>

#include "model/media/grid_density.h"
#include "model/media/height_fog_density.h"
#include "model/media/henyey_greenstein.h"
#include "model/media/uniform_density.h"
#include "spectral/spectrum.h"

namespace spt {

using DensityField = std::variant<UniformDensity, GridDensity, HeightFogDensity>;

struct Medium {
    std::string name;  ///< for messages
    Spectrum sigma_a, sigma_s;  ///< per unit length at density 1, before `scale`
    float scale = 1.f;          ///< multiplies both (thin fog from the same spectra)
    HenyeyGreenstein phase;
    DensityField density;

    bool is_uniform() const { return std::holds_alternative<UniformDensity>(density); }
    /// σa and σs at density 1 at the path's wavelengths.
    void coefficients(const SampledWavelengths& lambda, SampledSpectrum& sa, SampledSpectrum& ss) const {
        sa = sigma_a.sample(lambda) * scale;
        ss = sigma_s.sample(lambda) * scale;
    }
    float density_at(const Vec3& p) const {
        return std::visit([&](const auto& d) { return d.density(p); }, density);
    }
    float max_density(const Ray& ray, float t0, float t1) const {
        return std::visit([&](const auto& d) { return d.max_density(ray, t0, t1); }, density);
    }
    bool clip(const Ray& ray, float& t0, float& t1) const {
        return std::visit([&](const auto& d) { return d.clip(ray, t0, t1); }, density);
    }
};

/// The media on the two sides of a shape's surface (indices into Scene::media, −1:
/// vacuum): interior behind the geometric normal, exterior in front of it.
struct MediumInterface {
    int interior = -1, exterior = -1;
    /// The medium a ray is in after it leaves the surface in direction w.
    int after(const Vec3& n, const Vec3& w) const { return dot(w, n) < 0.f ? interior : exterior; }
};

}  // namespace spt
