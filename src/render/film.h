// The film: per-pixel sums of CIE XYZ in double precision, in the order samples arrive (each
// pixel belongs to one tile, each tile to one worker at a time, so no locks are needed).
// At fixed sample counts (chunk ends, see renderer.h) the renderer folds these sums into exact
// fixed-point totals, whose addition is associative: films of disjoint chunks merge into the
// very bits of one film that rendered them all.
// Samples that are not finite or negative are counted and dropped, never silently fixed.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/image.h"
#include "render/exact_sum.h"
#include "spectral/cie.h"
#include "spectral/color_space.h"
#include "spectral/spectral_bands.h"

namespace spt {

class Film {
public:
    /// A film integrating against `observer` (XYZ for CIE 1931, raw RGB for a camera sensor);
    /// the observer must outlive the film.
    Film(int width, int height, const Observer& observer = Cie1931::get());

    /// Adds one path's radiance at the path's wavelengths to pixel (x, y).
    [[gnu::always_inline]] void add_sample(int x, int y, const SampledSpectrum& L, const SampledWavelengths& lambda) {
        const std::size_t i = index(x, y);
        ++m_count[i];
        // One test of all four lanes: v − v is 0 for finite v and NaN for ±inf and NaN.
        const Float4 v = L.lanes();
        const Int4 nonfinite = (v - v) != 0.f, negative = v < 0.f;
        if (lane_bits(nonfinite | negative) != 0) [[unlikely]] {
            const bool bad = lane_bits(nonfinite) != 0;
            (bad ? m_rejected_nonfinite : m_rejected_negative).fetch_add(1, std::memory_order_relaxed);
            return;
        }
        // Paths that found no light add exactly zero: skip the conversion (the sums, all ≥ +0,
        // are the same bits either way).
        if (L.is_zero()) return;
        const Xyz c = m_observer->to_xyz(L, lambda);
        m_xyz[3 * i] += c.x, m_xyz[3 * i + 1] += c.y, m_xyz[3 * i + 2] += c.z;
        m_y_squared[i] += c.y * c.y;
        if (!m_band_sums.empty()) [[unlikely]] add_to_bands(i, L, lambda);
    }

    // ---- Spectral bands (spectral EXR output): empty unless enable_bands was called ----
    // Per pixel and band b of width Δ, the mean over samples of
    // Σ_k L(λk)·[λk ∈ b]/(pdf(λk)·K·Δ): an unbiased estimate of the band's mean spectral
    // radiance (1/Δ)∫_b L dλ, with the same pdf division as the observer's to_xyz (terminated
    // companions, pdf 0, add nothing). A film without bands pays one untaken branch.

    /// Starts accumulating `bands` (count > 0) from now on; call before any sample.
    void enable_bands(const SpectralBands& bands);
    const SpectralBands& bands() const { return m_bands; }
    bool has_bands() const { return !m_band_sums.empty(); }
    /// Mean band radiance of every pixel: bands().count floats per pixel, row-major.
    std::vector<float> develop_bands() const;

    // ---- Splats: light-path contributions that land on arbitrary pixels (bdpt, t = 1) ----
    // Estimator: pixel = Σ camera samples / count + Σ splats / M, with M = light paths traced
    // over the whole film / pixels (one light path per camera sample, so M = spp after whole
    // passes). The renderer adds splats in a fixed order (tile by tile), so the sums do not
    // depend on the thread count. Not thread-safe: one caller at a time.

    /// Adds one splatted XYZ contribution to pixel (x, y).
    void add_splat(int x, int y, const Xyz& c) {
        if (m_splat_xyz.empty()) allocate_splats();
        const std::size_t i = index(x, y);
        m_splat_xyz[3 * i] += c.x, m_splat_xyz[3 * i + 1] += c.y, m_splat_xyz[3 * i + 2] += c.z;
        m_splat_y_squared[i] += c.y * c.y;
    }
    /// Records that `n` more light paths were traced (whether or not they splatted).
    void add_light_paths(std::uint64_t n) {
        if (m_splat_xyz.empty()) allocate_splats();
        m_light_paths += n;
    }
    bool has_splats() const { return !m_splat_xyz.empty(); }
    /// Counts a splat that was not finite or negative (dropped, like rejected samples).
    void reject_splat(bool nonfinite) {
        (nonfinite ? m_rejected_nonfinite : m_rejected_negative).fetch_add(1, std::memory_order_relaxed);
    }

    int width() const { return m_width; }
    int height() const { return m_height; }
    std::uint32_t sample_count(int x, int y) const { return m_count[index(x, y)]; }
    /// Fewest and most samples of any pixel (they differ in a render stopped inside a pass).
    std::pair<std::uint32_t, std::uint32_t> sample_count_range() const;
    /// Mean XYZ of a pixel (zero when it has no samples).
    Xyz pixel_xyz(int x, int y) const;
    /// Standard error of the pixel's mean Y (from the per-sample second moment).
    double pixel_y_standard_error(int x, int y) const;

    std::uint64_t rejected_nonfinite() const { return m_rejected_nonfinite.load(); }
    std::uint64_t rejected_negative() const { return m_rejected_negative.load(); }
    std::uint64_t rejected_samples() const { return rejected_nonfinite() + rejected_negative(); }

    /// Mean XYZ of every pixel converted to linear RGB of the given colour space.
    Image develop(const ColorSpace& space) const;
    /// The observer's three values as they are (raw camera RGB for a sensor).
    Image develop_raw() const;
    const Observer& observer() const { return *m_observer; }

    /// Raw state, for bit-exact comparisons: per pixel X, Y, Z sums (folded totals plus the
    /// chunk in progress).
    std::vector<double> xyz_sums() const;

    // ---- Folding and merging (exact: see exact_sum.h) ----
    /// Moves pixel (x, y)'s sample sums into its exact totals (a chunk of its samples ended).
    void fold_pixel(int x, int y);
    /// Moves every pixel's splat sums into their exact totals (a chunk of passes ended).
    void fold_splats();
    /// True when every sum is folded (nothing in the chunk sums): such films can be merged.
    bool is_folded() const;
    /// Adds the samples of `part`, a folded film of the same size rendering disjoint
    /// samples of the same render. Exact, so the order of the parts does not matter.
    void merge(const Film& part);

    /// The whole accumulation state as bytes (checkpoints) and back. restore_state throws
    /// std::runtime_error when the bytes do not describe a film of this size.
    std::string save_state() const;
    void restore_state(std::string_view bytes);

private:
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(m_width) + static_cast<std::size_t>(x);
    }
    void allocate_splats() {
        m_splat_xyz.assign(m_xyz.size(), 0.0);
        m_splat_y_squared.assign(m_y_squared.size(), 0.0);
        m_exact_splats.assign(4 * m_y_squared.size(), ExactSum{});
    }
    /// Pixel i's sums: exact totals plus the chunk in progress (x, y, z, y²).
    std::array<double, 4> pixel_sums(std::size_t i) const;
    std::array<double, 4> pixel_splat_sums(std::size_t i) const;
    /// Light paths per pixel (M of the splat estimator); 0 when none were traced.
    double light_paths_per_pixel() const {
        return static_cast<double>(m_light_paths) / (static_cast<double>(m_width) * m_height);
    }
    int m_width, m_height;
    void add_to_bands(std::size_t i, const SampledSpectrum& L, const SampledWavelengths& lambda);
    /// A pointer, not Cie1931::get() per call: that is an out-of-line call with a guard check,
    /// which add_sample would otherwise make for every path.
    const Observer* m_observer;
    SpectralBands m_bands;
    std::vector<double> m_band_sums;  ///< bands.count per pixel; empty: no spectral output
    std::vector<double> m_xyz;
    std::vector<double> m_splat_xyz, m_splat_y_squared;  ///< empty unless splats were added
    std::uint64_t m_light_paths = 0;
    std::vector<double> m_y_squared;
    /// Folded totals: x, y, z, y² per pixel; with splats, the same for them.
    std::vector<ExactSum> m_exact, m_exact_splats;
    std::vector<std::uint32_t> m_count;
    std::atomic<std::uint64_t> m_rejected_nonfinite{0}, m_rejected_negative{0};
};

}  // namespace spt
