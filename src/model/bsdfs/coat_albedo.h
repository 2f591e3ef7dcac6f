// Directional albedo E(μ) of a rough dielectric coat's specular lobe alone, for the plastic's
// layering (plastic.h): at one roughness (CoatAlbedo), or as rows over one parameter
// (CoatAlbedoRows): over roughness for plastics whose roughness is a texture, read at each
// hit's α (coat_albedo_table), or over the coat index for a dispersive coat (coat_albedo_over_index).
//
// E(μ) is tabulated on kPoints cosines by a fixed 64×64 stratified quadrature of the VNDF
// sampling estimator, linear in between; E_avg = 2∫E(μ)μ dμ is the exact integral of that
// interpolant, which is what makes the plastic's diffuse term integrate exactly.
//
// The table over roughness has rows at α = i/32 (each the CoatAlbedo of that α, bit for bit),
// linear in α between them; E_avg alike, so it stays the exact integral of the interpolant
// and the plastic energy-conserving. The α interpolation's error (midway between rows, every
// tabulated cosine, indices 1.2, 1.5, 2.5: tests/test_microfacet.cpp, CoatAlbedoTable.*): in
// E for cos θ ≥ 0.1, 3.2e-3 for α ≥ 1/32 and 1.3e-2 below (E moves fastest with α there); at
// grazing cosines up to 7e-2 near α = 0 (the smooth coat's Fresnel is 1 there); in E_avg 7e-4.
// It adds to the white furnace's error. (Rows at α = (i/32)² would be ~10× closer below 1/32.)
//
// The table over the coat index, for a coat whose index varies with λ at
// one roughness: rows evenly spaced over the material's own index range [η_min, η_max] (its
// extremes over 360–830 nm), at most kCoatIndexStep apart, each the CoatAlbedo of that index bit
// for bit, linear in η between them; E_avg alike (so still the exact integral of the
// interpolant: the white furnace holds per λ). Its interpolation error midway between rows,
// at every tabulated cosine, for roughnesses 0 to 1 and indices 1.05 to 3 (tests/
// test_plastic_dispersion.cpp, CoatAlbedoOverIndex.*): ≤ 6e-4 in E (grazing cosines), 1e-5
// in E_avg, smooth or rough; a range wider than kCoatMaxIndexRows·kCoatIndexStep: error ∝ spacing², as
// the rows spread (a real glass spans < 0.2).
#pragma once
#include <algorithm>
#include <array>
#include <vector>

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

/// Rows of E over one parameter x (the roughness α, or the coat index η), evenly spaced:
/// row r at x = first + r / rows_per_unit, at least two rows; linear in x between them, x held
/// within [first, last]. Each row is the CoatAlbedo of its x bit for bit, so at a row's x
/// exactly that row's values.
struct CoatAlbedoRows {
    float first = 0.f, last = 0.f;
    float rows_per_unit = 0.f;     ///< 1 / spacing (0 when first = last: two equal rows)
    std::vector<CoatAlbedo> rows;

    /// x held within the rows' range.
    float clamp_parameter(float x) const { return std::clamp(x, first, last); }
    /// E(x, μ), bilinear.
    float at(float x, float mu) const {
        int r;
        const float t = row_weight(x, r);
        return lerp(t, rows[static_cast<std::size_t>(r)].at(mu), rows[static_cast<std::size_t>(r) + 1].at(mu));
    }
    /// E_avg(x), linear between the rows: the exact integral of at(x, ·).
    float average(float x) const {
        int r;
        const float t = row_weight(x, r);
        return lerp(t, rows[static_cast<std::size_t>(r)].average, rows[static_cast<std::size_t>(r) + 1].average);
    }

private:
    float row_weight(float x, int& r) const {
        const float u = (clamp_parameter(x) - first) * rows_per_unit;
        r = std::min(static_cast<int>(u), static_cast<int>(rows.size()) - 2);
        return u - static_cast<float>(r);
    }
};

/// Rows over roughness: α = i/32, i = 0..32.
inline constexpr int kCoatRoughnessRows = 33;
/// Rows over the coat index: at most this far apart in η, and at most this many.
inline constexpr float kCoatIndexStep = 0.01f;
inline constexpr int kCoatMaxIndexRows = 129;

/// The table at roughness alpha over [eta_min, eta_max] (1 ≤ eta_min ≤ eta_max ≤ 100),
/// computed on first use (rows × 262 144 evaluations of the coat's lobe; about 12 rows for a
/// flint glass) and kept for the rest of the process, shared by plastics of the same α and
/// range. Thread-safe.
const CoatAlbedoRows& coat_albedo_over_index(float alpha, float eta_min, float eta_max);

/// The table of the coat of index eta, computed on first use (about 8 M evaluations of the
/// coat's lobe) and kept for the rest of the process: plastics of the same index share it,
/// and a BSDF holding a pointer to it stays trivially copyable. Thread-safe.
const CoatAlbedoRows& coat_albedo_table(float eta);

}  // namespace spt
