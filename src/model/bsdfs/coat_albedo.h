// Directional albedo E(μ) of a rough dielectric coat's specular lobe alone, for the plastic's
// layering (plastic.h): at one roughness (CoatAlbedo), or over roughness too (CoatAlbedoTable)
// for plastics whose roughness is a texture, read at each hit's α.
//
// E(μ) is tabulated on kPoints cosines by a fixed 64×64 stratified quadrature of the VNDF
// sampling estimator, linear in between; E_avg = 2∫E(μ)μ dμ is the exact integral of that
// interpolant, which is what makes the plastic's diffuse term integrate exactly.
//
// The table over roughness has rows at α = i/32 (each row the CoatAlbedo of that α, bit for
// bit), linear in α between them; E_avg is linear in α too, so it stays the exact integral of
// the interpolant and the plastic stays energy-conserving. What the α interpolation costs is
// its distance to the row of the true α: at most 1.5e-3 in E (measured at every midpoint
// between rows, every tabulated cosine and indices 1.2, 1.5 and 2.5 by
// tests/test_microfacet.cpp, CoatAlbedoTable.*), which is the white furnace's error on top
// of the one-roughness table's.
#pragma once
#include <algorithm>
#include <array>

#include "core/math.h"

namespace spt {

struct CoatAlbedo {
    static constexpr int kPoints = 64;
    std::array<float, kPoints> e{};  ///< E(μ) at μ = j/(kPoints − 1)
    float average = 0.f;             ///< E_avg of the interpolant

    /// E(μ), linear between the tabulated cosines.
    float at(float mu) const {
        const float x = std::clamp(mu, 0.f, 1.f) * (kPoints - 1);
        const int j = std::min(static_cast<int>(x), kPoints - 2);
        return lerp(x - static_cast<float>(j), e[static_cast<std::size_t>(j)], e[static_cast<std::size_t>(j) + 1]);
    }
};

/// E of the coat of index eta ≥ 1 at GGX roughness alpha in [0, 1] (α below the smooth
/// threshold: the Fresnel reflectance of the mirror coat).
CoatAlbedo make_coat_albedo(float alpha, float eta);

struct CoatAlbedoTable {
    static constexpr int kRoughnessPoints = 33;
    std::array<CoatAlbedo, kRoughnessPoints> rows;  ///< at α = i/(kRoughnessPoints − 1)

    /// E(α, μ), bilinear (at a row's α exactly that row's value).
    float at(float alpha, float mu) const {
        int i;
        const float t = row_weight(alpha, i);
        return lerp(t, rows[static_cast<std::size_t>(i)].at(mu), rows[static_cast<std::size_t>(i) + 1].at(mu));
    }
    /// E_avg(α), linear between the rows: the exact integral of at(α, ·).
    float average(float alpha) const {
        int i;
        const float t = row_weight(alpha, i);
        return lerp(t, rows[static_cast<std::size_t>(i)].average, rows[static_cast<std::size_t>(i) + 1].average);
    }

private:
    static float row_weight(float alpha, int& i) {
        const float x = std::clamp(alpha, 0.f, 1.f) * (kRoughnessPoints - 1);
        i = std::min(static_cast<int>(x), kRoughnessPoints - 2);
        return x - static_cast<float>(i);
    }
};

/// The table of the coat of index eta, computed on first use (about 8 M evaluations of the
/// coat's lobe) and kept for the rest of the process: plastics of the same index share it,
/// and a BSDF holding a pointer to it stays trivially copyable. Thread-safe.
const CoatAlbedoTable& coat_albedo_table(float eta);

}  // namespace spt
