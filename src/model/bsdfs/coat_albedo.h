// Directional albedo E(μ) of a rough dielectric coat's specular lobe alone, for the plastic's
// layering (plastic.h): at one roughness (CoatAlbedo), or over roughness too (CoatAlbedoTable)
// for plastics whose roughness is a texture, read at each hit's α.
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
// The table over the coat index (CoatAlbedoOverIndex), for a coat whose index varies with λ at
// one roughness: rows evenly spaced over the material's own index range [η_min, η_max] (its
// extremes over 360–830 nm), at most kIndexStep apart, each the CoatAlbedo of that index bit
// for bit, linear in η between them; E_avg alike (so still the exact integral of the
// interpolant: the white furnace holds per λ). Its interpolation error midway between rows,
// at every tabulated cosine, for roughnesses 0 to 1 and indices 1.05 to 3 (tests/
// test_plastic_dispersion.cpp, CoatAlbedoOverIndex.*): ≤ 6e-4 in E (grazing cosines), 1e-5
// in E_avg, smooth or rough; a range wider than kMaxIndexRows·kIndexStep: error ∝ spacing², as
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

/// E over the coat index η in [eta_min, eta_max] at one roughness (see the file comment).
struct CoatAlbedoOverIndex {
    static constexpr float kIndexStep = 0.01f;  ///< largest spacing of the rows in η
    static constexpr int kMaxIndexRows = 129;
    float eta_min = 1.f, eta_max = 1.f;
    float rows_per_unit = 0.f;     ///< 1 / spacing (0 with one row)
    std::vector<CoatAlbedo> rows;  ///< at η = eta_min + r / rows_per_unit

    /// η held within the table's range.
    float clamp_index(float eta) const { return std::clamp(eta, eta_min, eta_max); }
    /// E(η, μ), linear in η between rows (η clamped to the range).
    float at(float eta, float mu) const {
        int r;
        const float t = row_weight(eta, r);
        return lerp(t, rows[static_cast<std::size_t>(r)].at(mu), rows[static_cast<std::size_t>(r) + 1].at(mu));
    }
    /// E_avg(η), linear between the rows: the exact integral of at(η, ·).
    float average(float eta) const {
        int r;
        const float t = row_weight(eta, r);
        return lerp(t, rows[static_cast<std::size_t>(r)].average, rows[static_cast<std::size_t>(r) + 1].average);
    }

private:
    float row_weight(float eta, int& r) const {
        const float x = (clamp_index(eta) - eta_min) * rows_per_unit;
        r = std::min(static_cast<int>(x), static_cast<int>(rows.size()) - 2);
        return x - static_cast<float>(r);
    }
};

/// The table at roughness alpha over [eta_min, eta_max] (1 ≤ eta_min ≤ eta_max ≤ 100),
/// computed on first use (rows × 262 144 evaluations of the coat's lobe; about 12 rows for a
/// flint glass) and kept for the rest of the process, shared by plastics of the same α and
/// range. Thread-safe.
const CoatAlbedoOverIndex& coat_albedo_over_index(float alpha, float eta_min, float eta_max);

/// The table of the coat of index eta, computed on first use (about 8 M evaluations of the
/// coat's lobe) and kept for the rest of the process: plastics of the same index share it,
/// and a BSDF holding a pointer to it stays trivially copyable. Thread-safe.
const CoatAlbedoTable& coat_albedo_table(float eta);

}  // namespace spt
